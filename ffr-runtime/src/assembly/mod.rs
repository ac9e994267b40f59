//! The equations of a system in the structure of its solver: residual,
//! analytic iteration matrix, mass system, energies and momenta, all in
//! preallocated storage (nothing allocates after [`Assembly::new`]).
//!
//! Unknowns are the coordinates that are not prescribed and one multiplier
//! per constraint row. Each flexible body's elastic coordinates form a band
//! block unless a marker of a joint or force element uses them; everything
//! else — frame coordinates, those marker coordinates, rigid bodies,
//! multipliers — is the border of [`BorderedSystem`], which solves by block
//! elimination (banded LU per body, dense Schur complement on the border), so
//! the cost grows linearly with the number of elements.
//!
//! Body residual (theory: `docs/theory.md`): `r_R = A f_r`, `r_θ = Ḡᵀ f_θ`,
//! `r_f = f_f + D q̇_f` with the body-frame forces at `ā = Aᵀ(R̈ − g)`,
//! `α = Ḡ θ̈`, `ω = Ḡ θ̇`; then `− Q_ext + Φ_qᵀ λ`. The iteration matrix is
//! the exact derivative with `∂q̈/∂q = β'`, `∂q̇/∂q = γ'`, through `A(θ)`,
//! `Ḡ(θ)` and the kernels' derivatives.

use crate::body::{BandBuf, Body, BodyForces, BodyMass, BodyState, BodyTangent, BodyWork};
use crate::error::{Error, Result};
use crate::force::{ForceElement, ForceEval, TorqueLaw};
use crate::joint::RowEval;
use crate::linalg::{BlockShape, BorderedSystem};
use crate::marker::MarkerKin;
use crate::rotation::Rotation;
use crate::system::System;
use nalgebra::Vector3;

/// The most entries of the dense border matrix (frame coordinates, joint
/// rows and marker coordinates of every body, squared) a system may need:
/// 2²⁶, 512 MiB, about 8000 border unknowns.
pub const MAX_BORDER_ENTRIES: usize = 1 << 26;

/// Where an unknown lives in the solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Slot {
    /// Band block `b`, local index.
    Band(u32, u32),
    /// Border index.
    Border(u32),
    /// Prescribed (not an unknown).
    Fixed,
}

struct ConsWork {
    ka: MarkerKin,
    kb: MarkerKin,
    rows: Vec<RowEval>,
    /// First multiplier index of this constraint.
    first: usize,
    qd: Vec<f64>,
}

struct ForceWork {
    ka: MarkerKin,
    kb: Option<MarkerKin>,
    eval: ForceEval,
    qd: Vec<f64>,
}

/// Per-body scratch.
struct BodyScratch {
    work: BodyWork,
    forces: BodyForces,
    tangent: BodyTangent,
    mass: BodyMass,
    /// `α m_ff + β K_ff`, if damped.
    damping: Option<BandBuf>,
    /// Evaluate the reference rows (some frame coordinate is free).
    frame_rows: bool,
    /// Skip the body entirely (every coordinate prescribed).
    skip: bool,
    /// Scratch of length `n_f` (momenta, damping power).
    vf: Vec<f64>,
}

/// The assembled equations of a [`System`].
pub struct Assembly<'s, B: Body> {
    pub(crate) sys: &'s System<B>,
    /// Coordinates.
    pub n: usize,
    /// Constraint rows (Euler normalizations first, then the joints').
    pub m: usize,
    pub(crate) coord_slot: Vec<Slot>,
    pub(crate) mult_slot: Vec<u32>,
    /// Prescribed coordinate → index into `sys.prescribed`.
    presc: Vec<Option<usize>>,
    /// Bodies with an Euler-parameter normalization row, and its row.
    norm_rows: Vec<(usize, usize)>,
    bodies: Vec<BodyScratch>,
    cons: Vec<ConsWork>,
    forces: Vec<ForceWork>,
    pub(crate) solver: BorderedSystem,
    x_band: Vec<f64>,
    x_border: Vec<f64>,
    /// Class of each multiplier (for convergence scales).
    pub(crate) mult_class: Vec<u32>,
    /// Class of each coordinate.
    pub(crate) coord_class: Vec<u32>,
    /// Per class: the class of the same body whose positions, times the
    /// factor, also set this class's round-off floor (a beam's elastic
    /// translations and rotations, linked by its length `L`).
    pub(crate) class_link: Vec<Option<(u32, f64)>>,
}

fn v3(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

impl<'s, B: Body> Assembly<'s, B> {
    /// Analyse the structure of `sys` and allocate everything.
    pub fn new(sys: &'s System<B>) -> Result<Self> {
        let n = sys.n_coords();
        let mut presc = vec![None; n];
        for (k, (c, _)) in sys.prescribed.iter().enumerate() {
            presc[*c] = Some(k);
        }
        // Constraint rows: normalizations of spatial bodies whose Euler
        // parameters are not all prescribed, then the joints'.
        let mut norm_rows = Vec::new();
        let mut m = 0;
        if sys.dim == 3 {
            for (i, b) in sys.bodies.iter().enumerate() {
                let e = b.offset + 3;
                if (e..e + 4).any(|c| presc[c].is_none()) {
                    norm_rows.push((i, m));
                    m += 1;
                }
            }
        }
        let n_norm = m;
        m += sys.constraints.iter().map(|c| c.rows.len()).sum::<usize>();

        // Elastic coordinates used by markers of joints and force elements go
        // to the border.
        let mut touched = vec![false; n];
        let mut cons = Vec::new();
        let mut first = n_norm;
        for c in &sys.constraints {
            let ka = kin(sys, &c.a);
            let kb = kin(sys, &c.b);
            for &g in ka.idx.iter().chain(&kb.idx) {
                touched[g] = true;
            }
            let nl = ka.len() + kb.len();
            cons.push(ConsWork {
                rows: c.rows.iter().map(|_| RowEval::new(nl)).collect(),
                ka,
                kb,
                first,
                qd: vec![0.0; nl],
            });
            first += c.rows.len();
        }
        let mut forces = Vec::new();
        for f in &sys.forces {
            let (ma, mb) = f.markers();
            let ka = kin(sys, ma);
            let kb = mb.map(|m| kin(sys, m));
            let nl = ka.len() + kb.as_ref().map_or(0, |k| k.len());
            for &g in ka.idx.iter().chain(kb.iter().flat_map(|k| k.idx.iter())) {
                touched[g] = true;
            }
            forces.push(ForceWork {
                ka,
                kb,
                eval: ForceEval::new(nl),
                qd: vec![0.0; nl],
            });
        }

        // Slots.
        let mut coord_slot = vec![Slot::Fixed; n];
        let mut blocks = Vec::new();
        let mut n_border = 0u32;
        let mut body_border: Vec<Vec<usize>> = Vec::new();
        let mut bodies = Vec::new();
        let mut coord_class = vec![0u32; n];
        let mut n_classes = 0u32;
        let mut class_link = Vec::new();
        for (i, b) in sys.bodies.iter().enumerate() {
            let lay = b.body.layout();
            let o = b.offset;
            let nfr = b.d + b.n_theta;
            let frame_free = (o..o + nfr).any(|c| presc[c].is_none());
            if lay.zero_frame_acceleration {
                let held = (o..o + b.d)
                    .all(|c| presc[c].is_some_and(|k| sys.prescribed[k].1.is_uniform()));
                if sys.gravity != Vector3::zeros() || !held {
                    return Err(Error::InvalidInput(format!(
                        "body `{}` ({}) was generated for a frame origin without acceleration and no gravity (ā ≡ 0), but {}: generate it without `zero_frame_acceleration`",
                        b.name,
                        lay.description,
                        if sys.gravity != Vector3::zeros() {
                            "the scene has gravity"
                        } else {
                            "its frame origin is not held by constant or uniform prescribed coordinates"
                        }
                    )));
                }
            }
            if frame_free && b.nf > 0 && !lay.free_frame {
                return Err(Error::InvalidInput(format!(
                    "body `{}` ({}) was generated for prescribed frame motion, but its frame coordinates are not all prescribed: generate it with a free frame",
                    b.name, lay.description
                )));
            }
            if frame_free && b.nf > 0 {
                let frame_marker = sys
                    .constraints
                    .iter()
                    .flat_map(|c| [&c.a, &c.b])
                    .any(|m| m.body.map(|x| x.0) == Some(i) && m.shape.entries.is_empty());
                if !frame_marker {
                    if let Some(what) = rigid_motion_in_elastic(b, &presc) {
                        return Err(Error::InvalidBody {
                            body: i,
                            reason: format!(
                                "`{}` ({}): its elastic coordinates include the rigid-body motion {what} of its frame, which is not prescribed, so the mass matrix is singular; use a `clamped` or `pinned` reference condition, or prescribe the frame (e.g. ground the body)",
                                b.name, lay.description
                            ),
                        });
                    }
                }
            }
            // Classes: frame translations, frame rotations, elastic
            // translations, elastic rotations.
            let base = n_classes;
            n_classes += 4;
            match lay.length {
                Some(l) if l > 0.0 && l.is_finite() && b.nf > 0 => {
                    class_link.extend([None, None, Some((base + 3, l)), Some((base + 2, 1.0 / l))])
                }
                _ => class_link.extend([None; 4]),
            }
            for k in 0..nfr {
                coord_class[o + k] = base + u32::from(k >= b.d);
            }
            for (j, l) in lay.labels.iter().enumerate() {
                coord_class[o + nfr + j] = base + 2 + u32::from(l.starts_with('r'));
            }
            let mut border = Vec::new();
            for c in o..o + nfr {
                if presc[c].is_none() {
                    coord_slot[c] = Slot::Border(n_border);
                    border.push(n_border as usize);
                    n_border += 1;
                }
            }
            let mut band = 0u32;
            let blk = blocks.len() as u32;
            for c in o + nfr..o + nfr + b.nf {
                if presc[c].is_some() {
                    continue;
                }
                if touched[c] {
                    coord_slot[c] = Slot::Border(n_border);
                    border.push(n_border as usize);
                    n_border += 1;
                } else {
                    coord_slot[c] = Slot::Band(blk, band);
                    band += 1;
                }
            }
            if band > 0 {
                blocks.push((band as usize, lay.half_bandwidth));
                body_border.push(border);
            }
            let own = b.body.damping();
            if let Some(d) = &own {
                if (d.n(), d.half_bandwidth()) != (b.nf, lay.half_bandwidth) {
                    return Err(Error::InvalidBody {
                        body: i,
                        reason: format!(
                            "its damping matrix is {}×{} with half-bandwidth {}, its elastic blocks {}×{} with {}",
                            d.n(),
                            d.n(),
                            d.half_bandwidth(),
                            b.nf,
                            b.nf,
                            lay.half_bandwidth
                        ),
                    });
                }
            }
            let rayleigh = b.damping.map(|r| {
                let mut work = b.body.work();
                let mut mass = BodyMass::zeros(b.nf, lay.half_bandwidth);
                let zeros = vec![0.0; b.nf];
                b.body.mass(&zeros, &mut work, &mut mass);
                let mut f = BodyForces::zeros(b.nf);
                let mut t = BodyTangent::zeros(b.nf, lay.half_bandwidth);
                let st = BodyState {
                    q_f: &zeros,
                    qd_f: &zeros,
                    qdd_f: &zeros,
                    frame: [0.0; 9],
                };
                b.body
                    .tangent(&st, 0.0, 0.0, false, &mut work, &mut f, &mut t);
                let mut d = BandBuf::zeros(b.nf, lay.half_bandwidth);
                d.add_scaled(r.alpha, &mass.m_ff);
                d.add_scaled(r.beta, &t.k_ff);
                d
            });
            // D = the body's own damping + α m_ff + β K_ff.
            let damping = match (own, rayleigh) {
                (Some(mut d), Some(r)) => {
                    d.add_scaled(1.0, &r);
                    Some(d)
                }
                (d, r) => d.or(r),
            };
            let all_fixed = (o..o + b.n_coords()).all(|c| presc[c].is_some());
            bodies.push(BodyScratch {
                work: b.body.work(),
                forces: BodyForces::zeros(b.nf),
                tangent: BodyTangent::zeros(b.nf, lay.half_bandwidth),
                mass: BodyMass::zeros(b.nf, lay.half_bandwidth),
                damping,
                frame_rows: frame_free,
                skip: all_fixed,
                vf: vec![0.0; b.nf],
            });
        }
        let mut mult_slot = Vec::with_capacity(m);
        let mut mult_class = Vec::with_capacity(m);
        for _ in 0..n_norm {
            mult_slot.push(n_border);
            mult_class.push(n_classes);
            n_border += 1;
        }
        if n_norm > 0 {
            n_classes += 1;
        }
        for c in &sys.constraints {
            for _ in &c.rows {
                mult_slot.push(n_border);
                mult_class.push(n_classes);
                n_border += 1;
            }
            n_classes += 1;
        }
        class_link.resize(n_classes as usize, None);
        // The border's Schur complement is dense: bound it before allocating.
        let nb = n_border as usize;
        if nb.saturating_mul(nb) > MAX_BORDER_ENTRIES {
            return Err(Error::InvalidInput(format!(
                "the system has {nb} border unknowns (frame coordinates, joint rows and the elastic coordinates at markers), whose dense Schur complement would need {:.1} GiB: more than the limit of {MAX_BORDER_ENTRIES} entries (MAX_BORDER_ENTRIES); use fewer bodies or joints",
                (nb as f64).powi(2) * 8.0 / (1u64 << 30) as f64
            )));
        }
        let shapes: Vec<BlockShape> = blocks
            .iter()
            .zip(&body_border)
            .map(|(&(nb, hb), border)| BlockShape {
                n: nb,
                kl: hb,
                ku: hb,
                border: border.clone(),
            })
            .collect();
        let solver = BorderedSystem::new(&shapes, n_border as usize);
        let nb_total: usize = blocks.iter().map(|b| b.0).sum();
        Ok(Self {
            sys,
            n,
            m,
            coord_slot,
            mult_slot,
            presc,
            norm_rows,
            bodies,
            cons,
            forces,
            solver,
            x_band: vec![0.0; nb_total],
            x_border: vec![0.0; n_border as usize],
            mult_class,
            coord_class,
            class_link,
        })
    }

    /// Whether coordinate `c` is prescribed.
    pub fn is_prescribed(&self, c: usize) -> bool {
        self.presc[c].is_some()
    }

    /// Set the prescribed coordinates, their rates and accelerations at `t`.
    pub fn apply_prescribed(&self, t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        for (c, d) in &self.sys.prescribed {
            let [f, fd, fdd] = d.eval(t);
            q[*c] = f;
            v[*c] = fd;
            a[*c] = fdd;
        }
    }

    /// Number of unknowns (free coordinates and multipliers).
    pub fn n_unknowns(&self) -> usize {
        self.x_band.len() + self.x_border.len()
    }

    fn body_state<'a>(
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
        let abar = rot.a.transpose() * (rdd - self.sys.gravity);
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
        for (fe, fw) in self.sys.forces.iter().zip(self.forces.iter_mut()) {
            eval_force(fe, fw, q, v, t, None);
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
        for (c, cw) in self.sys.constraints.iter().zip(self.cons.iter_mut()) {
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

    /// Route `J[row, col] += v` (coordinate or multiplier unknowns by slot).
    #[inline]
    fn add(solver: &mut BorderedSystem, row: Slot, col: Slot, v: f64) {
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
                solver.d_mut().add(g as usize, h as usize, v);
            }
        }
    }

    /// The body block of `∂r/∂q` into the solver, scaled by `s`, from its
    /// body-frame derivatives in `sc.tangent` and the maps from `q` to the
    /// frame inputs: `phi_r[k]` = `∂[ā, α, ω]/∂R_k`, `phi_th[j]` =
    /// `∂[ā, α, ω]/∂θ_j`; with `rotation_terms`, also `∂A/∂θ_j f_r` and
    /// `∂Ḡ/∂θ_jᵀ f_θ` (not in the mass matrix).
    #[allow(clippy::too_many_arguments)]
    fn add_body_block(
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
        self.solver.clear();
        let s = 1.0 / bp;
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
                for c in 0..3 {
                    pr[c] = bp * rot.a[(k, c)];
                }
            }
            let mut rdd = Vector3::zeros();
            for k in 0..d {
                rdd[k] = a[o + k];
            }
            let rg = rdd - self.sys.gravity;
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
        self.residual_from_forces(t, q, v, lam_scaled, bp, r);
        // Force elements.
        for (fe, fw) in self.sys.forces.iter().zip(self.forces.iter_mut()) {
            eval_force(fe, fw, q, v, t, Some(gp));
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
        // Joints.
        for (c, cw) in self.sys.constraints.iter().zip(self.cons.iter_mut()) {
            let nl = cw.ka.len() + cw.kb.len();
            for (k, (row, re)) in c.rows.iter().zip(cw.rows.iter()).enumerate() {
                let ms = Slot::Border(self.mult_slot[cw.first + k]);
                let l = lam_scaled[cw.first + k];
                for i in 0..nl {
                    let gi = if i < cw.ka.len() {
                        cw.ka.idx[i]
                    } else {
                        cw.kb.idx[i - cw.ka.len()]
                    };
                    let si = self.coord_slot[gi];
                    Self::add(&mut self.solver, si, ms, re.grad[i]);
                    Self::add(&mut self.solver, ms, si, re.grad[i]);
                    if l != 0.0 {
                        for j in 0..nl {
                            let gj = if j < cw.ka.len() {
                                cw.ka.idx[j]
                            } else {
                                cw.kb.idx[j - cw.ka.len()]
                            };
                            let h = re.hess(row, &cw.ka, &cw.kb, t, i, j);
                            Self::add(&mut self.solver, si, self.coord_slot[gj], l * h);
                        }
                    }
                }
            }
        }
    }

    /// The residual after [`Body::tangent`] filled the body forces.
    fn residual_from_forces(
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
                for c in 0..3 {
                    pr[c] = rot.a[(k, c)];
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
        for (c, cw) in self.sys.constraints.iter().zip(self.cons.iter_mut()) {
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

    /// `γ` of every constraint row at `(t, q, q̇)` (after [`Assembly::residual`]
    /// or [`Assembly::mass_system`] evaluated the rows at `q`), into `out` (m):
    /// `Φ̈ = Φ_q q̈ − γ`.
    pub fn gamma(&mut self, t: f64, v: &[f64], out: &mut [f64]) {
        for &(i, row) in &self.norm_rows {
            let o = self.sys.bodies[i].offset + 3;
            out[row] = -v[o..o + 4].iter().map(|x| x * x).sum::<f64>();
        }
        for (c, cw) in self.sys.constraints.iter().zip(self.cons.iter_mut()) {
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
        for (c, cw) in self.sys.constraints.iter().zip(self.cons.iter_mut()) {
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

    /// The joint (index into [`System::constraints`]) that constraint row
    /// `k` belongs to, and the row's place in it; `None` for an
    /// Euler-parameter normalization row.
    pub fn row_owner(&self, k: usize) -> Option<(usize, usize)> {
        self.sys
            .constraints
            .iter()
            .zip(&self.cons)
            .enumerate()
            .find(|(_, (c, cw))| (cw.first..cw.first + c.rows.len()).contains(&k))
            .map(|(j, (_, cw))| (j, k - cw.first))
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

    /// Factor the matrix in the solver.
    pub fn factor(&mut self, t: f64, what: &'static str) -> Result<()> {
        match self.solver.factor() {
            Ok(()) => Ok(()),
            Err(e) => Err(Error::Singular {
                what,
                t,
                detail: self.describe_singular(&e),
            }),
        }
    }

    /// The solver's failure with the unknown it stopped at named (the body
    /// and coordinate, or the constraint row), so that the message says
    /// which coordinate has no inertia or which joint is redundant.
    fn describe_singular(&self, e: &crate::linalg::Singular) -> String {
        use crate::linalg::Part;
        let slot = match e.part {
            Part::Block(b) => Slot::Band(b as u32, e.column as u32),
            Part::Schur => Slot::Border(e.column as u32),
            Part::Matrix => return e.to_string(),
        };
        if let Some(c) = self.coord_slot.iter().position(|s| *s == slot) {
            let Some(b) = self
                .sys
                .bodies
                .iter()
                .find(|b| (b.offset..b.offset + b.n_coords()).contains(&c))
            else {
                return e.to_string();
            };
            let k = c - b.offset;
            let name = if k < b.d {
                ["R_x", "R_y", "R_z"][k].to_string()
            } else if k < b.d + b.n_theta {
                if b.n_theta == 1 {
                    "θ".to_string()
                } else {
                    format!("e{}", k - b.d)
                }
            } else {
                b.body
                    .layout()
                    .labels
                    .get(k - b.d - b.n_theta)
                    .cloned()
                    .unwrap_or_else(|| format!("q_f[{}]", k - b.d - b.n_theta))
            };
            return format!(
                "{e}: coordinate `{name}` of body `{}` ({})",
                b.name,
                b.body.layout().description
            );
        }
        if let Slot::Border(g) = slot {
            if let Some(k) = self.mult_slot.iter().position(|s| *s == g) {
                if let Some(&(i, _)) = self.norm_rows.iter().find(|(_, row)| *row == k) {
                    return format!(
                        "{e}: the Euler-parameter normalization of body `{}`",
                        self.sys.bodies[i].name
                    );
                }
                for (c, cw) in self.sys.constraints.iter().zip(&self.cons) {
                    if (cw.first..cw.first + c.rows.len()).contains(&k) {
                        return format!("{e}: row {} of a {} joint", k - cw.first, c.kind);
                    }
                }
            }
        }
        e.to_string()
    }

    /// Solve `J x = rhs` with the factored matrix: `rhs` in coordinate/row
    /// space (`n + m`), `x` likewise (prescribed coordinates get 0).
    pub fn solve(&mut self, rhs: &[f64], x: &mut [f64]) {
        let n = self.n;
        for (c, s) in self.coord_slot.iter().enumerate() {
            match *s {
                Slot::Band(b, i) => {
                    let r = self.solver.block_range(b as usize);
                    self.x_band[r.start + i as usize] = rhs[c];
                }
                Slot::Border(g) => self.x_border[g as usize] = rhs[c],
                Slot::Fixed => {}
            }
        }
        for (k, &g) in self.mult_slot.iter().enumerate() {
            self.x_border[g as usize] = rhs[n + k];
        }
        self.solver.solve(&mut self.x_band, &mut self.x_border);
        for (c, s) in self.coord_slot.iter().enumerate() {
            x[c] = match *s {
                Slot::Band(b, i) => {
                    let r = self.solver.block_range(b as usize);
                    self.x_band[r.start + i as usize]
                }
                Slot::Border(g) => self.x_border[g as usize],
                Slot::Fixed => 0.0,
            };
        }
        for (k, &g) in self.mult_slot.iter().enumerate() {
            x[n + k] = self.x_border[g as usize];
        }
    }

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
                eval_force(fe, fw, q, v, 0.0, None);
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
            eval_force(fe, fw, q, v, t, None);
            let rate = fw.eval.rate;
            match fe {
                ForceElement::Point { .. }
                | ForceElement::Torque {
                    law: TorqueLaw::Torque(_) | TorqueLaw::Pd { .. },
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

    /// Class of each unknown coordinate and multiplier, and the links
    /// between classes (for convergence).
    pub(crate) fn classes(&self) -> (&[u32], &[u32], &[Option<(u32, f64)>]) {
        (&self.coord_class, &self.mult_class, &self.class_link)
    }

    /// Global position of a marker.
    pub fn marker_position(&self, m: &crate::Marker, q: &[f64]) -> Vector3<f64> {
        let mut k = kin(self.sys, m);
        k.eval(m, q);
        k.pos
    }
}

impl<B: Body> System<B> {
    /// Workspace to evaluate marker `m` of this system (allocates once; then
    /// [`MarkerKin::eval`] at any `q` allocates nothing).
    pub fn marker_kin(&self, m: &crate::Marker) -> MarkerKin {
        kin(self, m)
    }
}

impl MarkerKin {
    /// Global velocity `ṗ = J_p q̇` after [`MarkerKin::eval`].
    pub fn velocity(&self, v: &[f64]) -> Vector3<f64> {
        self.idx
            .iter()
            .zip(&self.dpos)
            .map(|(&g, d)| d * v[g])
            .sum()
    }
}

fn kin<B: Body>(sys: &System<B>, m: &crate::Marker) -> MarkerKin {
    match m.body {
        Some(b) => {
            let e = &sys.bodies[b.0];
            MarkerKin::new(m, e.offset, e.d, e.n_theta)
        }
        None => MarkerKin::new(m, 0, 0, 0),
    }
}

/// Whether a body's elastic coordinates can move it rigidly in a direction
/// its frame coordinates also move it (a `free` reference condition): the
/// inertia of that free frame direction (`R_k`, or a rotation) left after
/// the elastic coordinates take theirs, `M_rr − M_rf m_ff⁻¹ M_fr` at
/// `q_f = 0`, is round-off of its own (below `10⁴ ε`; a clamped beam of 256
/// elements keeps about `3·10⁻⁹` of its rotational inertia). The name of the
/// first such direction, or `None` (also when `m_ff` itself is singular: the
/// solver then names the coordinate without inertia).
fn rigid_motion_in_elastic<B: Body>(
    b: &crate::system::BodyEntry<B>,
    presc: &[Option<usize>],
) -> Option<&'static str> {
    let lay = b.body.layout();
    let (o, d, nf, hb) = (b.offset, b.d, b.nf, lay.half_bandwidth);
    let mut work = b.body.work();
    let mut mass = BodyMass::zeros(nf, hb);
    b.body.mass(&vec![0.0; nf], &mut work, &mut mass);
    let mut mff = crate::linalg::BandMatrix::new(nf, hb, hb);
    for r in 0..nf {
        for c in r.saturating_sub(hb)..(r + hb + 1).min(nf) {
            mff.set(r, c, mass.m_ff.get(r, c));
        }
    }
    mff.factor().ok()?;
    // Free frame directions among [ā (3), α (3)]: a translation whose
    // coordinate is free, the rotations if any rotational coordinate is.
    let rot_free = (o + d..o + d + b.n_theta).any(|c| presc[c].is_none());
    let dirs: Vec<(usize, &'static str)> = if d == 2 {
        [(0, "R_x"), (1, "R_y"), (5, "θ")]
            .into_iter()
            .filter(|&(k, _)| {
                if k < 3 {
                    presc[o + k].is_none()
                } else {
                    rot_free
                }
            })
            .collect()
    } else {
        [
            (0, "R_x"),
            (1, "R_y"),
            (2, "R_z"),
            (3, "(rotation about the body x axis)"),
            (4, "(rotation about the body y axis)"),
            (5, "(rotation about the body z axis)"),
        ]
        .into_iter()
        .filter(|&(k, _)| {
            if k < 3 {
                presc[o + k].is_none()
            } else {
                rot_free
            }
        })
        .collect()
    };
    let n = dirs.len();
    // S = M_rr − M_rf m_ff⁻¹ M_fr on the free directions.
    let mut x = vec![0.0; nf * n];
    for (j, &(k, _)) in dirs.iter().enumerate() {
        x[j * nf..(j + 1) * nf].copy_from_slice(&mass.m_ref_f[k * nf..(k + 1) * nf]);
    }
    mff.solve_many(&mut x, n);
    let mut s = vec![0.0; n * n];
    for (i, &(ki, _)) in dirs.iter().enumerate() {
        for (j, &(kj, _)) in dirs.iter().enumerate() {
            let coupling: f64 = (0..nf)
                .map(|a| mass.m_ref_f[ki * nf + a] * x[j * nf + a])
                .sum();
            s[i * n + j] = mass.m_ref_frame[ki * 6 + kj] - coupling;
        }
    }
    // Symmetric elimination; a pivot at round-off of the direction's own
    // inertia is a direction the elastic coordinates already describe.
    for k in 0..n {
        let own = mass.m_ref_frame[dirs[k].0 * 7];
        let p = s[k * n + k];
        if !(p > 1e4 * f64::EPSILON * own) {
            return Some(dirs[k].1);
        }
        for i in k + 1..n {
            let f = s[i * n + k] / p;
            for j in k..n {
                s[i * n + j] -= f * s[k * n + j];
            }
        }
    }
    None
}

fn local_index(ka: &MarkerKin, kb: Option<&MarkerKin>, i: usize) -> usize {
    if i < ka.len() {
        ka.idx[i]
    } else {
        kb.expect("second marker").idx[i - ka.len()]
    }
}

fn eval_force(
    fe: &ForceElement,
    fw: &mut ForceWork,
    q: &[f64],
    v: &[f64],
    t: f64,
    gp: Option<f64>,
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
    fw.eval.eval(fe, &fw.ka, fw.kb.as_ref(), t, &fw.qd, gp);
}

impl<B: Body> Assembly<'_, B> {
    /// The scaled generalized-α residual `[r_dyn/β'; Φ]` with `λ = β' λ̃`.
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
            for i in 0..n + m {
                if !(i < n && self.coord_slot[i] == Slot::Fixed) {
                    colmax = colmax.max(analytic[i].abs());
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
