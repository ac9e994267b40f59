//! Banded LU with partial pivoting (the algorithms of LAPACK `dgbtf2` and
//! `dgbtrs`, unblocked, 0-based).

use super::{Failure, Part, PivotInfo, Singular};

/// A square `n × n` band matrix `A` with `kl` sub- and `ku` superdiagonals
/// (`a_ij = 0` unless `−kl ≤ j − i ≤ ku`), and its LU factorization with
/// partial pivoting `A = Π L U` computed in place.
///
/// Storage is LAPACK's band layout with `kl` extra rows for the fill-in of
/// row interchanges: column-major with leading dimension
/// `ldab = 2 kl + ku + 1`, `a_ij` at `ab[j·ldab + kl + ku + i − j]`. After
/// [`factor`](Self::factor), rows `0..=kl+ku` of each column hold `U` (upper
/// triangular with `kl + ku` superdiagonals), rows `kl+ku+1..ldab` the
/// multipliers of `L` (unit lower triangular, `kl` subdiagonals), and the
/// pivot indices say which row was swapped with row `j` at step `j`.
///
/// `kl` and `ku` are clamped to `n − 1` (a wider band holds nothing more).
///
/// Life cycle: [`new`](Self::new) (allocates), then repeatedly
/// [`clear`](Self::clear), [`add`](Self::add)/[`set`](Self::set),
/// [`factor`](Self::factor), [`solve`](Self::solve) — none of which allocates.
#[derive(Debug, Clone)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    ldab: usize,
    ab: Vec<f64>,
    ipiv: Vec<usize>,
    factored: bool,
    info: PivotInfo,
}

impl BandMatrix {
    /// A zero `n × n` matrix with half-bandwidths `kl`, `ku` (clamped to
    /// `n − 1`). Allocates `(2 kl + ku + 1) n` values and `n` pivot indices.
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let kl = kl.min(n.saturating_sub(1));
        let ku = ku.min(n.saturating_sub(1));
        let ldab = 2 * kl + ku + 1;
        BandMatrix {
            n,
            kl,
            ku,
            ldab,
            ab: vec![0.0; ldab * n],
            ipiv: vec![0; n],
            factored: false,
            info: PivotInfo::default(),
        }
    }

    /// Order `n`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of subdiagonals `kl` (after clamping to `n − 1`).
    pub fn kl(&self) -> usize {
        self.kl
    }

    /// Number of superdiagonals `ku` (after clamping to `n − 1`).
    pub fn ku(&self) -> usize {
        self.ku
    }

    /// Whether `i, j` lies in the band: `j ≤ i + ku` and `i ≤ j + kl`.
    pub fn in_band(&self, i: usize, j: usize) -> bool {
        i < self.n && j < self.n && j <= i + self.ku && i <= j + self.kl
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        j * self.ldab + self.kl + self.ku + i - j
    }

    /// `A ← 0` (entries, fill rows and factorization state). No allocation.
    pub fn clear(&mut self) {
        self.ab.fill(0.0);
        self.factored = false;
        self.info = PivotInfo::default();
    }

    /// `a_ij ← a_ij + v`. `i, j` must be in the band (checked in debug
    /// builds; out-of-band entries would silently corrupt the storage) and
    /// the matrix must not be factored.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(self.in_band(i, j), "({i}, {j}) outside the band");
        debug_assert!(!self.factored, "add to a factored BandMatrix");
        let k = self.idx(i, j);
        self.ab[k] += v;
    }

    /// `a_ij ← v` (same conditions as [`add`](Self::add)).
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(self.in_band(i, j), "({i}, {j}) outside the band");
        debug_assert!(!self.factored, "set in a factored BandMatrix");
        let k = self.idx(i, j);
        self.ab[k] = v;
    }

    /// `a_ij` (0 outside the band). After [`factor`](Self::factor) this
    /// reads the band storage of the factors, not `A`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if self.in_band(i, j) {
            self.ab[self.idx(i, j)]
        } else {
            0.0
        }
    }

    /// `y ← y + A x` with the unfactored matrix (panics if factored).
    /// Cost `O(n (kl + ku + 1))`.
    pub fn mul_vec_add(&self, x: &[f64], y: &mut [f64]) {
        assert!(!self.factored, "mul_vec_add on a factored BandMatrix");
        assert_eq!(x.len(), self.n);
        assert_eq!(y.len(), self.n);
        let kv = self.kl + self.ku;
        for (j, &xj) in x.iter().enumerate() {
            if xj == 0.0 {
                continue;
            }
            let i0 = j.saturating_sub(self.ku);
            let i1 = (j + self.kl).min(self.n - 1);
            let col = &self.ab[j * self.ldab + kv + i0 - j..=j * self.ldab + kv + i1 - j];
            for (yi, a) in y[i0..=i1].iter_mut().zip(col) {
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
        assert!(self.factored, "det_sign of an unfactored BandMatrix");
        let kv = self.kl + self.ku;
        let mut sign = 1.0;
        for j in 0..self.n {
            if self.ab[j * self.ldab + kv] < 0.0 {
                sign = -sign;
            }
            if self.ipiv[j] != j {
                sign = -sign;
            }
        }
        sign
    }

    /// `A = Π L U` in place with partial pivoting (LAPACK `dgbtf2`): at step
    /// `j` the row with the largest `|a_ij|`, `j ≤ i ≤ min(j + kl, n − 1)`,
    /// is swapped into row `j`, `l_ij = a_ij / a_jj`, and
    /// `a_ic ← a_ic − l_ij a_jc` for `c` up to the last column reached by
    /// the swapped rows. Cost `O(n kl (kl + ku))`, no allocation.
    ///
    /// Fails on an exactly zero pivot ([`Failure::ZeroPivot`]) or a
    /// non-finite entry of `A` or of the factors ([`Failure::NonFinite`]);
    /// then the matrix is left unusable until the next
    /// [`clear`](Self::clear). `part` of the error is [`Part::Matrix`].
    pub fn factor(&mut self) -> Result<(), Singular> {
        assert!(!self.factored, "BandMatrix factored twice without clear");
        let (n, kl, ku, ld) = (self.n, self.kl, self.ku, self.ldab);
        let kv = kl + ku;
        let fail = |column, failure| Singular {
            part: Part::Matrix,
            column,
            failure,
        };
        // Input: largest entry, finiteness; zero the fill rows.
        let mut max_entry = 0.0f64;
        for j in 0..n {
            let col = &mut self.ab[j * ld..(j + 1) * ld];
            col[..kl].fill(0.0);
            for &a in &col[kl..] {
                if !a.is_finite() {
                    return Err(fail(j, Failure::NonFinite));
                }
                max_entry = max_entry.max(a.abs());
            }
        }
        let mut min_pivot = f64::INFINITY;
        let mut max_pivot = 0.0f64;
        // Last column touched by the row interchanges so far.
        let mut ju = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let col = j * ld + kv;
            let mut jp = 0;
            let mut amax = self.ab[col].abs();
            for p in 1..=km {
                let a = self.ab[col + p].abs();
                if a > amax {
                    amax = a;
                    jp = p;
                }
            }
            self.ipiv[j] = j + jp;
            if amax == 0.0 {
                return Err(fail(j, Failure::ZeroPivot));
            }
            if !amax.is_finite() {
                return Err(fail(j, Failure::NonFinite));
            }
            min_pivot = min_pivot.min(amax);
            max_pivot = max_pivot.max(amax);
            ju = ju.max((j + ku + jp).min(n - 1));
            if jp != 0 {
                for c in j..=ju {
                    let base = c * ld + kv + j - c;
                    self.ab.swap(base, base + jp);
                }
            }
            if km > 0 {
                let r = 1.0 / self.ab[col];
                for l in &mut self.ab[col + 1..=col + km] {
                    *l *= r;
                }
                let (left, right) = self.ab.split_at_mut((j + 1) * ld);
                let mult = &left[col + 1..=col + km];
                for c in j + 1..=ju {
                    // Row j of column c, then rows j+1..=j+km below it.
                    let base = (c - j - 1) * ld + kv + j - c;
                    let t = right[base];
                    if t != 0.0 {
                        for (a, l) in right[base + 1..=base + km].iter_mut().zip(mult) {
                            *a -= l * t;
                        }
                    }
                }
            }
        }
        // Output: largest |u_ij|, finiteness (overflow in the elimination).
        let mut max_u = 0.0f64;
        for j in 0..n {
            let col = &self.ab[j * ld..(j + 1) * ld];
            if col.iter().any(|a| !a.is_finite()) {
                return Err(fail(j, Failure::NonFinite));
            }
            for &u in &col[..=kv] {
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

    /// `b ← A⁻¹ b` with the factors (LAPACK `dgbtrs`, no transpose):
    /// `b ← L⁻¹ Πᵀ b` (interchanges and multipliers applied step by step),
    /// then `b ← U⁻¹ b`. Panics unless factored. Cost `O(n (2 kl + ku))`,
    /// no allocation.
    pub fn solve(&self, b: &mut [f64]) {
        assert!(self.factored, "solve with an unfactored BandMatrix");
        assert_eq!(b.len(), self.n);
        let (n, kl, ld) = (self.n, self.kl, self.ldab);
        let kv = kl + self.ku;
        if kl > 0 {
            for j in 0..n.saturating_sub(1) {
                let lm = kl.min(n - 1 - j);
                let l = self.ipiv[j];
                if l != j {
                    b.swap(l, j);
                }
                let bj = b[j];
                if bj != 0.0 {
                    let mult = &self.ab[j * ld + kv + 1..=j * ld + kv + lm];
                    for (bi, m) in b[j + 1..=j + lm].iter_mut().zip(mult) {
                        *bi -= m * bj;
                    }
                }
            }
        }
        for j in (0..n).rev() {
            if b[j] != 0.0 {
                let bj = b[j] / self.ab[j * ld + kv];
                b[j] = bj;
                let i0 = j.saturating_sub(kv);
                let ucol = &self.ab[j * ld + kv + i0 - j..j * ld + kv];
                for (bi, u) in b[i0..j].iter_mut().zip(ucol) {
                    *bi -= u * bj;
                }
            }
        }
    }

    /// `B ← A⁻¹ B` for `nrhs` right-hand sides stored column-major in `b`
    /// (`b.len() == n · nrhs`, column `r` at `b[r·n..(r+1)·n]`).
    pub fn solve_many(&self, b: &mut [f64], nrhs: usize) {
        assert_eq!(b.len(), self.n * nrhs);
        if self.n == 0 {
            assert!(self.factored, "solve with an unfactored BandMatrix");
            return;
        }
        for col in b.chunks_exact_mut(self.n) {
            self.solve(col);
        }
    }
}
