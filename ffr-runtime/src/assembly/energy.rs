//! Monitored quantities: energies, rates of work of the force elements and
//! the damping, linear and angular momentum.

use super::residual::eval_force;
use super::{v3, Assembly};
use crate::body::Body;
use crate::force::{ForceElement, TorqueLaw};
use crate::rotation::Rotation;
use nalgebra::Vector3;

impl<B: Body> Assembly<'_, B> {
    /// Kinetic, elastic, gravitational and spring energy at `(q, q̇)`.
    pub fn energy(&mut self, q: &[f64], v: &[f64]) -> crate::Energy {
        let mut e = crate::Energy::default();
        for i in 0..self.sys.bodies.len() {
            let b = &self.sys.bodies[i];
            let (o, d, nth, nf) = (b.offset, b.d, b.n_theta, b.nf);
            let f0 = o + d + nth;
            let rot = Rotation::new(&q[o + d..f0]);
            let sc = &mut self.bodies[i];
            b.body.mass(&q[f0..f0 + nf], &mut sc.work, &mut sc.mass);
            let mut rd = Vector3::zeros();
            let mut r = Vector3::zeros();
            for k in 0..d {
                rd[k] = v[o + k];
                r[k] = q[o + k];
            }
            let vb = rot.a.transpose() * rd;
            let w = rot.omega(&v[o + d..f0]);
            let h = sc.mass.momenta_into(
                &[vb.x, vb.y, vb.z],
                &[w.x, w.y, w.z],
                &v[f0..f0 + nf],
                &mut sc.vf,
            );
            let mut t = vb.dot(&v3(&h[0..3])) + w.dot(&v3(&h[3..6]));
            for k in 0..nf {
                t += v[f0 + k] * sc.vf[k];
            }
            e.kinetic += 0.5 * t;
            e.elastic += b.body.elastic_energy(&q[f0..f0 + nf], &mut sc.work);
            let st = v3(&sc.mass.s_t);
            e.gravity -= self.sys.gravity.dot(&(r * sc.mass.mass() + rot.a * st));
        }
        for (fe, fw) in self.sys.forces.iter().zip(self.forces.iter_mut()) {
            if matches!(
                fe,
                ForceElement::SpringDamper { .. } | ForceElement::Torque { .. }
            ) {
                eval_force(fe, fw, q, v, 0.0, None, &self.inputs);
                e.springs += fw.eval.energy;
            }
        }
        e
    }

    /// Rates of work of the force elements and of the damping at `(t, q, q̇)`
    /// ([`crate::Power`]).
    pub fn power(&mut self, t: f64, q: &[f64], v: &[f64]) -> crate::Power {
        let mut p = crate::Power::default();
        for (b, sc) in self.sys.bodies.iter().zip(self.bodies.iter_mut()) {
            if let Some(dm) = &sc.damping {
                let f0 = b.offset + b.d + b.n_theta;
                let vf = &v[f0..f0 + b.nf];
                sc.vf.iter_mut().for_each(|x| *x = 0.0);
                dm.mul_add(vf, 1.0, &mut sc.vf);
                p.dissipated += vf.iter().zip(&sc.vf).map(|(a, b)| a * b).sum::<f64>();
            }
        }
        for (fe, fw) in self.sys.forces.iter().zip(self.forces.iter_mut()) {
            eval_force(fe, fw, q, v, t, None, &self.inputs);
            let rate = fw.eval.rate;
            match fe {
                ForceElement::Point { .. }
                | ForceElement::Input { .. }
                | ForceElement::Torque {
                    law: TorqueLaw::Torque(_) | TorqueLaw::Input(_) | TorqueLaw::Pd { .. },
                    ..
                } => {
                    p.applied += fw
                        .eval
                        .q
                        .iter()
                        .zip(&fw.qd)
                        .map(|(a, b)| a * b)
                        .sum::<f64>();
                }
                ForceElement::Torque {
                    law: TorqueLaw::SpringDamper { damping, .. },
                    ..
                }
                | ForceElement::SpringDamper { damping, .. } => {
                    p.dissipated += damping * rate * rate;
                }
            }
        }
        p
    }

    /// Total linear momentum and angular momentum about the global origin.
    pub fn momentum(&mut self, q: &[f64], v: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
        let (mut p, mut hh) = (Vector3::zeros(), Vector3::zeros());
        for i in 0..self.sys.bodies.len() {
            let b = &self.sys.bodies[i];
            let (o, d, nth, nf) = (b.offset, b.d, b.n_theta, b.nf);
            let f0 = o + d + nth;
            let rot = Rotation::new(&q[o + d..f0]);
            let sc = &mut self.bodies[i];
            b.body.mass(&q[f0..f0 + nf], &mut sc.work, &mut sc.mass);
            let mut rd = Vector3::zeros();
            let mut r = Vector3::zeros();
            for k in 0..d {
                rd[k] = v[o + k];
                r[k] = q[o + k];
            }
            let vb = rot.a.transpose() * rd;
            let w = rot.omega(&v[o + d..f0]);
            let (h, _) = sc
                .mass
                .momenta(&[vb.x, vb.y, vb.z], &[w.x, w.y, w.z], &v[f0..f0 + nf]);
            let pb = rot.a * v3(&h[0..3]);
            p += pb;
            hh += r.cross(&pb) + rot.a * v3(&h[3..6]);
        }
        (p, hh)
    }
}
