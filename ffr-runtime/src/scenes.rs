//! Benchmark scenes built from bodies given as `Box<dyn FlexBody>`.
//!
//! Beam bodies are assumed to run along body x from the body-frame origin
//! (node 0) to node `N`, with elastic-coordinate labels `kind_node`
//! (`ux, uy, uz, rx, ry, rz`, see [`FlexBody::dof_labels`]).

use crate::body::FlexBody;
use crate::driver::Driver;
use crate::error::{Error, Result};
use crate::integrator::{GeneralizedAlpha, Integrator};
use crate::marker::{dof_index, BodyId, Marker};
use crate::rigid::RigidBody;
use crate::system::{Pose, State, System};
use nalgebra::{DVector, Matrix3xX, UnitQuaternion, Vector2, Vector3};
use std::ops::ControlFlow;
use std::sync::Arc;

/// Highest node index among `kind_node` labels.
pub fn last_node(labels: &[String]) -> Option<usize> {
    labels
        .iter()
        .filter_map(|l| l.split_once('_')?.1.parse::<usize>().ok())
        .max()
}

/// Length of a uniform beam body from its invariants: `L = 2 S_t0,x / m`.
pub fn beam_length(body: &dyn FlexBody) -> f64 {
    let inv = body.invariants();
    2.0 * inv.s_t0.x / inv.mass
}

/// `S_P` of beam node `node` (translations only).
pub fn node_shape(body: &dyn FlexBody, node: usize) -> Matrix3xX<f64> {
    crate::marker::node_shapes(&body.dof_labels(), node).0
}

// ------------------------------------------------------------------ spin-up

/// Settings of the Kane–Ryan–Banerjee spin-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpinUp {
    /// Final spin rate `ω_s` (rad/s).
    pub omega_s: f64,
    /// Ramp time `T` (s), 15 in the benchmark.
    pub t_ramp: f64,
    /// End time (s).
    pub t_end: f64,
    /// Step (s).
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Geometric stiffening on (requires a body that has it).
    pub stiffening: bool,
}

impl SpinUp {
    /// `ω_s`, `T = 15 s`, `t_end = 20 s`, `dt = 0.01 s`, generalized-α `ρ∞ = 0.8`, stiffening on.
    pub fn new(omega_s: f64) -> Self {
        Self {
            omega_s,
            t_ramp: 15.0,
            t_end: 20.0,
            dt: 0.01,
            integrator: Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.8)),
            stiffening: true,
        }
    }
}

/// Why a run stopped early.
#[derive(Clone, Debug, PartialEq)]
pub struct Divergence {
    /// Time (s).
    pub t: f64,
    /// What happened (tip beyond the beam length, or the integrator's error).
    pub reason: String,
}

/// Tip displacement history of a spin-up run, in the rotating hub (body) frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpinUpResult {
    /// Times (s).
    pub t: Vec<f64>,
    /// Hub angle θ(t) (rad).
    pub hub_angle: Vec<f64>,
    /// Tip displacement along the hub-frame x axis (m).
    pub tip_axial: Vec<f64>,
    /// Tip displacement along the hub-frame y axis (m; negative = lagging, hub turning positively about z).
    pub tip_transverse: Vec<f64>,
    /// Set if the run diverged (|tip| > L) or the integrator failed.
    pub diverged: Option<Divergence>,
}

impl SpinUpResult {
    /// `(t, value)` of the most negative transverse tip deflection.
    pub fn min_transverse(&self) -> Option<(f64, f64)> {
        self.t
            .iter()
            .zip(&self.tip_transverse)
            .map(|(a, b)| (*a, *b))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
    /// Largest `|tip_transverse|` for `t ≥ t_from`.
    pub fn max_abs_transverse_after(&self, t_from: f64) -> f64 {
        self.t
            .iter()
            .zip(&self.tip_transverse)
            .filter(|(t, _)| **t >= t_from)
            .map(|(_, v)| v.abs())
            .fold(0.0, f64::max)
    }
    /// Linear interpolation of the transverse deflection at `t`.
    pub fn transverse_at(&self, t: f64) -> Option<f64> {
        let i = self.t.iter().position(|&x| x >= t)?;
        if i == 0 {
            return self.tip_transverse.first().copied();
        }
        let (t0, t1) = (self.t[i - 1], self.t[i]);
        let w = (t - t0) / (t1 - t0);
        Some(self.tip_transverse[i - 1] * (1.0 - w) + self.tip_transverse[i] * w)
    }
}

/// The spin-up scene: planar, the beam clamped at the hub (its frame origin
/// fixed at the global origin), hub angle `θ(t)` prescribed ([`Driver::spin_up`]).
pub fn spin_up_system(
    body: Box<dyn FlexBody>,
    omega_s: f64,
    t_ramp: f64,
    stiffening: bool,
) -> Result<(System, BodyId)> {
    if body.dim() != 2 {
        return Err(Error::InvalidInput(
            "the spin-up scene is planar: it needs a planar (dim 2) body".into(),
        ));
    }
    if !(omega_s.is_finite() && t_ramp > 0.0) {
        return Err(Error::InvalidInput(format!(
            "spin-up needs finite ω_s and T > 0 (got {omega_s}, {t_ramp})"
        )));
    }
    let mut sys = System::planar();
    let b = sys.add_body(body, Pose::planar(0.0, 0.0, 0.0))?;
    sys.set_stiffening(b, stiffening)?;
    sys.prescribe_coordinate(b, 0, Driver::constant(0.0))?;
    sys.prescribe_coordinate(b, 1, Driver::constant(0.0))?;
    sys.prescribe_coordinate(b, 2, Driver::spin_up(omega_s, t_ramp))?;
    Ok((sys, b))
}

/// The tip's `S_P` for a spin-up run: `tip_shape` if given (3 × n_f), else
/// the last node's translations (which must include `ux` and `uy`).
fn spin_up_tip(body: &dyn FlexBody, tip_shape: Option<Matrix3xX<f64>>) -> Result<Matrix3xX<f64>> {
    let labels = body.dof_labels();
    let nf = body.nf();
    match tip_shape {
        Some(s) if s.ncols() == nf => Ok(s),
        Some(s) => Err(Error::InvalidInput(format!(
            "tip shape has {} columns, n_f = {nf}",
            s.ncols()
        ))),
        None => {
            let n = last_node(&labels).ok_or_else(|| {
                Error::InvalidInput("body has no node labels; pass the tip shape".into())
            })?;
            let (ix, iy) = (
                dof_index(&labels, &format!("ux_{n}")),
                dof_index(&labels, &format!("uy_{n}")),
            );
            if ix.is_none() || iy.is_none() {
                return Err(Error::InvalidInput(format!(
                    "no ux_{n}/uy_{n} coordinates; pass the tip shape"
                )));
            }
            Ok(node_shape(body, n))
        }
    }
}

/// Integrate a spin-up system, recording the tip (`tip * q_f`, hub frame)
/// and the hub angle `hub_angle(q)`; `extra` sees every state. Divergence
/// (|tip| > `length`) or an integrator failure ends the run and is reported
/// in [`SpinUpResult::diverged`].
fn run_spin_up(
    sys: &System,
    b: BodyId,
    tip: &Matrix3xX<f64>,
    length: f64,
    cfg: &SpinUp,
    mut hub_angle: impl FnMut(&DVector<f64>) -> f64,
    mut extra: impl FnMut(&State),
) -> Result<SpinUpResult> {
    let nf = sys.body(b).nf();
    let fo = sys.offset(b) + sys.body(b).f_offset();
    let mut res = SpinUpResult::default();
    let run = sys.simulate(cfg.t_end, cfg.dt, &cfg.integrator, |v| {
        let q = &v.state.q;
        let qf = q.rows(fo, nf);
        let u = tip * qf;
        res.t.push(v.state.t);
        res.hub_angle.push(hub_angle(q));
        res.tip_axial.push(u.x);
        res.tip_transverse.push(u.y);
        extra(v.state);
        if u.norm() > length {
            res.diverged = Some(Divergence {
                t: v.state.t,
                reason: format!(
                    "tip displacement {:.3} m exceeds the beam length {length} m",
                    u.norm()
                ),
            });
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    });
    match run {
        Ok(_) => {}
        Err(
            e @ (Error::NoConvergence { .. }
            | Error::NonFinite { .. }
            | Error::Unstable { .. }
            | Error::Singular { .. }),
        ) => {
            res.diverged = Some(Divergence {
                t: res.t.last().copied().unwrap_or(0.0),
                reason: e.to_string(),
            });
        }
        Err(e) => return Err(e),
    }
    Ok(res)
}

/// Run the spin-up. The tip is `tip_shape` (`S_P`, 3 × n_f) if given, else
/// the last node's `ux`/`uy` coordinates. Divergence (|tip| > L, `L = 2 S_t0,x/m`)
/// or an integrator failure stops the run and is reported in
/// [`SpinUpResult::diverged`]; bad input is an `Err`.
pub fn spin_up(
    body: Box<dyn FlexBody>,
    tip_shape: Option<Matrix3xX<f64>>,
    cfg: &SpinUp,
) -> Result<SpinUpResult> {
    let length = beam_length(body.as_ref());
    let tip = spin_up_tip(body.as_ref(), tip_shape)?;
    let (sys, b) = spin_up_system(body, cfg.omega_s, cfg.t_ramp, cfg.stiffening)?;
    let ith = sys.offset(b) + 2;
    run_spin_up(&sys, b, &tip, length, cfg, |q| q[ith], |_| {})
}

// ------------------------------------------------------------------ spin-up in space

/// The spin-up modelled in space: the body (planar or spatial) in a spatial
/// scene with Euler parameters, its frame origin held at the global origin
/// and its frame turned about global z by the spin-up angle `θ(t)`
/// ([`Driver::spin_up`]). The hub is a revolute joint between a ground
/// marker at the origin and the body-frame origin (`R = 0`, `z_g · x_b =
/// z_g · y_b = 0`: the rotations about x and y are locked), driven by
/// [`System::prescribe_rotation`] (`sin(φ − θ(t)) = 0`).
///
/// Together with the Euler-parameter normalization these are 7 equations
/// on the 7 frame coordinates, independent wherever the body's z axis is
/// the global one (`e1 = e2 = 0`).
pub fn spin_up_spatial_system(
    body: Box<dyn FlexBody>,
    omega_s: f64,
    t_ramp: f64,
    stiffening: bool,
) -> Result<(System, BodyId)> {
    if !(omega_s.is_finite() && t_ramp > 0.0) {
        return Err(Error::InvalidInput(format!(
            "spin-up needs finite ω_s and T > 0 (got {omega_s}, {t_ramp})"
        )));
    }
    let mut sys = System::spatial();
    let b = sys.add_body(body, Pose::identity(3))?;
    sys.set_stiffening(b, stiffening)?;
    let hub = Marker::ground(Vector3::zeros());
    sys.revolute(hub.clone(), Marker::origin(b))?;
    sys.prescribe_rotation(hub, Marker::origin(b), Driver::spin_up(omega_s, t_ramp))?;
    Ok((sys, b))
}

/// A spin-up run in space ([`spin_up_spatial`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpinUpSpatialResult {
    /// The same history as the planar [`spin_up`]: hub angle (from the Euler
    /// parameters, `2 atan2(e3, e0)` unwrapped) and the tip's in-plane
    /// displacement in the hub frame.
    pub in_plane: SpinUpResult,
    /// Tip displacement along the hub-frame z axis (out of the plane; m).
    pub tip_lateral: Vec<f64>,
    /// Torsion rotation `rx` of the tip node (rad; 0 if the body has none).
    pub tip_torsion: Vec<f64>,
    /// Largest `|·|` of all out-of-plane coordinates: `R_z`, `e1`, `e2` and
    /// every elastic coordinate labelled `uz`, `rx` or `ry`.
    pub out_of_plane: Vec<f64>,
    /// Euler-parameter normalization `eᵀe − 1`.
    pub normalization: Vec<f64>,
    /// Hub angle error `φ − θ(t)` (rad).
    pub angle_error: Vec<f64>,
    /// Hub rate `ω_z = (A Ḡ ė)_z` (rad/s), the integrator's velocity of the
    /// Euler parameters mapped to the angular velocity about global z.
    pub hub_rate: Vec<f64>,
}

/// Run the spin-up in space ([`spin_up_spatial_system`]) with the settings of
/// the planar run; the tip is `tip_shape` or the last node as in [`spin_up`].
pub fn spin_up_spatial(
    body: Box<dyn FlexBody>,
    tip_shape: Option<Matrix3xX<f64>>,
    cfg: &SpinUp,
) -> Result<SpinUpSpatialResult> {
    let length = beam_length(body.as_ref());
    let tip = spin_up_tip(body.as_ref(), tip_shape)?;
    let labels = body.dof_labels();
    let torsion = last_node(&labels).and_then(|n| dof_index(&labels, &format!("rx_{n}")));
    let (sys, b) = spin_up_spatial_system(body, cfg.omega_s, cfg.t_ramp, cfg.stiffening)?;
    let (o, fo, nf) = (
        sys.offset(b),
        sys.offset(b) + sys.body(b).f_offset(),
        sys.body(b).nf(),
    );
    let out_f: Vec<usize> = labels
        .iter()
        .enumerate()
        .filter(|(_, l)| matches!(l.split_once('_'), Some(("uz" | "rx" | "ry", _))))
        .map(|(j, _)| fo + j)
        .collect();
    let out_idx: Vec<usize> = [o + 2, o + 4, o + 5].into_iter().chain(out_f).collect();
    let driver = Driver::spin_up(cfg.omega_s, cfg.t_ramp);
    let mut extra = SpinUpSpatialResult::default();
    let mut phi_prev = 0.0;
    let hub_angle = |q: &DVector<f64>| {
        // 2 atan2(e3, e0) is the angle modulo 2π (e and −e are one rotation);
        // unwrap to the branch nearest the previous sample.
        let raw = 2.0 * q[o + 6].atan2(q[o + 3]);
        let tau = 2.0 * std::f64::consts::PI;
        let phi = raw + tau * ((phi_prev - raw) / tau).round();
        phi_prev = phi;
        phi
    };
    let in_plane = run_spin_up(&sys, b, &tip, length, cfg, hub_angle, |s| {
        let q = &s.q;
        let qf = q.rows(fo, nf);
        extra.tip_lateral.push((&tip * qf).z);
        extra
            .tip_torsion
            .push(torsion.map(|j| q[fo + j]).unwrap_or(0.0));
        extra
            .out_of_plane
            .push(out_idx.iter().map(|&j| q[j].abs()).fold(0.0, f64::max));
        extra
            .normalization
            .push(q.rows(o + 3, 4).norm_squared() - 1.0);
        let fr = sys.body(b).frame(sys.body_slice(b, q));
        extra.hub_rate.push((fr.a * (&fr.g * s.v.rows(o + 3, 4))).z);
    })?;
    extra.angle_error = in_plane
        .t
        .iter()
        .zip(&in_plane.hub_angle)
        .map(|(&t, &phi)| phi - driver.eval(t)[0])
        .collect();
    extra.in_plane = in_plane;
    Ok(extra)
}

/// Convergence study of the spin-up: for each `(body, dt)` the transverse tip
/// deflection at the sample times `t_samples` (or NaN if diverged before).
/// `make_body(elements)` builds the body.
pub fn spin_up_convergence(
    make_body: &dyn Fn(usize) -> Box<dyn FlexBody>,
    elements: &[usize],
    steps: &[f64],
    base: &SpinUp,
    t_samples: &[f64],
) -> Result<Vec<(usize, f64, Vec<f64>)>> {
    let mut out = Vec::new();
    for &n in elements {
        for &dt in steps {
            let cfg = SpinUp {
                dt,
                t_end: t_samples.iter().copied().fold(0.0, f64::max) + dt,
                ..*base
            };
            let r = spin_up(make_body(n), None, &cfg)?;
            let vals = t_samples
                .iter()
                .map(|&t| r.transverse_at(t).unwrap_or(f64::NAN))
                .collect();
            out.push((n, dt, vals));
        }
    }
    Ok(out)
}

// ------------------------------------------------------------------ pendulum

/// A flexible pendulum: the body's node 0 (its frame origin) pinned to the
/// ground at the origin by a revolute joint about global z, the body initially
/// horizontal along +x, gravity `−9.81 e_y`. Planar for a `dim 2` body,
/// spatial (Euler parameters, spatial revolute) for a `dim 3` body.
pub fn pendulum(body: Box<dyn FlexBody>) -> Result<(System, BodyId)> {
    let d = body.dim();
    let labels = body.dof_labels();
    let mut sys = if d == 2 {
        System::planar()
    } else {
        System::spatial()
    };
    let b = sys.add_body(body, Pose::identity(d))?;
    let pin = Marker::node(b, Vector3::zeros(), &labels, 0);
    sys.revolute(Marker::ground(Vector3::zeros()), pin)?;
    sys.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    Ok((sys, b))
}

// ------------------------------------------------------------------ free floating

/// A free body (no joints, no forces) with initial frame velocity `v`,
/// angular velocity `omega` (global) and elastic state `(q_f, q̇_f)`.
pub fn free_floating(
    body: Box<dyn FlexBody>,
    v: Vector3<f64>,
    omega: Vector3<f64>,
    q_f: &[f64],
    qd_f: &[f64],
) -> Result<(System, BodyId)> {
    let d = body.dim();
    let mut sys = if d == 2 {
        System::planar()
    } else {
        System::spatial()
    };
    let pose = if d == 2 {
        Pose::planar(0.1, -0.2, 0.3)
    } else {
        Pose::spatial(
            Vector3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.2, -0.3, 0.5),
        )
    };
    let b = sys.add_body(body, pose)?;
    sys.set_velocity(b, v, omega)?;
    sys.set_elastic(b, q_f, qd_f)?;
    Ok((sys, b))
}

// ------------------------------------------------------------------ slider-crank

/// The slider-crank: crank 0.15 m, 0.36 kg, `J = 0.002727 kg m²` about its
/// pivot (centre of mass at mid-length), driven at 150 rad/s from `θ = 0`;
/// the flexible rod (0.30 m, steel 8 × 8 mm in the literature; given as a body,
/// best with a `pinned` reference so that `uy` of the middle node is the
/// midpoint deflection) from the crank tip to the slider (0.075552 kg) on the x axis.
pub struct SliderCrank {
    /// The system.
    pub system: System,
    /// Crank body.
    pub crank: BodyId,
    /// Rod body.
    pub rod: BodyId,
    /// Slider body.
    pub slider: BodyId,
    /// Index in `q` of the rod's middle-node `uy`.
    pub mid_uy: usize,
}

/// Crank length (m).
pub const CRANK_LENGTH: f64 = 0.15;
/// Rod length (m).
pub const ROD_LENGTH: f64 = 0.30;
/// Crank speed (rad/s).
pub const CRANK_SPEED: f64 = 150.0;

/// A planar displacement field along a beam body's x axis (`0 ≤ x ≤ L`):
/// lateral `v(x)` (body y), its slope `v'(x)`, and axial `u(x)` (body x).
/// Used for displacements and, likewise, for velocities `v̇, v̇', u̇`.
#[derive(Clone)]
pub struct BeamField {
    /// Lateral displacement `v(x)`.
    pub v: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    /// Slope `v'(x)` (the small rotation about body z).
    pub dv: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    /// Axial displacement `u(x)`.
    pub u: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
}

impl std::fmt::Debug for BeamField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BeamField")
    }
}

impl BeamField {
    /// From closures `v`, `v'`, `u`.
    pub fn new(
        v: impl Fn(f64) -> f64 + Send + Sync + 'static,
        dv: impl Fn(f64) -> f64 + Send + Sync + 'static,
        u: impl Fn(f64) -> f64 + Send + Sync + 'static,
    ) -> Self {
        Self {
            v: Arc::new(v),
            dv: Arc::new(dv),
            u: Arc::new(u),
        }
    }
    /// The zero field.
    pub fn zero() -> Self {
        Self::new(|_| 0.0, |_| 0.0, |_| 0.0)
    }
    /// Nodal coordinates of a planar beam body of length `length` with
    /// `N` equal elements (labels `kind_node`, nodes at `x_i = i L / N`):
    /// `ux_i = u(x_i)`, `uy_i = v(x_i)`, `rz_i = v'(x_i)`. Coordinates the
    /// reference conditions removed are simply absent; any other label
    /// (a spatial or non-beam body) is an error.
    pub fn nodal_coordinates(&self, labels: &[String], length: f64) -> Result<Vec<f64>> {
        let n = last_node(labels)
            .filter(|&n| n > 0)
            .ok_or_else(|| Error::InvalidInput("body has no beam node labels".into()))?;
        labels
            .iter()
            .map(|lab| {
                let (kind, node) = lab
                    .split_once('_')
                    .and_then(|(k, i)| Some((k, i.parse::<usize>().ok()?)))
                    .ok_or_else(|| Error::InvalidInput(format!("`{lab}` is no beam node label")))?;
                let x = length * node as f64 / n as f64;
                let val = match kind {
                    "ux" => (self.u)(x),
                    "uy" => (self.v)(x),
                    "rz" => (self.dv)(x),
                    _ => {
                        return Err(Error::InvalidInput(format!(
                            "`{lab}`: a planar beam field has no `{kind}` component"
                        )))
                    }
                };
                if val.is_finite() {
                    Ok(val)
                } else {
                    Err(Error::InvalidInput(format!(
                        "field is not finite at `{lab}`"
                    )))
                }
            })
            .collect()
    }
}

/// The rod's initial elastic state.
#[derive(Clone, Debug, Default)]
pub enum RodElastic {
    /// Undeformed, at rest relative to its frame.
    #[default]
    Undeformed,
    /// Displacement and velocity fields projected onto a beam rod's nodal
    /// coordinates ([`BeamField::nodal_coordinates`]).
    Fields {
        /// Displacements `v, v', u`.
        q: BeamField,
        /// Velocities `v̇, v̇', u̇`.
        qd: BeamField,
    },
    /// The rod's elastic coordinates and velocities as they are (any body).
    Coordinates {
        /// `q_f`.
        q_f: Vec<f64>,
        /// `q̇_f`.
        qd_f: Vec<f64>,
    },
}

/// Initial conditions of the slider-crank at `t = 0` (crank angle 0, crank
/// speed [`CRANK_SPEED`]). They are made consistent by the system's initial
/// projection ([`System::initial_state`]): least-norm corrections onto the
/// position and velocity constraints.
#[derive(Clone, Debug)]
pub struct SliderCrankInit {
    /// Rod angle `φ₂` (rad; frame x axis from the crank pin to the slider pin).
    pub rod_angle: f64,
    /// Rod angular velocity `φ̇₂` (rad/s).
    pub rod_rate: f64,
    /// Slider position on the x axis (m).
    pub slider_x: f64,
    /// Slider velocity (m/s).
    pub slider_v: f64,
    /// Elastic state of the rod.
    pub elastic: RodElastic,
}

impl SliderCrankInit {
    /// The rigid mechanism at `θ = 0`: rod along +x, `φ̇₂ = −(l_c/l_r) θ̇`,
    /// slider at `l_c + l_r` at rest, rod undeformed.
    pub fn rigid() -> Self {
        Self {
            rod_angle: 0.0,
            rod_rate: -CRANK_LENGTH / ROD_LENGTH * CRANK_SPEED,
            slider_x: CRANK_LENGTH + ROD_LENGTH,
            slider_v: 0.0,
            elastic: RodElastic::Undeformed,
        }
    }
}

impl Default for SliderCrankInit {
    fn default() -> Self {
        Self::rigid()
    }
}

/// Build the slider-crank with `rod` (planar beam of length 0.3 m and an even
/// number of elements), starting as the rigid mechanism ([`SliderCrankInit::rigid`]).
pub fn slider_crank(rod: Box<dyn FlexBody>) -> Result<SliderCrank> {
    slider_crank_with(rod, &SliderCrankInit::rigid())
}

/// The slider-crank with `rod` from the initial conditions `init`.
///
/// The rod may be any planar body whose elastic-coordinate labels name beam
/// nodes (`kind_node`): the crank pin is node 0 (the frame origin), the slider
/// pin node `N` at `x = 0.3 m`, and `N` must be even so that node `N/2` is the
/// midpoint. With a `pinned` reference the frame is the chord frame and `uy`
/// of the middle node is the midpoint deflection.
pub fn slider_crank_with(rod: Box<dyn FlexBody>, init: &SliderCrankInit) -> Result<SliderCrank> {
    if rod.dim() != 2 {
        return Err(Error::InvalidInput(
            "the slider-crank is planar: the rod must be a dim-2 body".into(),
        ));
    }
    let labels = rod.dof_labels();
    let n =
        last_node(&labels).ok_or_else(|| Error::InvalidInput("rod has no node labels".into()))?;
    if n % 2 != 0 {
        return Err(Error::InvalidInput(format!(
            "the rod needs an even number of elements (has {n})"
        )));
    }
    let mid = dof_index(&labels, &format!("uy_{}", n / 2))
        .ok_or_else(|| Error::InvalidInput("rod has no middle-node uy".into()))?;
    let (q_f, qd_f) = match &init.elastic {
        RodElastic::Undeformed => (None, None),
        RodElastic::Fields { q, qd } => (
            Some(q.nodal_coordinates(&labels, ROD_LENGTH)?),
            Some(qd.nodal_coordinates(&labels, ROD_LENGTH)?),
        ),
        RodElastic::Coordinates { q_f, qd_f } => (Some(q_f.clone()), Some(qd_f.clone())),
    };
    let (lc, lr, w) = (CRANK_LENGTH, ROD_LENGTH, CRANK_SPEED);
    let mut sys = System::planar();
    let j_pivot = 0.002727;
    let m_crank = 0.36;
    let crank = RigidBody::planar(
        m_crank,
        j_pivot - m_crank * (lc / 2.0) * (lc / 2.0),
        Vector2::new(lc / 2.0, 0.0),
    );
    let c = sys.add_body(Box::new(crank), Pose::planar(0.0, 0.0, 0.0))?;
    let r = sys.add_body(rod, Pose::planar(lc, 0.0, init.rod_angle))?;
    let s = sys.add_body(
        Box::new(RigidBody::planar(0.075552, 1e-6, Vector2::zeros())),
        Pose::planar(init.slider_x, 0.0, 0.0),
    )?;
    // Crank: pivot at the origin, angle 150 t.
    sys.prescribe_coordinate(c, 0, Driver::constant(0.0))?;
    sys.prescribe_coordinate(c, 1, Driver::constant(0.0))?;
    sys.prescribe_coordinate(c, 2, Driver::linear(0.0, w))?;
    sys.revolute(
        Marker::at(c, Vector3::new(lc, 0.0, 0.0)),
        Marker::node(r, Vector3::zeros(), &labels, 0),
    )?;
    sys.revolute(
        Marker::node(r, Vector3::new(lr, 0.0, 0.0), &labels, n),
        Marker::origin(s),
    )?;
    // Slider on the x axis, not turning.
    sys.prescribe_coordinate(s, 1, Driver::constant(0.0))?;
    sys.prescribe_coordinate(s, 2, Driver::constant(0.0))?;
    // Velocities at θ = 0: crank tip (the rod origin) moves with l_c θ̇ along +y.
    sys.set_velocity(c, Vector3::zeros(), Vector3::new(0.0, 0.0, w))?;
    sys.set_velocity(
        r,
        Vector3::new(0.0, lc * w, 0.0),
        Vector3::new(0.0, 0.0, init.rod_rate),
    )?;
    sys.set_velocity(s, Vector3::new(init.slider_v, 0.0, 0.0), Vector3::zeros())?;
    if let (Some(q_f), Some(qd_f)) = (q_f, qd_f) {
        sys.set_elastic(r, &q_f, &qd_f)?;
    }
    let mid_uy = sys.offset(r) + sys.body(r).f_offset() + mid;
    Ok(SliderCrank {
        system: sys,
        crank: c,
        rod: r,
        slider: s,
        mid_uy,
    })
}

/// Samples of a slider-crank run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SliderCrankRun {
    /// Times (s).
    pub t: Vec<f64>,
    /// Rod angle `φ₂` (rad).
    pub rod_angle: Vec<f64>,
    /// Slider position `x₃` (m).
    pub slider_x: Vec<f64>,
    /// Midpoint deflection (m): `uy` of the rod's middle node.
    pub mid_deflection: Vec<f64>,
    /// Its rate (m/s).
    pub mid_velocity: Vec<f64>,
    /// The rod's elastic coordinates at the end.
    pub rod_q_f: Vec<f64>,
    /// Their rates at the end.
    pub rod_qd_f: Vec<f64>,
    /// The final state of the system.
    pub last: Option<crate::system::State>,
}

impl SliderCrank {
    /// Run to `t_end` with step `dt`: `(t, midpoint deflection)` samples.
    pub fn run(
        &self,
        t_end: f64,
        dt: f64,
        integrator: &Integrator,
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        let (mut t, mut y) = (Vec::new(), Vec::new());
        self.system.simulate(t_end, dt, integrator, |v| {
            t.push(v.state.t);
            y.push(v.state.q[self.mid_uy]);
            ControlFlow::Continue(())
        })?;
        Ok((t, y))
    }

    /// Run to `t_end` with step `dt`, sampling rod angle, slider position and
    /// the midpoint deflection and its rate at every step.
    pub fn run_samples(
        &self,
        t_end: f64,
        dt: f64,
        integrator: &Integrator,
    ) -> Result<SliderCrankRun> {
        let mut out = SliderCrankRun::default();
        let (ir, is) = (
            self.system.offset(self.rod) + 2,
            self.system.offset(self.slider),
        );
        let summary = self.system.simulate(t_end, dt, integrator, |v| {
            let (q, qd) = (&v.state.q, &v.state.v);
            out.t.push(v.state.t);
            out.rod_angle.push(q[ir]);
            out.slider_x.push(q[is]);
            out.mid_deflection.push(q[self.mid_uy]);
            out.mid_velocity.push(qd[self.mid_uy]);
            ControlFlow::Continue(())
        })?;
        let rod = self.system.body(self.rod);
        let (fo, nf) = (self.system.offset(self.rod) + rod.f_offset(), rod.nf());
        out.rod_q_f = summary.last.q.as_slice()[fo..fo + nf].to_vec();
        out.rod_qd_f = summary.last.v.as_slice()[fo..fo + nf].to_vec();
        out.last = Some(summary.last);
        Ok(out)
    }
}
