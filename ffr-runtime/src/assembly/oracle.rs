//! Test oracle of the analytic iteration matrix: central differences of
//! the scaled residual.

use super::{Assembly, Slot};
use crate::body::Body;

impl<B: Body> Assembly<'_, B> {
    /// The scaled generalized-α residual `[r_dyn/β'; Φ]` with `λ = β' λ̃`.
    #[allow(clippy::too_many_arguments)]
    fn scaled_residual(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam_scaled: &[f64],
        bp: f64,
        r: &mut [f64],
    ) {
        let lam: Vec<f64> = lam_scaled.iter().map(|l| l * bp).collect();
        self.residual(t, q, v, a, &lam, r);
        for x in r[..self.n].iter_mut() {
            *x /= bp;
        }
    }

    /// Test oracle of the analytic iteration matrix: the largest difference
    /// between an entry of [`Assembly::jacobian`] and the central difference
    /// of the scaled residual (with `q̇ += γ' δ`, `q̈ += β' δ` for a coordinate
    /// step `δ`), relative to the entry (with a floor of 10⁻⁶ of the
    /// column's largest entry); and the column where it occurs. Allocates
    /// (checks only).
    #[allow(clippy::too_many_arguments)]
    pub fn iteration_matrix_error(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam_scaled: &[f64],
        bp: f64,
        gp: f64,
    ) -> (f64, usize) {
        let (n, m) = (self.n, self.m);
        let mut r = vec![0.0; n + m];
        self.jacobian(t, q, v, a, lam_scaled, bp, gp, &mut r);
        let nb = self.x_band.len();
        let nk = self.x_border.len();
        let (mut yb, mut yk) = (vec![0.0; nb], vec![0.0; nk]);
        let (mut xb, mut xk) = (vec![0.0; nb], vec![0.0; nk]);
        let mut worst = (0.0f64, 0usize);
        let (mut rp, mut rm) = (vec![0.0; n + m], vec![0.0; n + m]);
        for col in 0..n + m {
            let slot = if col < n {
                self.coord_slot[col]
            } else {
                Slot::Border(self.mult_slot[col - n])
            };
            xb.iter_mut().for_each(|x| *x = 0.0);
            xk.iter_mut().for_each(|x| *x = 0.0);
            match slot {
                Slot::Fixed => continue,
                Slot::Band(b, i) => {
                    xb[self.solver.block_range(b as usize).start + i as usize] = 1.0
                }
                Slot::Border(g) => xk[g as usize] = 1.0,
            }
            self.solver.mul_vec(&xb, &xk, &mut yb, &mut yk);
            // Analytic column in coordinate/row space (also kept for callers).
            let mut analytic = vec![0.0; n + m];
            for (c, s) in self.coord_slot.iter().enumerate() {
                analytic[c] = match *s {
                    Slot::Band(b, i) => yb[self.solver.block_range(b as usize).start + i as usize],
                    Slot::Border(g) => yk[g as usize],
                    Slot::Fixed => 0.0,
                };
            }
            for (k, &g) in self.mult_slot.iter().enumerate() {
                analytic[n + k] = yk[g as usize];
            }
            // Central difference.
            let (mut qp, mut vp, mut ap, mut lp) =
                (q.to_vec(), v.to_vec(), a.to_vec(), lam_scaled.to_vec());
            let e;
            if col < n {
                e = 1e-6 * (1.0 + q[col].abs());
                qp[col] += e;
                vp[col] += gp * e;
                ap[col] += bp * e;
            } else {
                e = 1e-6 * (1.0 + lam_scaled[col - n].abs());
                lp[col - n] += e;
            }
            self.scaled_residual(t, &qp, &vp, &ap, &lp, bp, &mut rp);
            let (mut qm, mut vm, mut am, mut lm) =
                (q.to_vec(), v.to_vec(), a.to_vec(), lam_scaled.to_vec());
            if col < n {
                qm[col] -= e;
                vm[col] -= gp * e;
                am[col] -= bp * e;
            } else {
                lm[col - n] -= e;
            }
            self.scaled_residual(t, &qm, &vm, &am, &lm, bp, &mut rm);
            // Per entry, relative to the entry (floor: 10⁻⁶ of the column's
            // largest, below which differences are round-off of the others).
            let mut colmax = 0.0f64;
            for (i, x) in analytic.iter().enumerate() {
                if !(i < n && self.coord_slot[i] == Slot::Fixed) {
                    colmax = colmax.max(x.abs());
                }
            }
            let mut rel = 0.0f64;
            for i in 0..n + m {
                if i < n && self.coord_slot[i] == Slot::Fixed {
                    continue;
                }
                let fd = (rp[i] - rm[i]) / (2.0 * e);
                let scale = analytic[i].abs().max(fd.abs()) + 1e-6 * colmax;
                if scale > 0.0 {
                    rel = rel.max((fd - analytic[i]).abs() / scale);
                }
            }
            if rel > worst.0 {
                worst = (rel, col);
            }
        }
        // Restore a factorizable state for callers that go on.
        self.jacobian(t, q, v, a, lam_scaled, bp, gp, &mut r);
        worst
    }
}
