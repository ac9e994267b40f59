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
//!
//! One file per concept, each an `impl Assembly` block: `layout` (where the
//! unknowns are), `residual`, `iteration_matrix`, `mass` (the mass system),
//! `constraints` (velocity- and acceleration-level rows, set-up checks),
//! `solve` (factor and solve), `energy` (monitored quantities), `linear`
//! (the dense parts `M`, `C`, `K`, `Φ_q` for linear models), `statics`
//! (the matrix with explicit coefficients `c_M M + c_C C + K` and the load
//! factor of a load-stepped static solution),
//! `kinematics` (markers) and `oracle` (finite-difference check of the
//! iteration matrix).

mod constraints;
mod energy;
mod iteration_matrix;
mod kinematics;
mod layout;
mod linear;
mod mass;
mod oracle;
mod residual;
mod solve;
mod statics;

use crate::body::{BandBuf, Body, BodyForces, BodyMass, BodyState, BodyTangent, BodyWork};
use crate::error::{Error, Result};
use crate::force::ForceEval;
use crate::joint::RowEval;
use crate::linalg::{BlockShape, BorderedSystem};
use crate::marker::MarkerKin;
use crate::system::System;
use kinematics::kin;
use layout::rigid_motion_in_elastic;
pub use linear::TangentParts;
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
    /// `Σ_r λ_r ∂²Φ_r/∂q²` over the local coordinates (`nl × nl`).
    hess: Vec<f64>,
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
    pub(crate) class_link: Vec<ClassLink>,
    /// The gravity the equations use: the system's, times
    /// [`Assembly::load_scale`] (equal to it unless a static solution
    /// steps its loads).
    gravity: Vector3<f64>,
    /// The factor on gravity and the applied loads (point forces, constant
    /// motor torques): 1 except in a load-stepped static solution
    /// ([`Assembly::set_load_scale`]).
    load_scale: f64,
    /// The values of the system's inputs (per assembly, so that several
    /// integrations of one system are independent).
    inputs: Vec<f64>,
    /// Per input, its drive perturbation at the start of the current
    /// step: `[t₀, δ(t₀), δ̇(t₀)]` (`δ̈` is the input's value over the step).
    drives: Vec<[f64; 3]>,
    /// The system's constraints, with each driver perturbed by an input
    /// reading that perturbation from `cells` (this assembly's own).
    constraints: Vec<crate::joint::Constraint>,
    /// The drive perturbations and input values as the constraints'
    /// drivers read them (`[t₀, δ₀, δ̇₀, u]` per input, as bits).
    cells: std::sync::Arc<Vec<[std::sync::atomic::AtomicU64; 4]>>,
}

/// `[δ, δ̇, δ̈]` at `t` of a drive perturbation that starts the step at
/// `t₀` with `δ₀`, `δ̇₀` and has `δ̈ = u` over it.
fn perturbation([t0, d0, dd0, u]: [f64; 4], t: f64) -> [f64; 3] {
    let s = t - t0;
    [d0 + dd0 * s + 0.5 * u * s * s, dd0 + u * s, u]
}

/// `sys`'s constraints with every driver perturbed by an input replaced by
/// one that reads the perturbation from `cells`.
fn perturbed_constraints(
    constraints: &[crate::joint::Constraint],
    cells: &std::sync::Arc<Vec<[std::sync::atomic::AtomicU64; 4]>>,
) -> Vec<crate::joint::Constraint> {
    use crate::joint::Coef;
    let wrap = |d: &crate::Driver| -> crate::Driver {
        match d.input() {
            None => d.clone(),
            Some(k) => {
                let (d, cells) = (d.clone(), cells.clone());
                crate::Driver::new(move |t| {
                    let c = &cells[k];
                    let x = std::array::from_fn(|i| {
                        f64::from_bits(c[i].load(std::sync::atomic::Ordering::Relaxed))
                    });
                    d.eval_perturbed(t, perturbation(x, t))
                })
            }
        }
    };
    constraints
        .iter()
        .map(|c| {
            let mut c = c.clone();
            for row in &mut c.rows {
                if let Some(d) = &mut row.offset {
                    *d = wrap(d);
                }
                for term in row.v1.iter_mut().chain(row.v2.iter_mut()) {
                    match &mut term.coef {
                        Coef::Cos(d) | Coef::Sin(d) => *d = wrap(d),
                        Coef::Const(_) => {}
                    }
                }
            }
            c
        })
        .collect()
}

/// A class's links (see [`Assembly::classes`]): a class whose positions,
/// times the factor, also set this class's round-off floor, and a constant
/// added to it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ClassLink {
    /// The linked class and the factor on its largest `|q|`.
    pub(crate) link: Option<(u32, f64)>,
    /// A constant part of the floor (a length or an angle).
    pub(crate) constant: f64,
}

/// The round-off floor of a class: its own largest `|q|` plus its link's
/// (`qmax` by class) and its constant.
pub(crate) fn class_floor(own: f64, link: &ClassLink, qmax: &[f64]) -> f64 {
    own + link.constant + link.link.map_or(0.0, |(p, f)| f * qmax[p as usize])
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
                hess: vec![0.0; nl * nl],
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
            // A beam's elastic translations and rotations are linked by its
            // length. A segment of a body run as segments has its elastic
            // coordinates at the cuts set by the cut joints, through
            // differences of positions as large as its length and axes of
            // unit length: they are not known better than ε l and ε (a
            // constant floor; a body not run as segments keeps its own).
            // Likewise its frame's rotation, set by the cut through unit
            // axes: not better than ε.
            let segment = sys.segment_group(crate::marker::BodyId(i)).is_some();
            match lay.length {
                Some(l) if l > 0.0 && l.is_finite() && b.nf > 0 => {
                    let (ct, cr) = if segment { (l, 1.0) } else { (0.0, 0.0) };
                    class_link.extend([
                        ClassLink::default(),
                        ClassLink {
                            link: None,
                            constant: cr,
                        },
                        ClassLink {
                            link: Some((base + 3, l)),
                            constant: ct,
                        },
                        ClassLink {
                            link: Some((base + 2, 1.0 / l)),
                            constant: cr,
                        },
                    ])
                }
                _ => class_link.extend([ClassLink::default(); 4]),
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
        class_link.resize(n_classes as usize, ClassLink::default());
        // The border's Schur complement is dense: bound it before allocating.
        let nb = n_border as usize;
        if nb.saturating_mul(nb) > MAX_BORDER_ENTRIES {
            return Err(Error::InvalidInput(format!(
                "the system has {nb} border unknowns (frame coordinates, joint rows and the elastic coordinates at markers), whose dense Schur complement would need {:.1} GiB: more than the limit of {MAX_BORDER_ENTRIES} entries (MAX_BORDER_ENTRIES); use fewer bodies or joints",
                (nb as f64).powi(2) * 8.0 / (1u64 << 30) as f64
            )));
        }
        // A long border whose couplings are banded in a reordering (a chain
        // of bodies end to end) is renumbered and factored in band storage.
        let band = border_order(sys, &cons, &forces, &norm_rows, &coord_slot, &mult_slot, nb);
        if let Some((pos, _)) = &band {
            let renum = |s: &mut Slot| {
                if let Slot::Border(g) = s {
                    *g = pos[*g as usize] as u32;
                }
            };
            coord_slot.iter_mut().for_each(renum);
            mult_slot
                .iter_mut()
                .for_each(|g| *g = pos[*g as usize] as u32);
            for border in &mut body_border {
                border.iter_mut().for_each(|g| *g = pos[*g]);
                border.sort_unstable();
            }
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
        let solver = match band {
            Some((_, b)) => BorderedSystem::with_banded_border(&shapes, nb, b, b),
            None => BorderedSystem::new(&shapes, nb),
        };
        let nb_total: usize = blocks.iter().map(|b| b.0).sum();
        let cells = std::sync::Arc::new(
            sys.inputs
                .iter()
                .map(|u| {
                    [0.0, 0.0, 0.0, *u].map(|x| std::sync::atomic::AtomicU64::new(x.to_bits()))
                })
                .collect(),
        );
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
            x_border: vec![0.0; nb],
            mult_class,
            coord_class,
            class_link,
            gravity: sys.gravity,
            load_scale: 1.0,
            inputs: sys.inputs.clone(),
            drives: vec![[0.0; 3]; sys.inputs.len()],
            constraints: perturbed_constraints(&sys.constraints, &cells),
            cells,
        })
    }
}

impl<B: Body> Assembly<'_, B> {
    /// The values of the system's inputs.
    pub fn inputs(&self) -> &[f64] {
        &self.inputs
    }

    /// The values of the system's inputs, to set (then
    /// [`Assembly::sync_inputs`], for the drivers of constraints perturbed
    /// by an input).
    pub fn inputs_mut(&mut self) -> &mut [f64] {
        &mut self.inputs
    }

    /// Input `k`'s drive perturbation `[δ, δ̇, δ̈]` at `t` in the current
    /// step: `δ̈ = u` (the input's value, constant over the step) and `δ`,
    /// `δ̇` its exact integrals from the step's start `t₀`:
    /// `δ(t) = δ₀ + δ̇₀ s + ½ u s²`, `δ̇(t) = δ̇₀ + u s`, `s = t − t₀`.
    pub fn drive_perturbation(&self, k: usize, t: f64) -> [f64; 3] {
        let [t0, d0, dd0] = self.drives[k];
        perturbation([t0, d0, dd0, self.inputs[k]], t)
    }

    /// Give the constraints' perturbed drivers the current drive
    /// perturbations and input values (after either changed).
    pub fn sync_inputs(&self) {
        for ((c, d), u) in self.cells.iter().zip(&self.drives).zip(&self.inputs) {
            for (cell, x) in c.iter().zip([d[0], d[1], d[2], *u]) {
                cell.store(x.to_bits(), std::sync::atomic::Ordering::Relaxed);
            }
        }
    }

    /// Move the drive perturbations to `t` (the end of a step taken):
    /// `δ`, `δ̇` there become the next step's start values.
    pub fn advance_drive_perturbations(&mut self, t: f64) {
        for k in 0..self.drives.len() {
            let [d, dd, _] = self.drive_perturbation(k, t);
            self.drives[k] = [t, d, dd];
        }
        self.sync_inputs();
    }

    /// The drive perturbations' start values (`[t₀, δ₀, δ̇₀]` per input).
    pub fn drive_states(&self) -> &[[f64; 3]] {
        &self.drives
    }

    /// Set the drive perturbations' start values (a restored state).
    pub fn drive_states_mut(&mut self) -> &mut [[f64; 3]] {
        &mut self.drives
    }
}

/// The smallest border that is worth ordering for band storage.
const MIN_BANDED_BORDER: usize = 48;

/// A reordering of the border (`pos[g]`: the new index of border unknown
/// `g`) that makes its couplings banded with half-bandwidth `b`, if the
/// border has at least [`MIN_BANDED_BORDER`] unknowns and band storage then
/// costs less to factor than the dense Schur complement (`12 b² < k²`);
/// otherwise `None` (the order and the dense factorization of before).
///
/// The couplings: a body's border unknowns with each other (its frame
/// rows and the Schur complement of its band block), a joint's multipliers
/// with its markers' coordinates and those with each other (its Hessian),
/// a force element's coordinates with each other, a normalization with
/// its Euler parameters. Reverse Cuthill–McKee orders them.
fn border_order<B: Body>(
    sys: &System<B>,
    cons: &[ConsWork],
    forces: &[ForceWork],
    norm_rows: &[(usize, usize)],
    coord_slot: &[Slot],
    mult_slot: &[u32],
    nb: usize,
) -> Option<(Vec<usize>, usize)> {
    if nb < MIN_BANDED_BORDER {
        return None;
    }
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); nb];
    let border = |c: usize| match coord_slot[c] {
        Slot::Border(g) => Some(g as usize),
        _ => None,
    };
    let mut clique = |members: &[usize]| {
        for (i, &a) in members.iter().enumerate() {
            for &b in &members[i + 1..] {
                if a != b {
                    adj[a].push(b);
                    adj[b].push(a);
                }
            }
        }
    };
    for b in &sys.bodies {
        let members: Vec<usize> = (b.offset..b.offset + b.n_coords())
            .filter_map(border)
            .collect();
        clique(&members);
    }
    for &(i, row) in norm_rows {
        let o = sys.bodies[i].offset + 3;
        let mut members: Vec<usize> = (o..o + 4).filter_map(border).collect();
        members.push(mult_slot[row] as usize);
        clique(&members);
    }
    for (c, cw) in sys.constraints.iter().zip(cons) {
        let mut members: Vec<usize> = cw
            .ka
            .idx
            .iter()
            .chain(&cw.kb.idx)
            .filter_map(|&g| border(g))
            .collect();
        members.extend((cw.first..cw.first + c.rows.len()).map(|k| mult_slot[k] as usize));
        clique(&members);
    }
    for fw in forces {
        let members: Vec<usize> = fw
            .ka
            .idx
            .iter()
            .chain(fw.kb.iter().flat_map(|k| k.idx.iter()))
            .filter_map(|&g| border(g))
            .collect();
        clique(&members);
    }
    for a in &mut adj {
        a.sort_unstable();
        a.dedup();
    }
    let order = crate::linalg::reverse_cuthill_mckee(&adj);
    let mut pos = vec![0; nb];
    for (p, &g) in order.iter().enumerate() {
        pos[g] = p;
    }
    let b = crate::linalg::bandwidth(&adj, &pos);
    (12 * b * b < nb * nb).then_some((pos, b))
}
