//! The mass system `[M, Φ_qᵀ; Φ_q, 0]` (initial accelerations, explicit
//! integrators) and single diagonal entries of `M` (set-up weights).

use super::{v3, Assembly, Slot};
use crate::body::Body;
use crate::rotation::Rotation;
use nalgebra::Vector3;

impl<B: Body> Assembly<'_, B> {
    /// The mass system `[M, Φ_qᵀ; Φ_q, 0]` at `(t, q)` into the solver
    /// (for initial accelerations and explicit integrators).
    pub fn mass_system(&mut self, t: f64, q: &[f64]) {
        self.solver.clear();
        for i in 0..self.sys.bodies.len() {
            if self.bodies[i].skip {
                continue;
            }
            let b = &self.sys.bodies[i];
            let (o, d, nth, nf) = (b.offset, b.d, b.n_theta, b.nf);
            let rot = Rotation::new(&q[o + d..o + d + nth]);
            let sc = &mut self.bodies[i];
            b.body.mass(
                &q[o + d + nth..o + d + nth + nf],
                &mut sc.work,
                &mut sc.mass,
            );
            // Copy the acceleration blocks into the tangent layout.
            let t_ = &mut sc.tangent;
            t_.clear();
            t_.k_ff.add_scaled(1.0, &sc.mass.m_ff);
            for a in 0..nf {
                t_.d_f_frame[a * 9..a * 9 + 6]
                    .copy_from_slice(&sc.mass.m_f_frame[a * 6..a * 6 + 6]);
            }
            t_.k_ref_f.copy_from_slice(&sc.mass.m_ref_f);
            for r in 0..6 {
                t_.d_ref_frame[r * 9..r * 9 + 6]
                    .copy_from_slice(&sc.mass.m_ref_frame[r * 6..r * 6 + 6]);
            }
            let mut phi_r = [[0.0; 9]; 3];
            for (k, pr) in phi_r.iter_mut().enumerate().take(d) {
                for (c, p) in pr[..3].iter_mut().enumerate() {
                    *p = rot.a[(k, c)];
                }
            }
            let mut phi_th = [[0.0; 9]; 4];
            for (j, pt) in phi_th.iter_mut().enumerate().take(nth) {
                pt[3..6].copy_from_slice(rot.g[j].as_slice());
            }
            Self::add_body_block(
                &mut self.solver,
                &self.coord_slot,
                (o, d, nth, nf),
                sc,
                &rot,
                &phi_r,
                &phi_th,
                false,
                1.0,
            );
        }
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            let ms = Slot::Border(self.mult_slot[row]);
            for k in 0..4 {
                let cs = self.coord_slot[o + k];
                Self::add(&mut self.solver, cs, ms, q[o + k]);
                Self::add(&mut self.solver, ms, cs, q[o + k]);
            }
        }
        for (c, cw) in self.constraints.iter().zip(self.cons.iter_mut()) {
            cw.ka.eval(&c.a, q);
            cw.kb.eval(&c.b, q);
            let nl = cw.ka.len() + cw.kb.len();
            for (k, (row, re)) in c.rows.iter().zip(cw.rows.iter_mut()).enumerate() {
                re.eval(row, &cw.ka, &cw.kb, t);
                let ms = Slot::Border(self.mult_slot[cw.first + k]);
                for i in 0..nl {
                    let gi = if i < cw.ka.len() {
                        cw.ka.idx[i]
                    } else {
                        cw.kb.idx[i - cw.ka.len()]
                    };
                    let si = self.coord_slot[gi];
                    Self::add(&mut self.solver, si, ms, re.grad[i]);
                    Self::add(&mut self.solver, ms, si, re.grad[i]);
                }
            }
        }
    }

    /// The diagonal entries `M_cc` of the mass matrix at `q` for the
    /// coordinates `coords` (twice the kinetic energy at the unit velocity
    /// of each), for weighting set-up projections.
    pub fn mass_diagonal(&mut self, q: &[f64], coords: &[usize]) -> Vec<f64> {
        let mut out = vec![0.0; coords.len()];
        for i in 0..self.sys.bodies.len() {
            let b = &self.sys.bodies[i];
            let (o, d, nth, nf) = (b.offset, b.d, b.n_theta, b.nf);
            let f0 = o + d + nth;
            let mine: Vec<usize> = (0..coords.len())
                .filter(|&k| (o..f0 + nf).contains(&coords[k]))
                .collect();
            if mine.is_empty() {
                continue;
            }
            let rot = Rotation::new(&q[o + d..f0]);
            let sc = &mut self.bodies[i];
            b.body.mass(&q[f0..f0 + nf], &mut sc.work, &mut sc.mass);
            for k in mine {
                let c = coords[k] - o;
                let mut rd = Vector3::zeros();
                let mut th = [0.0; 4];
                let mut vf = vec![0.0; nf];
                if c < d {
                    rd[c] = 1.0;
                } else if c < d + nth {
                    th[c - d] = 1.0;
                } else {
                    vf[c - d - nth] = 1.0;
                }
                let vb = rot.a.transpose() * rd;
                let w = rot.omega(&th[..nth]);
                let (h, mf) = sc.mass.momenta(&[vb.x, vb.y, vb.z], &[w.x, w.y, w.z], &vf);
                let mut t = vb.dot(&v3(&h[0..3])) + w.dot(&v3(&h[3..6]));
                for a in 0..nf {
                    t += vf[a] * mf[a];
                }
                out[k] = t;
            }
        }
        out
    }
}
