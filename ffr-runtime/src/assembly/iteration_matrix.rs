//! The analytic iteration matrix of a generalized-α step (the exact
//! derivative of the residual with `∂q̈/∂q = β'`, `∂q̇/∂q = γ'`) into the
//! bordered solver, entry by entry through each unknown's [`Slot`].

use super::residual::{eval_force, is_applied_load};
use super::{v3, Assembly, BodyScratch, Slot};
use crate::body::Body;
use crate::linalg::BorderedSystem;
use crate::marker::MarkerKin;
use crate::rotation::Rotation;
use nalgebra::Vector3;

impl<B: Body> Assembly<'_, B> {
    /// Route `J[row, col] += v` (coordinate or multiplier unknowns by slot).
    #[inline]
    pub(super) fn add(solver: &mut BorderedSystem, row: Slot, col: Slot, v: f64) {
        if v == 0.0 {
            return;
        }
        match (row, col) {
            (Slot::Fixed, _) | (_, Slot::Fixed) => {}
            (Slot::Band(b, i), Slot::Band(c, j)) => {
                debug_assert_eq!(b, c, "band entries couple one body only");
                solver.band_mut(b as usize).add(i as usize, j as usize, v);
            }
            (Slot::Band(b, i), Slot::Border(g)) => {
                let l = solver
                    .border_local(b as usize, g as usize)
                    .expect("border column of the body");
                solver.c_mut(b as usize).add(i as usize, l, v);
            }
            (Slot::Border(g), Slot::Band(b, j)) => {
                let l = solver
                    .border_local(b as usize, g as usize)
                    .expect("border row of the body");
                solver.e_mut(b as usize).add(l, j as usize, v);
            }
            (Slot::Border(g), Slot::Border(h)) => {
                solver.d_add(g as usize, h as usize, v);
            }
        }
    }

    /// The body block of `∂r/∂q` into the solver, scaled by `s`, from its
    /// body-frame derivatives in `sc.tangent` and the maps from `q` to the
    /// frame inputs: `phi_r[k]` = `∂[ā, α, ω]/∂R_k`, `phi_th[j]` =
    /// `∂[ā, α, ω]/∂θ_j`; with `rotation_terms`, also `∂A/∂θ_j f_r` and
    /// `∂Ḡ/∂θ_jᵀ f_θ` (not in the mass matrix).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_body_block(
        solver: &mut BorderedSystem,
        slots: &[Slot],
        i_body: (usize, usize, usize, usize),
        sc: &BodyScratch,
        rot: &Rotation,
        phi_r: &[[f64; 9]; 3],
        phi_th: &[[f64; 9]; 4],
        rotation_terms: bool,
        s: f64,
    ) {
        let (o, d, nth, nf) = i_body;
        let f0 = o + d + nth;
        let t = &sc.tangent;
        // Elastic rows.
        for a in 0..nf {
            let ra = slots[f0 + a];
            if ra == Slot::Fixed {
                continue;
            }
            let (lo, row) = t.k_ff.row(a);
            for (k, val) in row.iter().enumerate() {
                Self::add(solver, ra, slots[f0 + lo + k], s * val);
            }
            if sc.frame_rows {
                let dfp = &t.d_f_frame[a * 9..a * 9 + 9];
                for (k, pr) in phi_r.iter().enumerate().take(d) {
                    let v: f64 = (0..9).map(|p| dfp[p] * pr[p]).sum();
                    Self::add(solver, ra, slots[o + k], s * v);
                }
                for (j, pt) in phi_th.iter().enumerate().take(nth) {
                    let v: f64 = (0..9).map(|p| dfp[p] * pt[p]).sum();
                    Self::add(solver, ra, slots[o + d + j], s * v);
                }
            }
        }
        if !sc.frame_rows {
            return;
        }
        // Reference rows: r_R = A f_r, r_θ = Ḡᵀ f_θ.
        // ∂F/∂x for x = q_f (k_ref_f), R_k, θ_j, as 6-vectors, then mapped.
        let mut map_rows = |col: Slot, dfx: [f64; 6], extra_r: Vector3<f64>, extra_th: [f64; 4]| {
            let fr = rot.a * Vector3::new(dfx[0], dfx[1], dfx[2]) + extra_r;
            for k in 0..d {
                Self::add(solver, slots[o + k], col, s * fr[k]);
            }
            let gth = rot.g_t(&Vector3::new(dfx[3], dfx[4], dfx[5]));
            for j in 0..nth {
                Self::add(solver, slots[o + d + j], col, s * (gth[j] + extra_th[j]));
            }
        };
        for b in 0..nf {
            let col = slots[f0 + b];
            if col == Slot::Fixed {
                continue;
            }
            let dfx: [f64; 6] = std::array::from_fn(|r| t.k_ref_f[r * nf + b]);
            map_rows(col, dfx, Vector3::zeros(), [0.0; 4]);
        }
        let drp = |r: usize, p: &[f64; 9]| -> f64 {
            (0..9).map(|k| t.d_ref_frame[r * 9 + k] * p[k]).sum()
        };
        for (k, pr) in phi_r.iter().enumerate().take(d) {
            let dfx: [f64; 6] = std::array::from_fn(|r| drp(r, pr));
            map_rows(slots[o + k], dfx, Vector3::zeros(), [0.0; 4]);
        }
        for (j, pt) in phi_th.iter().enumerate().take(nth) {
            let dfx: [f64; 6] = std::array::from_fn(|r| drp(r, pt));
            let (er, eth) = if rotation_terms {
                let er = rot.da[j] * v3(&sc.forces.f_r);
                let fth = v3(&sc.forces.f_th);
                let mut eth = [0.0; 4];
                for (m, e) in eth.iter_mut().enumerate().take(nth) {
                    *e = rot.dg[j][m].dot(&fth);
                }
                (er, eth)
            } else {
                (Vector3::zeros(), [0.0; 4])
            };
            map_rows(slots[o + d + j], dfx, er, eth);
        }
    }

    /// The scaled iteration matrix of a generalized-α step into the solver:
    /// `[(β' M + γ' C + K)/β' + ∂(Φ_qᵀ λ̃)/∂q, Φ_qᵀ; Φ_q, 0]` (with
    /// `λ = β' λ̃`), and the residual at the same point into `r` (unscaled,
    /// as [`Assembly::residual`] with `λ = β' λ̃`).
    #[allow(clippy::too_many_arguments)]
    pub fn jacobian(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam_scaled: &[f64],
        bp: f64,
        gp: f64,
        r: &mut [f64],
    ) {
        self.assemble_matrix(t, q, v, a, lam_scaled, bp, gp, 1.0 / bp, bp, r);
    }

    /// The matrix `[s (β' M + γ' C + K) + ∂(Φ_qᵀ λ̃)/∂q, Φ_qᵀ; Φ_q, 0]`
    /// into the solver and the residual at `λ = f_λ λ̃` into `r`: the
    /// generalized-α iteration matrix with `s = 1/β'`, `f_λ = β'`
    /// ([`Assembly::jacobian`]), the static matrix with `s = f_λ = 1`
    /// ([`Assembly::static_matrix`]). The products are the same for
    /// either (the time step's arithmetic does not change).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn assemble_matrix(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam_scaled: &[f64],
        bp: f64,
        gp: f64,
        s: f64,
        lam_factor: f64,
        r: &mut [f64],
    ) {
        self.solver.clear();
        for i in 0..self.sys.bodies.len() {
            if self.bodies[i].skip {
                continue;
            }
            let (st, rot) = self.body_state(i, q, v, a);
            let b = &self.sys.bodies[i];
            let sc = &mut self.bodies[i];
            b.body.tangent(
                &st,
                bp,
                gp,
                sc.frame_rows,
                &mut sc.work,
                &mut sc.forces,
                &mut sc.tangent,
            );
            if let Some(dm) = &sc.damping {
                sc.tangent.k_ff.add_scaled(gp, dm);
            }
            let (o, d, nth) = (b.offset, b.d, b.n_theta);
            // ∂[ā, α, ω]/∂R_k and ∂/∂θ_j.
            let mut phi_r = [[0.0; 9]; 3];
            for (k, pr) in phi_r.iter_mut().enumerate().take(d) {
                for (c, p) in pr[..3].iter_mut().enumerate() {
                    *p = bp * rot.a[(k, c)];
                }
            }
            let mut rdd = Vector3::zeros();
            for k in 0..d {
                rdd[k] = a[o + k];
            }
            let rg = rdd - self.gravity;
            let thd = &v[o + d..o + d + nth];
            let thdd = &a[o + d..o + d + nth];
            let mut phi_th = [[0.0; 9]; 4];
            for (j, pt) in phi_th.iter_mut().enumerate().take(nth) {
                let da = rot.da[j].transpose() * rg;
                let mut al = rot.g[j] * bp;
                let mut w = rot.g[j] * gp;
                for m in 0..nth {
                    al += rot.dg[j][m] * thdd[m];
                    w += rot.dg[j][m] * thd[m];
                }
                pt[..3].copy_from_slice(da.as_slice());
                pt[3..6].copy_from_slice(al.as_slice());
                pt[6..9].copy_from_slice(w.as_slice());
            }
            Self::add_body_block(
                &mut self.solver,
                &self.coord_slot,
                (o, d, nth, b.nf),
                sc,
                &rot,
                &phi_r,
                &phi_th,
                true,
                s,
            );
        }
        // Residual from the same evaluations (forces were just computed).
        self.residual_from_forces(t, q, v, lam_scaled, lam_factor, r);
        // Force elements.
        let load = self.load_scale;
        for (fe, fw) in self.sys.forces.iter().zip(self.forces.iter_mut()) {
            eval_force(fe, fw, q, v, t, Some(gp), &self.inputs);
            if load != 1.0 && is_applied_load(fe) {
                fw.eval.k.iter_mut().for_each(|x| *x *= load);
            }
            let nl = fw.eval.q.len();
            for i in 0..nl {
                let gi = local_index(&fw.ka, fw.kb.as_ref(), i);
                for j in 0..nl {
                    let gj = local_index(&fw.ka, fw.kb.as_ref(), j);
                    Self::add(
                        &mut self.solver,
                        self.coord_slot[gi],
                        self.coord_slot[gj],
                        s * fw.eval.k[i * nl + j],
                    );
                }
            }
        }
        // Normalizations.
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            let ms = Slot::Border(self.mult_slot[row]);
            for k in 0..4 {
                let cs = self.coord_slot[o + k];
                Self::add(&mut self.solver, cs, cs, lam_scaled[row]);
                Self::add(&mut self.solver, cs, ms, q[o + k]);
                Self::add(&mut self.solver, ms, cs, q[o + k]);
            }
        }
        // Joints: Φ_q and Φ_qᵀ, and the Hessian contracted with λ̃.
        for (c, cw) in self.constraints.iter().zip(self.cons.iter_mut()) {
            let (na, nl) = (cw.ka.len(), cw.ka.len() + cw.kb.len());
            let global = |i: usize| {
                if i < na {
                    cw.ka.idx[i]
                } else {
                    cw.kb.idx[i - na]
                }
            };
            for (k, re) in cw.rows.iter().enumerate() {
                let ms = Slot::Border(self.mult_slot[cw.first + k]);
                for i in 0..nl {
                    let si = self.coord_slot[global(i)];
                    Self::add(&mut self.solver, si, ms, re.grad[i]);
                    Self::add(&mut self.solver, ms, si, re.grad[i]);
                }
            }
            let lam = &lam_scaled[cw.first..cw.first + c.rows.len()];
            if lam.iter().all(|l| *l == 0.0) {
                continue;
            }
            crate::joint::contracted_hessian(
                &c.rows,
                &cw.rows,
                &cw.ka,
                &cw.kb,
                t,
                lam,
                &mut cw.hess,
            );
            for i in 0..nl {
                let si = self.coord_slot[global(i)];
                for j in 0..nl {
                    Self::add(
                        &mut self.solver,
                        si,
                        self.coord_slot[global(j)],
                        cw.hess[i * nl + j],
                    );
                }
            }
        }
    }
}

fn local_index(ka: &MarkerKin, kb: Option<&MarkerKin>, i: usize) -> usize {
    if i < ka.len() {
        ka.idx[i]
    } else {
        kb.expect("second marker").idx[i - ka.len()]
    }
}
