//! The separate parts of the iteration matrix as dense matrices over the
//! free coordinates, for linear models ([`crate::linear`]): `M` from the
//! mass system, `K` and `C` from the analytic iteration matrix with chosen
//! `(β', γ')`; and the generalized force of a force element at a state.

use super::residual::eval_force;
use super::{kinematics::kin, Assembly, ForceWork, Slot};
use crate::body::Body;
use crate::force::{ForceElement, ForceEval};
use nalgebra::DMatrix;

/// `γ'` of the evaluation that isolates `C`: a power of two (exact
/// scaling), large enough that `(M + K)/γ'` is below round-off of `C`.
const GAMMA_C: f64 = 1099511627776.0; // 2⁴⁰

/// The linearized equations' matrices at a state, over the free
/// coordinates `free` (in coordinate order) and the constraint rows.
#[derive(Clone, Debug)]
pub struct TangentParts {
    /// The free (not prescribed) coordinates, global indices.
    pub free: Vec<usize>,
    /// `M = ∂r/∂q̈`.
    pub m: DMatrix<f64>,
    /// `C = ∂r/∂q̇` (damping, gyroscopic terms).
    pub c: DMatrix<f64>,
    /// `K = ∂r/∂q + ∂(Φ_qᵀ λ)/∂q` (elastic, stiffening, inertial and
    /// geometric terms of the constraint reactions).
    pub k: DMatrix<f64>,
    /// `Φ_q` (constraint rows × free coordinates).
    pub phi_q: DMatrix<f64>,
}

impl<B: Body> Assembly<'_, B> {
    /// The matrix now in the solver as a dense matrix over `[free
    /// coordinates; multipliers]` (rows and columns in that order).
    fn dense_solver_matrix(&self, free: &[usize]) -> DMatrix<f64> {
        let nu = free.len();
        let dim = nu + self.m;
        let slot = |k: usize| -> Slot {
            if k < nu {
                self.coord_slot[free[k]]
            } else {
                Slot::Border(self.mult_slot[k - nu])
            }
        };
        let nb = self.x_band.len();
        let nk = self.x_border.len();
        let (mut xb, mut xk) = (vec![0.0; nb], vec![0.0; nk]);
        let (mut yb, mut yk) = (vec![0.0; nb], vec![0.0; nk]);
        let mut out = DMatrix::zeros(dim, dim);
        for col in 0..dim {
            xb.iter_mut().for_each(|x| *x = 0.0);
            xk.iter_mut().for_each(|x| *x = 0.0);
            match slot(col) {
                Slot::Band(b, i) => {
                    xb[self.solver.block_range(b as usize).start + i as usize] = 1.0
                }
                Slot::Border(g) => xk[g as usize] = 1.0,
                Slot::Fixed => continue,
            }
            self.solver.mul_vec(&xb, &xk, &mut yb, &mut yk);
            for row in 0..dim {
                out[(row, col)] = match slot(row) {
                    Slot::Band(b, i) => yb[self.solver.block_range(b as usize).start + i as usize],
                    Slot::Border(g) => yk[g as usize],
                    Slot::Fixed => 0.0,
                };
            }
        }
        out
    }

    /// The free coordinates (not prescribed), in coordinate order.
    pub fn free_coordinates(&self) -> Vec<usize> {
        (0..self.n).filter(|&c| !self.is_prescribed(c)).collect()
    }

    /// `M`, `C`, `K` and `Φ_q` at the state `(t, q, q̇, q̈, λ)`, dense over
    /// the free coordinates: `M` and `Φ_q` from the mass system
    /// ([`Assembly::mass_system`]); with `J(β', γ') = β' M + γ' C + K` the
    /// analytic iteration matrix (times `β'`, [`Assembly::jacobian`] with
    /// `λ̃ = λ/β'`), `K = J(1, 0) − M` and `C = (J(1, γ_c) − J(1, 0))/γ_c`
    /// with `γ_c = 2⁴⁰` (exact scaling; the error of `C` is round-off of
    /// `(M + K)/γ_c`). Allocates (analysis, not stepping).
    pub fn tangent_parts(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam: &[f64],
    ) -> TangentParts {
        let free = self.free_coordinates();
        let nu = free.len();
        self.mass_system(t, q);
        let ms = self.dense_solver_matrix(&free);
        let mut r = vec![0.0; self.n + self.m];
        self.jacobian(t, q, v, a, lam, 1.0, 0.0, &mut r);
        let j0 = self.dense_solver_matrix(&free);
        self.jacobian(t, q, v, a, lam, 1.0, GAMMA_C, &mut r);
        let jg = self.dense_solver_matrix(&free);
        let m = ms.view((0, 0), (nu, nu)).into_owned();
        let k = j0.view((0, 0), (nu, nu)) - &m;
        let c = (jg.view((0, 0), (nu, nu)) - j0.view((0, 0), (nu, nu))) / GAMMA_C;
        let phi_q = ms.view((nu, 0), (self.m, nu)).into_owned();
        TangentParts {
            free,
            m,
            c,
            k,
            phi_q,
        }
    }

    /// The generalized force `Q` (length `n`, all coordinates) of the force
    /// element `fe` at `(t, q, q̇)`, by the same evaluation the residual
    /// uses. The element need not belong to the system (an input of a
    /// linear model). Allocates.
    pub fn generalized_force(&self, fe: &ForceElement, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        let (ma, mb) = fe.markers();
        let ka = kin(self.sys, ma);
        let kb = mb.map(|m| kin(self.sys, m));
        let nl = ka.len() + kb.as_ref().map_or(0, |k| k.len());
        let mut fw = ForceWork {
            ka,
            kb,
            eval: ForceEval::new(nl),
            qd: vec![0.0; nl],
        };
        eval_force(fe, &mut fw, q, v, t, None, &self.inputs);
        let mut out = vec![0.0; self.n];
        let na = fw.ka.len();
        for (i, &g) in fw.ka.idx.iter().enumerate() {
            out[g] += fw.eval.q[i];
        }
        if let Some(kb) = &fw.kb {
            for (i, &g) in kb.idx.iter().enumerate() {
                out[g] += fw.eval.q[na + i];
            }
        }
        out
    }
}
