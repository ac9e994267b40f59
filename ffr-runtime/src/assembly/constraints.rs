//! Constraint rows beyond the residual: `γ` of `Φ̈ = Φ_q q̈ − γ` and the
//! velocity violation `Φ_q q̇ + Φ_t` (Baumgarte stabilization, initial
//! velocities), the projection of Euler-parameter rates onto the
//! normalization, and every row densely for set-up checks.

use super::Assembly;
use crate::body::Body;

impl<B: Body> Assembly<'_, B> {
    /// `γ` of every constraint row at `(t, q, q̇)` (after [`Assembly::residual`]
    /// or [`Assembly::mass_system`] evaluated the rows at `q`), into `out` (m):
    /// `Φ̈ = Φ_q q̈ − γ`.
    pub fn gamma(&mut self, t: f64, v: &[f64], out: &mut [f64]) {
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            out[row] = -v[o..o + 4].iter().map(|x| x * x).sum::<f64>();
        }
        for (c, cw) in self.constraints.iter().zip(self.cons.iter_mut()) {
            for (i, &g) in cw.ka.idx.iter().chain(&cw.kb.idx).enumerate() {
                cw.qd[i] = v[g];
            }
            for (k, (row, re)) in c.rows.iter().zip(cw.rows.iter()).enumerate() {
                out[cw.first + k] = re.gamma(row, &cw.ka, &cw.kb, t, &cw.qd);
            }
        }
    }

    /// Remove from each body's Euler-parameter rates `ė` their component
    /// along `e` (`ė ← ė − e (eᵀė)/(eᵀe)`): the velocity form of the
    /// normalization `eᵀe = 1`. The component is invisible to the motion
    /// (`ω = Ḡ ė` and `Ḡ e = 0`), so this changes no physical velocity.
    pub fn project_normalization_rates(&self, q: &[f64], v: &mut [f64]) {
        for &(i, _) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            let ee: f64 = (0..4).map(|k| q[o + k] * q[o + k]).sum();
            let ed: f64 = (0..4).map(|k| q[o + k] * v[o + k]).sum();
            for k in 0..4 {
                v[o + k] -= q[o + k] * ed / ee;
            }
        }
    }

    /// `Φ_q q̇ + Φ_t` of every row (after the rows were evaluated at `q`).
    pub fn velocity_violation(&self, v: &[f64], q: &[f64], out: &mut [f64]) {
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            out[row] = (0..4).map(|k| q[o + k] * v[o + k]).sum();
        }
        for cw in &self.cons {
            for (k, re) in cw.rows.iter().enumerate() {
                let mut s = re.phi_t;
                for (i, &g) in cw.ka.idx.iter().chain(&cw.kb.idx).enumerate() {
                    s += re.grad[i] * v[g];
                }
                out[cw.first + k] = s;
            }
        }
    }

    /// Every constraint row at `(t, q)` densely, for set-up checks (the
    /// initial projection, redundancy): `phi` (m) gets `Φ`, `phi_t` (m)
    /// `∂Φ/∂t`, `jac` (m × n, zeroed first) `Φ_q` over all coordinates,
    /// prescribed ones included. Allocation-free, but `O(m n)` storage: not
    /// for a step.
    pub fn constraints_dense(
        &mut self,
        t: f64,
        q: &[f64],
        phi: &mut [f64],
        phi_t: &mut [f64],
        jac: &mut nalgebra::DMatrix<f64>,
    ) {
        jac.fill(0.0);
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            let e = &q[o..o + 4];
            phi[row] = 0.5 * (e.iter().map(|x| x * x).sum::<f64>() - 1.0);
            phi_t[row] = 0.0;
            for k in 0..4 {
                jac[(row, o + k)] = e[k];
            }
        }
        for (c, cw) in self.constraints.iter().zip(self.cons.iter_mut()) {
            cw.ka.eval(&c.a, q);
            cw.kb.eval(&c.b, q);
            for (k, (row, re)) in c.rows.iter().zip(cw.rows.iter_mut()).enumerate() {
                re.eval(row, &cw.ka, &cw.kb, t);
                let r = cw.first + k;
                phi[r] = re.phi;
                phi_t[r] = re.phi_t;
                for (i, &g) in cw.ka.idx.iter().chain(&cw.kb.idx).enumerate() {
                    jac[(r, g)] += re.grad[i];
                }
            }
        }
    }
}
