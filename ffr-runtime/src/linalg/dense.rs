//! Dense LU with partial pivoting in preallocated storage (LAPACK `dgetf2` /
//! `dgetrs` without blocking), for the `k × k` Schur complement of the border.

use super::{Failure, Part, PivotInfo, Singular};

/// A dense `n × n` matrix `A`, column-major (`a_ij` at `a[i + j·n]`), and its
/// LU factorization with partial pivoting `A = Π L U` computed in place
/// (`L` unit lower triangular below the diagonal, `U` on and above it).
///
/// Only [`new`](Self::new) allocates.
#[derive(Debug, Clone)]
pub struct DenseLu {
    n: usize,
    a: Vec<f64>,
    ipiv: Vec<usize>,
    factored: bool,
    info: PivotInfo,
}

impl DenseLu {
    /// A zero `n × n` matrix (allocates `n²` values and `n` pivot indices).
    pub fn new(n: usize) -> Self {
        DenseLu {
            n,
            a: vec![0.0; n * n],
            ipiv: vec![0; n],
            factored: false,
            info: PivotInfo::default(),
        }
    }

    /// Order `n`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// `A ← 0` and forget the factorization. No allocation.
    pub fn clear(&mut self) {
        self.a.fill(0.0);
        self.factored = false;
        self.info = PivotInfo::default();
    }

    /// `a_ij` (after [`factor`](Self::factor): the entry of the factors).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.a[i + j * self.n]
    }

    /// `a_ij ← a_ij + v` (debug-asserts that the matrix is not factored).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(!self.factored, "add to a factored DenseLu");
        self.a[i + j * self.n] += v;
    }

    /// `a_ij ← v` (debug-asserts that the matrix is not factored).
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(!self.factored, "set in a factored DenseLu");
        self.a[i + j * self.n] = v;
    }

    /// The entries, column-major: `a_ij` at `[i + j·n]`.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        debug_assert!(!self.factored, "write to a factored DenseLu");
        &mut self.a
    }

    /// The entries (or factors), column-major.
    pub fn as_slice(&self) -> &[f64] {
        &self.a
    }

    /// `y ← y + A x` with the unfactored matrix (panics if factored).
    pub fn mul_vec_add(&self, x: &[f64], y: &mut [f64]) {
        assert!(!self.factored, "mul_vec_add on a factored DenseLu");
        assert_eq!(x.len(), self.n);
        assert_eq!(y.len(), self.n);
        if self.n == 0 {
            return;
        }
        for (col, &xj) in self.a.chunks_exact(self.n).zip(x) {
            for (yi, a) in y.iter_mut().zip(col) {
                *yi += a * xj;
            }
        }
    }

    /// Whether [`factor`](Self::factor) succeeded since the last
    /// [`clear`](Self::clear).
    pub fn is_factored(&self) -> bool {
        self.factored
    }

    /// Pivot statistics of the last successful factorization.
    pub fn pivot_info(&self) -> PivotInfo {
        self.info
    }

    /// The sign of `det A` (`±1`) from the last successful factorization:
    /// the signs of `U`'s diagonal times `(−1)` per row interchange.
    /// Panics unless factored. `O(n)`, no allocation.
    pub fn det_sign(&self) -> f64 {
        assert!(self.factored, "det_sign of an unfactored DenseLu");
        let n = self.n;
        let mut sign = 1.0;
        for j in 0..n {
            if self.a[j + j * n] < 0.0 {
                sign = -sign;
            }
            if self.ipiv[j] != j {
                sign = -sign;
            }
        }
        sign
    }

    /// `A = Π L U` in place with partial pivoting: at step `j` the row
    /// `p = argmax_{i ≥ j} |a_ij|` is swapped with row `j` (whole rows),
    /// `l_ij = a_ij / a_jj` and `a_ic ← a_ic − l_ij a_jc` for `i, c > j`.
    /// Cost `⅔ n³`, no allocation.
    ///
    /// Fails on an exactly zero pivot or a non-finite entry (of `A` or of
    /// the factors); then the matrix is unusable until the next
    /// [`clear`](Self::clear). `part` of the error is [`Part::Matrix`].
    pub fn factor(&mut self) -> Result<(), Singular> {
        assert!(!self.factored, "DenseLu factored twice without clear");
        let n = self.n;
        let fail = |column, failure| Singular {
            part: Part::Matrix,
            column,
            failure,
        };
        let mut max_entry = 0.0f64;
        for j in 0..n {
            for &a in &self.a[j * n..(j + 1) * n] {
                if !a.is_finite() {
                    return Err(fail(j, Failure::NonFinite));
                }
                max_entry = max_entry.max(a.abs());
            }
        }
        let mut min_pivot = f64::INFINITY;
        let mut max_pivot = 0.0f64;
        for j in 0..n {
            let mut p = j;
            let mut amax = self.a[j + j * n].abs();
            for i in j + 1..n {
                let a = self.a[i + j * n].abs();
                if a > amax {
                    amax = a;
                    p = i;
                }
            }
            self.ipiv[j] = p;
            if amax == 0.0 {
                return Err(fail(j, Failure::ZeroPivot));
            }
            if !amax.is_finite() {
                return Err(fail(j, Failure::NonFinite));
            }
            min_pivot = min_pivot.min(amax);
            max_pivot = max_pivot.max(amax);
            if p != j {
                for c in 0..n {
                    self.a.swap(j + c * n, p + c * n);
                }
            }
            let r = 1.0 / self.a[j + j * n];
            for l in &mut self.a[j * n + j + 1..(j + 1) * n] {
                *l *= r;
            }
            let (left, right) = self.a.split_at_mut((j + 1) * n);
            let mult = &left[j * n + j + 1..];
            for col in right.chunks_exact_mut(n) {
                let t = col[j];
                if t != 0.0 {
                    for (a, l) in col[j + 1..].iter_mut().zip(mult) {
                        *a -= l * t;
                    }
                }
            }
        }
        let mut max_u = 0.0f64;
        for j in 0..n {
            let col = &self.a[j * n..(j + 1) * n];
            if col.iter().any(|a| !a.is_finite()) {
                return Err(fail(j, Failure::NonFinite));
            }
            for &u in &col[..=j] {
                max_u = max_u.max(u.abs());
            }
        }
        self.info = PivotInfo {
            min_pivot: if n == 0 { 0.0 } else { min_pivot },
            max_pivot,
            max_entry,
            max_u,
        };
        self.factored = true;
        Ok(())
    }

    /// `b ← A⁻¹ b = U⁻¹ L⁻¹ Πᵀ b` with the factors. Panics unless factored.
    /// Cost `2 n²`, no allocation.
    pub fn solve(&self, b: &mut [f64]) {
        assert!(self.factored, "solve with an unfactored DenseLu");
        let n = self.n;
        assert_eq!(b.len(), n);
        for j in 0..n {
            let p = self.ipiv[j];
            if p != j {
                b.swap(p, j);
            }
        }
        for j in 0..n {
            let bj = b[j];
            if bj != 0.0 {
                for (bi, l) in b[j + 1..]
                    .iter_mut()
                    .zip(&self.a[j * n + j + 1..(j + 1) * n])
                {
                    *bi -= l * bj;
                }
            }
        }
        for j in (0..n).rev() {
            if b[j] != 0.0 {
                let bj = b[j] / self.a[j + j * n];
                b[j] = bj;
                for (bi, u) in b[..j].iter_mut().zip(&self.a[j * n..j * n + j]) {
                    *bi -= u * bj;
                }
            }
        }
    }

    /// `B ← A⁻¹ B` for `nrhs` right-hand sides stored column-major in `b`
    /// (`b.len() == n · nrhs`).
    pub fn solve_many(&self, b: &mut [f64], nrhs: usize) {
        assert_eq!(b.len(), self.n * nrhs);
        if self.n == 0 {
            assert!(self.factored, "solve with an unfactored DenseLu");
            return;
        }
        for col in b.chunks_exact_mut(self.n) {
            self.solve(col);
        }
    }
}
