//! What a static solution needs of the assembled equations
//! ([`crate::statics`]): the matrix with explicit coefficients
//! `c_M M + c_C C + K` (the stiffness `K` alone at `c_M = c_C = 0`), the
//! load factor on gravity and the applied loads, the sign of the matrix's
//! determinant, and a unit-free probe for a singular direction.

use super::{Assembly, Slot};
use crate::body::Body;

impl<B: Body> Assembly<'_, B> {
    /// Scale gravity and the applied loads (point forces, constant motor
    /// torques: not springs, dampers or PD motors) by `s` in every
    /// evaluation from now on: the load factor `λ` of a load-stepped static
    /// solution. `1` (the default) leaves the equations as they are, bit
    /// for bit.
    pub fn set_load_scale(&mut self, s: f64) {
        self.load_scale = s;
        self.gravity = self.sys.gravity * s;
    }

    /// The load factor ([`Assembly::set_load_scale`]).
    pub fn load_scale(&self) -> f64 {
        self.load_scale
    }

    /// The matrix `[c_M M + c_C C + K + ∂(Φ_qᵀ λ)/∂q, Φ_qᵀ; Φ_q, 0]` at
    /// `(t, q, q̇, q̈, λ)` into the solver (unscaled, physical multipliers),
    /// and the residual there into `r` (as [`Assembly::residual`]): `M =
    /// ∂r/∂q̈`, `C = ∂r/∂q̇`, `K = ∂r/∂q` from the same analytic
    /// derivatives as the generalized-α iteration matrix
    /// ([`Assembly::jacobian`] is this matrix with `c_M = β'`, `c_C = γ'`,
    /// divided by `β'`). With `c_M = c_C = 0` at `q̇ = q̈ = 0` it is the
    /// tangent stiffness of a static equilibrium; `c_M > 0` shifts it by
    /// the mass matrix. Allocates nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn static_matrix(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam: &[f64],
        cm: f64,
        cc: f64,
        r: &mut [f64],
    ) {
        self.assemble_matrix(t, q, v, a, lam, cm, cc, 1.0, 1.0, r);
    }

    /// The sign of the determinant of the matrix factored last
    /// ([`Assembly::factor`]; the unknowns' order does not change it: a
    /// symmetric permutation). Panics unless factored.
    pub fn det_sign(&self) -> f64 {
        self.solver.det_sign()
    }

    /// The unknown `u` (a coordinate `0..n`, a multiplier `n..n + m`) in
    /// words: ``coordinate `θ` of body `bar` (…)``, or a joint's row.
    pub fn describe_unknown(&self, u: usize) -> String {
        let slot = if u < self.n {
            self.coord_slot[u]
        } else {
            Slot::Border(self.mult_slot[u - self.n])
        };
        self.describe_slot(slot)
            .unwrap_or_else(|| format!("unknown {u}"))
    }

    /// Every entry `(row, column, value)` of the matrix in the solver
    /// (before it is factored), rows and columns as unknowns: coordinate
    /// `c`, or `n + k` for multiplier `k`. Allocates (diagnosis, not
    /// stepping).
    fn for_each_entry(&mut self, mut f: impl FnMut(usize, usize, f64)) {
        let n = self.n;
        let nb = self.solver.n_blocks();
        // The unknown of every band row of every block, and of every border index.
        let mut band_unknown: Vec<Vec<usize>> = (0..nb)
            .map(|b| vec![usize::MAX; self.solver.block_range(b).len()])
            .collect();
        let mut border_unknown = vec![usize::MAX; self.solver.k()];
        for (c, s) in self.coord_slot.iter().enumerate() {
            match *s {
                Slot::Band(b, i) => band_unknown[b as usize][i as usize] = c,
                Slot::Border(g) => border_unknown[g as usize] = c,
                Slot::Fixed => {}
            }
        }
        for (k, &g) in self.mult_slot.iter().enumerate() {
            border_unknown[g as usize] = n + k;
        }
        for (b, rows) in band_unknown.iter().enumerate() {
            let band = self.solver.band(b);
            let nn = band.n();
            for j in 0..nn {
                let i0 = j.saturating_sub(band.ku());
                let i1 = (j + band.kl()).min(nn.saturating_sub(1));
                for i in i0..=i1 {
                    f(rows[i], rows[j], band.get(i, j));
                }
            }
            let border: Vec<usize> = self.solver.border(b).to_vec();
            let c = self.solver.c_mut(b);
            for (l, &g) in border.iter().enumerate() {
                for (i, &row) in rows.iter().enumerate() {
                    f(row, border_unknown[g], c.get(i, l));
                }
            }
            let e = self.solver.e_mut(b);
            for (l, &g) in border.iter().enumerate() {
                for (j, &col) in rows.iter().enumerate() {
                    f(border_unknown[g], col, e.get(l, j));
                }
            }
        }
        let k = self.solver.k();
        // Dense or banded border: `d_get` is 0 outside a band.
        for h in 0..k {
            for g in 0..k {
                f(
                    border_unknown[g],
                    border_unknown[h],
                    self.solver.d_get(g, h),
                );
            }
        }
    }

    /// The diagonal entries of the matrix in the solver (before it is
    /// factored) for the coordinates `coords`. Allocates.
    pub fn matrix_diagonal(&mut self, coords: &[usize]) -> Vec<f64> {
        let mut diag = vec![0.0; self.n];
        self.for_each_entry(|i, j, v| {
            if i == j && i < diag.len() {
                diag[i] += v;
            }
        });
        coords.iter().map(|&c| diag[c]).collect()
    }

    /// Row and column scalings `D_r`, `D_c` (length `n + m`, powers of
    /// two) that equilibrate the matrix in the solver (before it is
    /// factored) as LAPACK's `dgeequ`: each row's largest entry scaled to
    /// about 1, then each column's. A change of units of the coordinates
    /// or of the constraint rows scales the matrix by diagonal matrices,
    /// which these scalings undo, so that the condition of `D_r J D_c` is
    /// free of units. Prescribed coordinates and empty rows get 1.
    /// Allocates.
    pub fn equilibration(&mut self) -> (Vec<f64>, Vec<f64>) {
        let dim = self.n + self.m;
        let mut row = vec![0.0f64; dim];
        self.for_each_entry(|i, _, v| row[i] = row[i].max(v.abs()));
        let pow2 = |x: f64| {
            if x > 0.0 && x.is_finite() {
                (-x.log2().round()).exp2()
            } else {
                1.0
            }
        };
        let dr: Vec<f64> = row.iter().map(|&x| pow2(x)).collect();
        let mut col = vec![0.0f64; dim];
        self.for_each_entry(|i, j, v| col[j] = col[j].max((dr[i] * v).abs()));
        let dc: Vec<f64> = col.iter().map(|&x| pow2(x)).collect();
        (dr, dc)
    }
}
