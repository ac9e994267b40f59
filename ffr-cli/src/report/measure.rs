//! Running one case of the grid: set up the scene with the library's scene
//! modules (not timed), integrate it under a CPU clock, measure its error
//! (not timed), repeat and keep the cheapest run.

use super::grid::{BodyModel, Case, Scene};
use crate::benchmarks::{free_floating, pendulum, slider_crank, spin_up};
use ffr::runtime::nalgebra::Vector3;
use ffr::runtime::spec::Reference;
use ffr::runtime::Body;
use std::ops::ControlFlow;
use std::sync::OnceLock;

pub use crate::clock::{clock_name, thread_cpu_seconds};

/// One successful run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Run {
    /// CPU seconds of the integration.
    pub cpu_s: f64,
    /// The scene's error.
    pub error: f64,
    /// Steps taken.
    pub steps: usize,
}

/// The measurement of a case: the cheapest of its repetitions, or why it failed.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// It ran: minimum CPU time over `reps` repetitions, the error (equal in
    /// every repetition: the runs are deterministic; checked).
    Point {
        /// Minimum CPU seconds.
        cpu_s: f64,
        /// Error.
        error: f64,
        /// Repetitions.
        reps: usize,
        /// Steps of one run.
        steps: usize,
    },
    /// It did not run to the end or gave no usable error.
    Failed {
        /// Why (the runtime's or the scene's message).
        reason: String,
        /// Simulated time reached (s), if known.
        t: Option<f64>,
    },
}

/// Why a run failed, and when.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The message.
    pub reason: String,
    /// Simulated time reached (s).
    pub t: Option<f64>,
}

impl Failure {
    fn new(reason: impl Into<String>, t: Option<f64>) -> Self {
        Self {
            reason: reason.into(),
            t,
        }
    }
}

impl<E: std::fmt::Display> From<E> for Failure {
    fn from(e: E) -> Self {
        Failure::new(e.to_string(), None)
    }
}

/// Run `case` up to `reps` times (at least once), stopping early once the
/// repetitions used `budget` CPU seconds, and keep the minimum CPU time.
/// Nothing here panics or returns early on a failed run: a failure (also a
/// panic inside the runtime, caught) is an [`Outcome::Failed`].
pub fn measure(case: &Case, reps: usize, budget: f64) -> Outcome {
    let mut best: Option<Run> = None;
    let mut used = 0.0;
    let mut n = 0;
    while n < reps.max(1) {
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run_once(case)))
            .unwrap_or_else(|p| {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "unknown panic".into());
                Err(Failure::new(format!("panicked: {msg}"), None))
            });
        match r {
            Err(f) => {
                return Outcome::Failed {
                    reason: f.reason,
                    t: f.t,
                }
            }
            Ok(run) => {
                if let Some(b) = &best {
                    if run.error.to_bits() != b.error.to_bits() {
                        return Outcome::Failed {
                            reason: format!(
                                "not reproducible: error {:e} in one repetition, {:e} in another",
                                b.error, run.error
                            ),
                            t: None,
                        };
                    }
                }
                used += run.cpu_s;
                n += 1;
                if best.is_none_or(|b| run.cpu_s < b.cpu_s) {
                    best = Some(run);
                }
            }
        }
        if used >= budget {
            break;
        }
    }
    let b = best.expect("at least one repetition ran");
    Outcome::Point {
        cpu_s: b.cpu_s,
        error: b.error,
        reps: n,
        steps: b.steps,
    }
}

/// One run of `case`: set-up, timed integration, error.
pub fn run_once(case: &Case) -> Result<Run, Failure> {
    let r = match case.scene {
        Scene::SpinUp4 => run_spin_up(case, 4.0),
        Scene::SpinUp10 => run_spin_up(case, 10.0),
        Scene::SpinUp3d => run_spin_up(case, 4.0),
        Scene::SliderCrank => run_slider_crank(case),
        Scene::Pendulum => run_pendulum(case),
        Scene::FreeFloating => run_free_floating(case),
    }?;
    if !r.error.is_finite() || r.error < 0.0 {
        return Err(Failure::new(
            format!("the error is {} (not a finite number)", r.error),
            None,
        ));
    }
    if !(r.cpu_s.is_finite() && r.cpu_s > 0.0) {
        return Err(Failure::new(
            format!("the CPU clock gave {} s", r.cpu_s),
            None,
        ));
    }
    Ok(r)
}

fn reached(summary_t: f64, t_end: f64, dt: f64) -> Result<(), Failure> {
    if (summary_t - t_end).abs() > 1e-6 * dt.max(t_end) {
        return Err(Failure::new(
            format!("the run stopped at t = {summary_t} s before t_end = {t_end} s"),
            Some(summary_t),
        ));
    }
    Ok(())
}

fn not_body(case: &Case) -> Result<(), Failure> {
    not_segmented(case)?;
    if case.method.body != BodyModel::Beam {
        return Err(Failure::new(
            format!("{} has no such body", case.scene),
            None,
        ));
    }
    if case.method.general && !matches!(case.scene, Scene::SpinUp4 | Scene::SpinUp10) {
        return Err(Failure::new(
            "the general-vs-specialized choice applies to the planar spin-ups only",
            None,
        ));
    }
    Ok(())
}

fn not_segmented(case: &Case) -> Result<(), Failure> {
    if case.method.segments != 1 {
        return Err(Failure::new(
            format!(
                "segments are measured on the spin-ups only, not on {}",
                case.scene
            ),
            None,
        ));
    }
    Ok(())
}

/// The geometrically exact reference of a spin-up scene, parsed once.
fn reference(scene: Scene) -> Option<&'static crate::reference::Reference> {
    static R4: OnceLock<Option<crate::reference::Reference>> = OnceLock::new();
    static R10: OnceLock<Option<crate::reference::Reference>> = OnceLock::new();
    static R3D: OnceLock<Option<crate::reference::Reference>> = OnceLock::new();
    match scene {
        Scene::SpinUp4 => R4.get_or_init(|| crate::reference::spin_up(4.0)),
        Scene::SpinUp10 => R10.get_or_init(|| crate::reference::spin_up(10.0)),
        Scene::SpinUp3d => R3D.get_or_init(|| Some(crate::reference::spin_up_gravity())),
        _ => return None,
    }
    .as_ref()
}

/// Gravity along the spin axis in [`Scene::SpinUp3d`] (m/s², along −z).
pub const SPIN_UP_3D_GRAVITY: f64 = 9.81;

/// The spatial spin-up's beam: the KRB data with the torsion data of the
/// thin tube of the same `A` and `I` (as `scenes/spin_up_gravity.toml` and
/// the Exudyn reference; `bench/reference/README.md`).
pub fn spin_up_3d_params() -> ffr::runtime::spec::Params {
    ffr::runtime::spec::Params {
        g: 2.5922e10,
        j: 1.64378e-8,
        ..spin_up::KRB
    }
}

/// Spin-up: error of the transverse tip history in the hub frame against
/// the Exudyn reference, `max_k |y − y_ref| / max_k |y_ref|` over the run's
/// step times in `[0, 20 s]` (every step is an output time). In space
/// ([`Scene::SpinUp3d`]) the larger of that error for the tip's two
/// transverse components, `tip_v` (hub y, in the rotation plane) and
/// `tip_w` (hub z, along the spin axis), each against its own reference peak.
fn run_spin_up(case: &Case, omega: f64) -> Result<Run, Failure> {
    if !matches!(case.method.body, BodyModel::Beam | BodyModel::Modal) {
        return Err(Failure::new(
            "the spin-up has only the beam body and its modal reductions",
            None,
        ));
    }
    let t_end = case.scene.t_end();
    let spatial = case.scene == Scene::SpinUp3d;
    let reference = reference(case.scene)
        .ok_or_else(|| Failure::new(format!("no reference history for {}", case.scene), None))?;
    let m = &case.method;
    if spatial && m.general {
        return Err(Failure::new(
            "the general-vs-specialized choice applies to the planar spin-ups only",
            None,
        ));
    }
    let mut cfg = spin_up::SpinUp::new(omega);
    if spatial {
        cfg.spatial = true;
        cfg.gravity = SPIN_UP_3D_GRAVITY;
        cfg.params = spin_up_3d_params();
    }
    cfg.t_end = t_end;
    cfg.dt = case.dt;
    cfg.elements = case.elements;
    cfg.integrator = m.scheme.integrator(case.scene);
    cfg.stiffening = m.stiffening;
    cfg.formalism = m.formalism;
    cfg.force_tape = m.tape;
    cfg.general = m.general;
    cfg.segments = m.segments;
    if m.segments == 0 || !case.elements.is_multiple_of(m.segments) {
        return Err(Failure::new(
            format!(
                "{} segments do not divide {} elements",
                m.segments, case.elements
            ),
            None,
        ));
    }
    if m.body == BodyModel::Modal {
        cfg.elements = super::grid::MODAL_MESH;
        cfg.modal = Some(ffr::modal::ModalSettings::truncation(case.elements));
    }
    let r = spin_up::run(&cfg)?;
    if let Some(d) = r.diverged {
        return Err(Failure::new(
            format!("diverged at t = {:.3} s: {}", d.t, d.reason),
            Some(d.t),
        ));
    }
    let last = r.t.last().copied().unwrap_or(0.0);
    reached(last, t_end, case.dt)?;
    let outside = || Failure::new("the run's times are outside the reference's", None);
    let error = if spatial {
        let (ev, _) = reference
            .error("tip_v", &r.t, &r.tip_transverse, t_end)
            .ok_or_else(outside)?;
        let (ew, _) = reference
            .error("tip_w", &r.t, &r.tip_lateral, t_end)
            .ok_or_else(outside)?;
        ev.max(ew)
    } else {
        reference
            .error("tip_transverse", &r.t, &r.tip_transverse, t_end)
            .ok_or_else(outside)?
            .0
    };
    Ok(Run {
        cpu_s: r.cpu,
        error,
        steps: r.steps,
    })
}

/// A drift-measured run's outcome: the integrator's error (at `t_last`), a
/// divergence the observer stopped at, or a run short of `t_end` is a
/// failure; else the run with its CPU time and largest drift.
fn finish(
    res: ffr::runtime::Result<ffr::runtime::Summary>,
    diverged: Option<Failure>,
    t_last: f64,
    t_end: f64,
    dt: f64,
    cpu_s: f64,
    drift: f64,
) -> Result<Run, Failure> {
    let summary = res.map_err(|e| Failure::new(e.to_string(), Some(t_last)))?;
    if let Some(d) = diverged {
        return Err(d);
    }
    reached(summary.last.t, t_end, dt)?;
    Ok(Run {
        cpu_s,
        error: drift,
        steps: summary.steps,
    })
}

/// Slider crank: relative error of the rod's first lateral sine-mode
/// amplitude at `t = 0.1 s` against the published `q₁` (the quantity the
/// benchmark's `q₁` is; for Simeon's rod its own `q₁`).
fn run_slider_crank(case: &Case) -> Result<Run, Failure> {
    use slider_crank::{
        beam_init, beam_rod, simeon_init, simeon_rod, sine_amplitude, slider_crank_guided,
        SliderGuide, PUBLISHED, SIMEON_INIT, T_END,
    };
    not_segmented(case)?;
    let m = &case.method;
    if m.general {
        return Err(Failure::new(
            "the general-vs-specialized choice applies to the spin-up only",
            None,
        ));
    }
    let (rod, init): (Box<dyn Body>, _) = match m.body {
        BodyModel::Beam => {
            let mut spec = beam_rod(case.elements)
                .formalism(m.formalism)
                .stiffening(m.stiffening);
            spec.force_tape = m.tape;
            (Box::new(spec.body()?), beam_init(&SIMEON_INIT))
        }
        BodyModel::SimeonRod => (simeon_rod(15.0, false), simeon_init(&SIMEON_INIT)),
        BodyModel::Modal => {
            return Err(Failure::new(
                "modal bodies are measured on the spin-up only",
                None,
            ))
        }
    };
    let sc = slider_crank_guided(rod, &init, SliderGuide::Prismatic)?;
    let labels = sc.system.body(sc.rod).layout().labels.clone();
    let entry = sc.system.body_entry(sc.rod);
    let (fo, nf) = (entry.f_offset(), entry.nf);
    let integrator = m.scheme.integrator(case.scene);
    let c0 = thread_cpu_seconds();
    let res = sc
        .system
        .simulate(T_END, case.dt, &integrator, |_| ControlFlow::Continue(()));
    let cpu_s = thread_cpu_seconds() - c0;
    let summary = res?;
    reached(summary.last.t, T_END, case.dt)?;
    let q_f = &summary.last.q[fo..fo + nf];
    let a1 = match m.body {
        BodyModel::Beam => sine_amplitude(&labels, q_f, 1),
        BodyModel::SimeonRod | BodyModel::Modal => q_f[0],
    };
    Ok(Run {
        cpu_s,
        error: (a1 - PUBLISHED.q[0]).abs() / PUBLISHED.q[0].abs(),
        steps: summary.steps,
    })
}

/// Number of samples of a conserved quantity over a run (every
/// `t_end / SAMPLES`, and at the end).
pub const SAMPLES: usize = 200;

fn stride(t_end: f64, dt: f64) -> usize {
    ((t_end / SAMPLES as f64 / dt).round() as usize).max(1)
}

/// Pendulum: energy drift `max |E(t) − E(0)| / (m g L / 2)` over `SAMPLES`
/// sample times.
fn run_pendulum(case: &Case) -> Result<Run, Failure> {
    not_body(case)?;
    let m = &case.method;
    let t_end = case.scene.t_end();
    let mut spec = pendulum::beam_spec(
        pendulum::Beam::Beam2,
        case.elements,
        Reference::Clamped,
        pendulum::ALUMINIUM_BAR,
    );
    spec.options.formalism = m.formalism;
    spec.options.stiffening = m.stiffening;
    spec.force_tape = m.tape;
    let (sys, b) = pendulum::scene(spec.body()?)?;
    let body = sys.body(b);
    let length = body
        .layout()
        .length
        .ok_or_else(|| Failure::new("the pendulum needs a beam body", None))?;
    let e_ref = body.invariants().mass * pendulum::GRAVITY * length / 2.0;
    let every = stride(t_end, case.dt);
    let integrator = m.scheme.integrator(case.scene);
    let (mut e0, mut drift, mut t_last) = (0.0, 0.0f64, 0.0);
    let mut diverged = None;
    let c0 = thread_cpu_seconds();
    let res = sys.simulate(t_end, case.dt, &integrator, |v| {
        t_last = v.state.t;
        if v.step.is_multiple_of(every) || v.state.t > t_end - 0.5 * case.dt {
            let e = v.energy().total();
            if v.step == 0 {
                e0 = e;
            }
            drift = drift.max((e - e0).abs() / e_ref);
            if !(drift <= 1.0) {
                diverged = Some(Failure::new(
                    format!(
                        "diverged: energy error {drift:.3e} of m g L/2 at t = {:.4} s",
                        v.state.t
                    ),
                    Some(v.state.t),
                ));
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    });
    let cpu_s = thread_cpu_seconds() - c0;
    finish(res, diverged, t_last, t_end, case.dt, cpu_s, drift)
}

/// Free-floating body: `max(max_t |p − p₀|/|p₀|, max_t |H − H₀|/|H₀|)` over
/// `SAMPLES` sample times. Scene as [`free_floating::system`] (its initial
/// velocities, the body deformed in its first elastic mode, amplitude
/// 1e-3, and moving in its second), with the modes of the consistent
/// compiled body of the same mesh for every variant, so that lumped, tape
/// and stiffened bodies start from the same state.
fn run_free_floating(case: &Case) -> Result<Run, Failure> {
    not_body(case)?;
    let m = &case.method;
    let t_end = case.scene.t_end();
    let beam = pendulum::Beam::Beam3;
    let amplitude = free_floating::FreeFloatingArgs::default().amplitude;
    let modes = free_floating::elastic_modes(&free_floating::free_body(beam, case.elements, true)?);
    if modes.len() < 2 {
        return Err(Failure::new("the body needs two elastic modes", None));
    }
    let q_f = &modes[0].1 * amplitude;
    let qd_f = &modes[1].1 * (amplitude * modes[1].0);
    let mut spec = free_floating::free_spec(beam, case.elements, true);
    spec.options.formalism = m.formalism;
    spec.options.stiffening = m.stiffening;
    spec.force_tape = m.tape;
    let (sys, _) = free_floating::scene(
        spec.body()?,
        Vector3::new(0.3, -0.1, 0.2),
        Vector3::new(0.5, 1.0, 2.0),
        q_f.as_slice(),
        qd_f.as_slice(),
    )?;
    let every = stride(t_end, case.dt);
    let integrator = m.scheme.integrator(case.scene);
    let (mut p0, mut h0) = (Vector3::zeros(), Vector3::zeros());
    let (mut drift, mut t_last) = (0.0f64, 0.0);
    let mut diverged = None;
    let c0 = thread_cpu_seconds();
    let res = sys.simulate(t_end, case.dt, &integrator, |v| {
        t_last = v.state.t;
        if v.step.is_multiple_of(every) || v.state.t > t_end - 0.5 * case.dt {
            let (p, h) = v.momentum();
            if v.step == 0 {
                (p0, h0) = (p, h);
            }
            let d = ((p - p0).norm() / p0.norm()).max((h - h0).norm() / h0.norm());
            drift = drift.max(d);
            if !(d <= 1.0) {
                diverged = Some(Failure::new(
                    format!("diverged: momentum error {d:.3e} at t = {:.5} s", v.state.t),
                    Some(v.state.t),
                ));
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    });
    let cpu_s = thread_cpu_seconds() - c0;
    finish(res, diverged, t_last, t_end, case.dt, cpu_s, drift)
}
