//! The residual `r = [M q̈ − Q + Φ_qᵀ λ; Φ]`: each body's forces from its
//! frame inputs `ā = Aᵀ(R̈ − g)`, `α = Ḡ θ̈`, `ω = Ḡ θ̇`, mapped by `A` and
//! `Ḡᵀ`, then the force elements, the normalizations and the joints.

use super::{v3, Assembly, ForceWork};
use crate::body::{Body, BodyState};
use crate::force::{ForceElement, TorqueLaw};
use crate::rotation::Rotation;
use nalgebra::Vector3;

impl<B: Body> Assembly<'_, B> {
    pub(super) fn body_state<'a>(
        &self,
        i: usize,
        q: &'a [f64],
        v: &'a [f64],
        a: &'a [f64],
    ) -> (BodyState<'a>, Rotation) {
        let b = &self.sys.bodies[i];
        let (o, d, nth) = (b.offset, b.d, b.n_theta);
        let rot = Rotation::new(&q[o + d..o + d + nth]);
        let mut rdd = Vector3::zeros();
        for k in 0..d {
            rdd[k] = a[o + k];
        }
        let abar = rot.a.transpose() * (rdd - self.gravity);
        let alpha = rot.omega(&a[o + d..o + d + nth]);
        let w = rot.omega(&v[o + d..o + d + nth]);
        let f0 = o + d + nth;
        (
            BodyState {
                q_f: &q[f0..f0 + b.nf],
                qd_f: &v[f0..f0 + b.nf],
                qdd_f: &a[f0..f0 + b.nf],
                frame: [
                    abar.x, abar.y, abar.z, alpha.x, alpha.y, alpha.z, w.x, w.y, w.z,
                ],
            },
            rot,
        )
    }

    /// The residual `r = [M q̈ − Q + Φ_qᵀ λ; Φ]` at `(t, q, q̇, q̈, λ)` into
    /// `r` (length `n + m`, coordinates then constraint rows). Rows of
    /// prescribed coordinates hold their reaction forces.
    pub fn residual(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        lam: &[f64],
        r: &mut [f64],
    ) {
        r.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..self.sys.bodies.len() {
            if self.bodies[i].skip {
                continue;
            }
            let (st, rot) = self.body_state(i, q, v, a);
            let b = &self.sys.bodies[i];
            let sc = &mut self.bodies[i];
            b.body
                .forces(&st, sc.frame_rows, &mut sc.work, &mut sc.forces);
            self.add_body_forces(i, || rot, v, r);
        }
        self.add_forces_and_constraints(t, q, v, lam, 1.0, r);
    }

    /// Body `i`'s forces (already in its scratch) into `r`: `A f_r`,
    /// `Ḡᵀ f_θ` (with frame rows; `rot` is called only then), `f_f` and its
    /// Rayleigh damping `D q̇_f`.
    fn add_body_forces(&self, i: usize, rot: impl FnOnce() -> Rotation, v: &[f64], r: &mut [f64]) {
        let b = &self.sys.bodies[i];
        let sc = &self.bodies[i];
        let (o, d, nth) = (b.offset, b.d, b.n_theta);
        let f0 = o + d + nth;
        if sc.frame_rows {
            let rot = rot();
            let fr = rot.a * v3(&sc.forces.f_r);
            for k in 0..d {
                r[o + k] += fr[k];
            }
            let gth = rot.g_t(&v3(&sc.forces.f_th));
            for j in 0..nth {
                r[o + d + j] += gth[j];
            }
        }
        for (k, f) in sc.forces.f_f.iter().enumerate() {
            r[f0 + k] += f;
        }
        if let Some(dm) = &sc.damping {
            dm.mul_add(&v[f0..f0 + b.nf], 1.0, &mut r[f0..f0 + b.nf]);
        }
    }

    /// The force elements (`− Q`), the normalizations `½(eᵀe − 1)` and the
    /// joints' rows `Φ` with their reactions `Φ_qᵀ λ`, `λ = lam · scale`,
    /// into `r`.
    fn add_forces_and_constraints(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam: &[f64],
        scale: f64,
        r: &mut [f64],
    ) {
        let n = self.n;
        let load = self.load_scale;
        for (fe, fw) in self.sys.forces.iter().zip(self.forces.iter_mut()) {
            eval_force(fe, fw, q, v, t, None, &self.inputs);
            if load != 1.0 && is_applied_load(fe) {
                fw.eval.q.iter_mut().for_each(|x| *x *= load);
            }
            let na = fw.ka.len();
            for (i, &g) in fw.ka.idx.iter().enumerate() {
                r[g] -= fw.eval.q[i];
            }
            if let Some(kb) = &fw.kb {
                for (i, &g) in kb.idx.iter().enumerate() {
                    r[g] -= fw.eval.q[na + i];
                }
            }
        }
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            let e = &q[o..o + 4];
            r[n + row] = 0.5 * (e.iter().map(|x| x * x).sum::<f64>() - 1.0);
            for k in 0..4 {
                r[o + k] += e[k] * lam[row] * scale;
            }
        }
        for (c, cw) in self.constraints.iter().zip(self.cons.iter_mut()) {
            cw.ka.eval(&c.a, q);
            cw.kb.eval(&c.b, q);
            for (k, (row, re)) in c.rows.iter().zip(cw.rows.iter_mut()).enumerate() {
                re.eval(row, &cw.ka, &cw.kb, t);
                let l = lam[cw.first + k] * scale;
                r[n + cw.first + k] = re.phi;
                for (i, &g) in cw.ka.idx.iter().chain(&cw.kb.idx).enumerate() {
                    r[g] += re.grad[i] * l;
                }
            }
        }
    }

    /// The residual after [`Body::tangent`] filled the body forces.
    pub(super) fn residual_from_forces(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        lam_scaled: &[f64],
        bp: f64,
        r: &mut [f64],
    ) {
        r.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..self.sys.bodies.len() {
            if self.bodies[i].skip {
                continue;
            }
            let b = &self.sys.bodies[i];
            let (o, d, nth) = (b.offset, b.d, b.n_theta);
            self.add_body_forces(i, || Rotation::new(&q[o + d..o + d + nth]), v, r);
        }
        self.add_forces_and_constraints(t, q, v, lam_scaled, bp, r);
    }
}

/// Whether `fe` is an applied load, which the load factor of a
/// load-stepped static solution scales ([`Assembly::set_load_scale`]): a
/// point force, or a torque of a constant-torque law `τ(t)` (a motor's
/// constant torque). Springs, dampers and PD motors are part of the
/// structure and are not scaled.
pub(super) fn is_applied_load(fe: &ForceElement) -> bool {
    matches!(
        fe,
        ForceElement::Point { .. }
            | ForceElement::Input { .. }
            | ForceElement::Torque {
                law: TorqueLaw::Torque(_) | TorqueLaw::Input(_),
                ..
            }
    )
}

pub(super) fn eval_force(
    fe: &ForceElement,
    fw: &mut ForceWork,
    q: &[f64],
    v: &[f64],
    t: f64,
    gp: Option<f64>,
    inputs: &[f64],
) {
    let (ma, mb) = fe.markers();
    fw.ka.eval(ma, q);
    if let (Some(kb), Some(mb)) = (fw.kb.as_mut(), mb) {
        kb.eval(mb, q);
    }
    let na = fw.ka.len();
    for (i, &g) in fw.ka.idx.iter().enumerate() {
        fw.qd[i] = v[g];
    }
    if let Some(kb) = &fw.kb {
        for (i, &g) in kb.idx.iter().enumerate() {
            fw.qd[na + i] = v[g];
        }
    }
    fw.eval
        .eval(fe, &fw.ka, fw.kb.as_ref(), t, &fw.qd, gp, inputs);
}
