//! The equations of motion of one body in FFR coordinates
//! `q = [R (d); θ (1 or 4); q_f]`, `d = 2` in a planar scene, 3 in space.
//!
//! Everything is computed from the cached [`Invariants`] and
//! [`FlexBody::inertia_terms`] (theory sheet, "Mass matrix" and
//! "Velocity-dependent inertia").

use crate::body::{FlexBody, InertiaTerms, Invariants, MassBlocks};
use crate::error::{Error, Result};
use crate::rotation::{rotation_and_g, skew};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3xX, Vector3};

/// Rayleigh damping `D = α M_ff + β K_ff` on the elastic coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Rayleigh {
    /// Mass-proportional coefficient `α` (1/s).
    pub alpha: f64,
    /// Stiffness-proportional coefficient `β` (s).
    pub beta: f64,
}

/// A body in a scene of dimension `d`, with its invariants cached.
pub struct BodyModel {
    body: Box<dyn FlexBody>,
    inv: Invariants,
    d: usize,
    nth: usize,
    nf: usize,
    /// Include `∂U_nl/∂q_f` (only if the body [`FlexBody::has_stiffening`]).
    pub stiffening: bool,
    /// Optional Rayleigh damping of the elastic coordinates.
    pub damping: Option<Rayleigh>,
}

/// The rigid-frame kinematics of a body at one configuration.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Frame origin `R` (global, z = 0 in the plane).
    pub r: Vector3<f64>,
    /// Rotation matrix `A`.
    pub a: Matrix3<f64>,
    /// `Ḡ` (3 × n_θ).
    pub g: Matrix3xX<f64>,
}

fn check_finite(what: &str, x: impl IntoIterator<Item = f64>, body: usize) -> Result<()> {
    if x.into_iter().all(f64::is_finite) {
        Ok(())
    } else {
        Err(Error::InvalidBody {
            body,
            reason: format!("{what} has non-finite entries"),
        })
    }
}

impl BodyModel {
    /// Wrap `body` for a scene of dimension `scene_dim` (2 or 3), evaluating
    /// and checking its invariants once. `index` only labels errors.
    pub fn new(body: Box<dyn FlexBody>, scene_dim: usize, index: usize) -> Result<Self> {
        let inv = body.invariants();
        let nf = body.nf();
        let bad = |reason: String| Error::InvalidBody {
            body: index,
            reason,
        };
        if scene_dim != 2 && scene_dim != 3 {
            return Err(Error::InvalidInput(format!(
                "scene dimension {scene_dim} is not 2 or 3"
            )));
        }
        if inv.dim != body.dim() || (inv.dim != 2 && inv.dim != 3) {
            return Err(bad(format!(
                "dimension {} (invariants say {})",
                body.dim(),
                inv.dim
            )));
        }
        if inv.dim > scene_dim {
            return Err(bad("a spatial body cannot be used in a planar scene".into()));
        }
        if inv.nf() != nf || inv.k_ff.shape() != (nf, nf) || inv.s_bar.ncols() != nf {
            return Err(bad(format!("invariant sizes do not match n_f = {nf}")));
        }
        for k in 0..3 {
            for l in 0..3 {
                if inv.s_kl[k][l].shape() != (nf, nf) || inv.i_kl[k][l].len() != nf {
                    return Err(bad(format!(
                        "S_kl / I_kl ({k},{l}) sizes do not match n_f = {nf}"
                    )));
                }
                check_finite("S_kl", inv.s_kl[k][l].iter().copied(), index)?;
                check_finite("I_kl", inv.i_kl[k][l].iter().copied(), index)?;
            }
        }
        check_finite("s_bar", inv.s_bar.iter().copied(), index)?;
        check_finite("m_ff", inv.m_ff.iter().copied(), index)?;
        check_finite("k_ff", inv.k_ff.iter().copied(), index)?;
        check_finite("theta", inv.theta.iter().copied(), index)?;
        check_finite("s_t0", inv.s_t0.iter().copied(), index)?;
        if !(inv.mass > 0.0 && inv.mass.is_finite()) {
            return Err(bad(format!("mass {} is not positive", inv.mass)));
        }
        let stiffening = body.has_stiffening();
        Ok(Self {
            body,
            inv,
            d: scene_dim,
            nth: if scene_dim == 2 { 1 } else { 4 },
            nf,
            stiffening,
            damping: None,
        })
    }

    /// The wrapped body.
    pub fn body(&self) -> &dyn FlexBody {
        self.body.as_ref()
    }
    /// The cached invariants.
    pub fn invariants(&self) -> &Invariants {
        &self.inv
    }
    /// Scene dimension `d`.
    pub fn dim(&self) -> usize {
        self.d
    }
    /// Number of rotational coordinates (1 or 4).
    pub fn n_theta(&self) -> usize {
        self.nth
    }
    /// Number of elastic coordinates.
    pub fn nf(&self) -> usize {
        self.nf
    }
    /// Number of body coordinates `d + n_θ + n_f`.
    pub fn n_coords(&self) -> usize {
        self.d + self.nth + self.nf
    }
    /// Index of the first elastic coordinate in the body's coordinates.
    pub fn f_offset(&self) -> usize {
        self.d + self.nth
    }

    /// `R`, `A`, `Ḡ` at body coordinates `q`.
    pub fn frame(&self, q: &[f64]) -> Frame {
        let mut r = Vector3::zeros();
        r.as_mut_slice()[..self.d].copy_from_slice(&q[..self.d]);
        let (a, g) = rotation_and_g(&q[self.d..self.d + self.nth]);
        Frame { r, a, g }
    }

    /// `S_t`, `Ī_θθ`, `Ī_θf` at `q_f`.
    pub fn inertia_terms(&self, q_f: &[f64]) -> InertiaTerms {
        let mut t = InertiaTerms::zeros(self.nf);
        self.body.inertia_terms(q_f, &mut t);
        t
    }

    fn split<'a>(&self, q: &'a [f64]) -> (&'a [f64], &'a [f64]) {
        (&q[self.d..self.d + self.nth], &q[self.f_offset()..])
    }

    /// The body mass matrix from the theory-sheet blocks:
    /// `m_RR = m I`, `m_Rθ = −A S̃_t Ḡ`, `m_Rf = A S̄`, `m_θθ = Ḡᵀ Ī_θθ Ḡ`,
    /// `m_θf = Ḡᵀ Ī_θf`, `m_ff` (R rows restricted to the scene's `d` axes).
    pub fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        let (d, nth, nf) = (self.d, self.nth, self.nf);
        let fr = self.frame(q);
        let t = self.inertia_terms(self.split(q).1);
        let n = self.n_coords();
        let mut m = DMatrix::zeros(n, n);
        for i in 0..d {
            m[(i, i)] = self.inv.mass;
        }
        let b = MassBlocks::new(&self.inv, &t, &fr.a, &fr.g);
        let (m_rth, m_rf, m_thth, m_thf) = (b.m_r_theta, b.m_rf, b.m_theta_theta, b.m_theta_f);
        for i in 0..d {
            for j in 0..nth {
                m[(i, d + j)] = m_rth[(i, j)];
                m[(d + j, i)] = m_rth[(i, j)];
            }
            for j in 0..nf {
                m[(i, d + nth + j)] = m_rf[(i, j)];
                m[(d + nth + j, i)] = m_rf[(i, j)];
            }
        }
        m.view_mut((d, d), (nth, nth)).copy_from(&m_thth);
        m.view_mut((d, d + nth), (nth, nf)).copy_from(&m_thf);
        m.view_mut((d + nth, d), (nf, nth))
            .copy_from(&m_thf.transpose());
        m.view_mut((d + nth, d + nth), (nf, nf))
            .copy_from(&self.inv.m_ff);
        m
    }

    /// The quadratic velocity vector `Q_v(q, q̇) = −∫ρ Lᵀ (A ω̃² ū + 2 A ω̃ S q̇_f) dV`
    /// (d'Alembert form of `−Ṁq̇ + ∂T/∂q`, using `Ḡ̇θ̇ = 0`), in invariants:
    ///
    /// - `(Q_v)_R = −A (ω̃² S_t + 2 ω̃ S̄ q̇_f)`
    /// - `(Q_v)_θ = −Ḡᵀ (ω̃ Ī_θθ ω̄ + 2 (tr P · ω̄ − Pᵀ ω̄))`, `P_kl = ∫ρ u_k S_l q̇_f dV = Ī_kl q̇_f + q_fᵀ S̄_kl q̇_f`
    /// - `(Q_v)_f = −Σ_kl [ (ω̃²)_kl (Ī_lk + S̄_kl q_f) + 2 ω̃_kl S̄_kl q̇_f ]`
    pub fn quadratic_velocity(&self, q: &[f64], qd: &[f64]) -> DVector<f64> {
        let (d, nth, nf) = (self.d, self.nth, self.nf);
        let fr = self.frame(q);
        let (_, qf) = self.split(q);
        let (thd, qfd) = self.split(qd);
        let t = self.inertia_terms(qf);
        let qf = DVector::from_column_slice(qf);
        let qfd = DVector::from_column_slice(qfd);
        let w: Vector3<f64> = &fr.g * DVector::from_column_slice(thd);
        let wt = skew(&w);
        let wt2 = wt * wt;
        let inv = &self.inv;
        let mut out = DVector::zeros(self.n_coords());

        let qr = -(fr.a * (wt2 * t.s_t + wt * (&inv.s_bar * &qfd) * 2.0));
        out.rows_mut(0, d).copy_from(&qr.rows(0, d));

        let mut p = Matrix3::zeros();
        let mut qf_part = DVector::zeros(nf);
        if nf > 0 {
            for k in 0..3 {
                for l in 0..3 {
                    let skl = &inv.s_kl[k][l];
                    let skl_qd = skl * &qfd;
                    p[(k, l)] = inv.i_kl[k][l].dot(&qfd) + qf.dot(&skl_qd);
                    if wt2[(k, l)] != 0.0 {
                        qf_part += (&inv.i_kl[l][k] + skl * &qf) * wt2[(k, l)];
                    }
                    if wt[(k, l)] != 0.0 {
                        qf_part += skl_qd * (2.0 * wt[(k, l)]);
                    }
                }
            }
        }
        let h = w.cross(&(t.i_theta_theta * w)) + (w * p.trace() - p.transpose() * w) * 2.0;
        let qth = -(fr.g.transpose() * h);
        out.rows_mut(d, nth).copy_from(&qth);
        out.rows_mut(d + nth, nf).copy_from(&(-qf_part));
        out
    }

    /// Applied forces on the body alone: gravity `g` (global)
    /// `Q_R = m g`, `Q_θ = Ḡᵀ S̃_t Aᵀ g`, `Q_f = S̄ᵀ Aᵀ g`; elastic
    /// `−K_ff q_f − ∂U_nl/∂q_f`; Rayleigh damping `−(α M_ff + β K_ff) q̇_f`.
    pub fn applied_forces(&self, q: &[f64], qd: &[f64], gravity: &Vector3<f64>) -> DVector<f64> {
        let (d, nth, nf) = (self.d, self.nth, self.nf);
        let mut out = DVector::zeros(self.n_coords());
        let (_, qf) = self.split(q);
        if gravity.norm_squared() > 0.0 {
            let fr = self.frame(q);
            let t = self.inertia_terms(qf);
            let gb = fr.a.transpose() * gravity;
            let fr_g = gravity * self.inv.mass;
            out.rows_mut(0, d).copy_from(&fr_g.rows(0, d));
            out.rows_mut(d, nth)
                .copy_from(&(fr.g.transpose() * (skew(&t.s_t) * gb)));
            out.rows_mut(d + nth, nf)
                .copy_from(&(self.inv.s_bar.transpose() * gb));
        }
        if nf > 0 {
            let qfv = DVector::from_column_slice(qf);
            let mut fe = -(&self.inv.k_ff * &qfv);
            if self.stiffening {
                let mut nl = vec![0.0; nf];
                self.body.stiffening(qf, &mut nl, None);
                fe -= DVector::from_vec(nl);
            }
            if let Some(r) = self.damping {
                let qfd = DVector::from_column_slice(&qd[d + nth..]);
                fe -= (&self.inv.m_ff * &qfd) * r.alpha + (&self.inv.k_ff * &qfd) * r.beta;
            }
            let mut v = out.rows_mut(d + nth, nf);
            v += fe;
        }
        out
    }

    /// Kinetic energy `T = ½ q̇ᵀ M q̇`.
    pub fn kinetic_energy(&self, q: &[f64], qd: &[f64]) -> f64 {
        let v = DVector::from_column_slice(qd);
        0.5 * v.dot(&(self.mass_matrix(q) * &v))
    }

    /// Elastic energy `½ q_fᵀ K_ff q_f + U_nl(q_f)` (`U_nl` only with stiffening on).
    pub fn elastic_energy(&self, q: &[f64]) -> f64 {
        let qf = self.split(q).1;
        let v = DVector::from_column_slice(qf);
        let mut e = 0.5 * v.dot(&(&self.inv.k_ff * &v));
        if self.stiffening && self.nf > 0 {
            e += self.body.stiffening_energy(qf);
        }
        e
    }

    /// Gravitational potential `V = −g · (m R + A S_t)`.
    pub fn gravity_energy(&self, q: &[f64], gravity: &Vector3<f64>) -> f64 {
        let fr = self.frame(q);
        let t = self.inertia_terms(self.split(q).1);
        -gravity.dot(&(fr.r * self.inv.mass + fr.a * t.s_t))
    }

    /// Linear momentum `p = ∫ρ ṙ dV = m Ṙ − A S̃_t ω̄ + A S̄ q̇_f` and angular
    /// momentum about the global origin `H = R × p + A (S̃_t Aᵀ Ṙ + Ī_θθ ω̄ + Ī_θf q̇_f)`.
    pub fn momentum(&self, q: &[f64], qd: &[f64]) -> (Vector3<f64>, Vector3<f64>) {
        let fr = self.frame(q);
        let (thd, qfd) = self.split(qd);
        let t = self.inertia_terms(self.split(q).1);
        let mut rd = Vector3::zeros();
        rd.as_mut_slice()[..self.d].copy_from_slice(&qd[..self.d]);
        let w: Vector3<f64> = &fr.g * DVector::from_column_slice(thd);
        let qfd = DVector::from_column_slice(qfd);
        let p = rd * self.inv.mass - fr.a * t.s_t.cross(&w) + fr.a * (&self.inv.s_bar * &qfd);
        let h = fr.r.cross(&p)
            + fr.a
                * (t.s_t.cross(&(fr.a.transpose() * rd))
                    + t.i_theta_theta * w
                    + &t.i_theta_f * &qfd);
        (p, h)
    }
}
