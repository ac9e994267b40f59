//! Running a scene: the outputs recorded at every step.

use super::model::{EnergyPart, OutputKind, Scene};
use super::simulation::Stepping;
use crate::runtime::marker::MarkerKin;
use crate::runtime::{Assembly, Body, Interrupt};
use std::ops::ControlFlow;

/// The recorded outputs of a scene run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneRun {
    /// Column names after `t`.
    pub names: Vec<String>,
    /// Times.
    pub t: Vec<f64>,
    /// One vector per output.
    pub columns: Vec<Vec<f64>>,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Iteration-matrix factorizations.
    pub jacobians: usize,
    /// Steps whose Newton iteration was started again from rest.
    pub restarts: usize,
    /// Steps done in halves.
    pub splits: usize,
    /// Wall time of the simulation (s).
    pub wall: f64,
    /// Why the run stopped early (an integrator failure), if it did.
    pub failed: Option<String>,
    /// The final state (coordinates, velocities, accelerations, multipliers)
    /// of a run that reached its end, for checks beyond the output columns.
    pub last: Option<crate::runtime::State>,
    /// The largest elastic section rotation of each flexible body over the
    /// run (of a run that reached its end; [`super::frames`]).
    pub rotations: Vec<super::frames::BodyRotation>,
    /// Warnings about a valid result outside the model's accuracy: a body
    /// that turned past what one floating frame describes
    /// ([`super::frames::warnings`]).
    pub warnings: Vec<String>,
}

/// Options of [`run_with`] beyond recording the outputs.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct RunOptions {
    /// Write a ParaView time series while running (feature `vtk`; see
    /// [`super::vtk`]): `DIR/<scene>.pvd` and one `.vtp` per written
    /// sample, `<scene>` the scene file's name without extension.
    #[cfg(feature = "vtk")]
    pub vtk: Option<super::vtk::VtkOptions>,
}

/// Run `scene` to its end time, recording every output at every step.
pub fn run(scene: &Scene) -> Result<SceneRun, crate::runtime::Error> {
    run_observed(scene, Interrupt::NEVER, |_, _| ControlFlow::Continue(()))
}

/// [`run`] with `options`: with `vtk`, the time series is checked before
/// the run (nothing is run if it cannot be written) and written during it;
/// its `.pvd` lists the samples written, also of a run that stopped early
/// ([`SceneRun::failed`]). A sample to write whose coordinates are not all
/// finite stops the run with an error (the `.pvd` lists the files before it).
pub fn run_with(scene: &Scene, options: &RunOptions) -> crate::Result<SceneRun> {
    run_interruptible(scene, options, Interrupt::NEVER)
}

/// [`run_with`], polling `interrupt` after every step: when it asks to
/// stop, [`crate::runtime::Error::Interrupted`] (a VTK series keeps the
/// files written so far, listed in its `.pvd`).
pub fn run_interruptible(
    scene: &Scene,
    options: &RunOptions,
    interrupt: Interrupt<'_>,
) -> crate::Result<SceneRun> {
    #[cfg(feature = "vtk")]
    if let Some(v) = &options.vtk {
        let mut series =
            super::vtk::VtkSeries::new(scene, v, &super::vtk::scene_stem(&scene.origin))?;
        let mut failure = None;
        let r = run_observed(scene, interrupt, |t, q| match series.observe(t, q) {
            Ok(()) => ControlFlow::Continue(()),
            Err(e) => {
                failure = Some(e);
                ControlFlow::Break(())
            }
        });
        let r = match r {
            Err(e @ crate::runtime::Error::Interrupted) => {
                // The .pvd of the files written so far (best effort).
                let _ = series.finish();
                return Err(e.into());
            }
            r => r?,
        };
        if let Some(e) = failure {
            // The .pvd of the files written before (best effort: the
            // error reported is the one that stopped the series).
            let _ = series.finish();
            return Err(e);
        }
        series.finish()?;
        return Ok(r);
    }
    let _ = options;
    Ok(run_observed(scene, interrupt, |_, _| {
        ControlFlow::Continue(())
    })?)
}

/// [`run`], calling `observe(t, q)` at every recorded sample after its
/// outputs (a `Break` stops the run there) and then `interrupt` (which
/// stops it with [`crate::runtime::Error::Interrupted`]).
fn run_observed(
    scene: &Scene,
    interrupt: Interrupt<'_>,
    mut observe: impl FnMut(f64, &[f64]) -> ControlFlow<()>,
) -> Result<SceneRun, crate::runtime::Error> {
    use crate::runtime::integrator::{step_count, step_length};
    // Reserve for the whole run only up to a bound: the loader checked that
    // the recorded values fit (`super::load::MAX_RECORDED_VALUES`), and a
    // run that stops early should not have taken the memory of its end.
    let n = ((scene.t_end / scene.dt).ceil() as usize + 2).min(1 << 16);
    let mut out = SceneRun {
        names: scene.outputs.iter().map(|o| o.name.clone()).collect(),
        t: Vec::with_capacity(n),
        columns: scene
            .outputs
            .iter()
            .map(|_| Vec::with_capacity(n))
            .collect(),
        ..SceneRun::default()
    };
    let start = std::time::Instant::now();
    // Steps, Newton iterations and iteration matrices of the samples
    // recorded (a failed run reports how far it got).
    let (mut steps, mut iterations, mut jacobians) = (0, 0, 0);
    let mut interrupted = false;
    let mut sample = |s: &Stepping<'_>, out: &mut SceneRun| {
        let c = s.stepper().counters();
        steps = c.steps;
        iterations = c.newton_iterations;
        jacobians = c.jacobians;
        let state = s.stepper().state();
        out.t.push(state.t);
        for (col, v) in out.columns.iter_mut().zip(s.outputs()) {
            col.push(*v);
        }
        if observe(state.t, &state.q).is_break() {
            return ControlFlow::Break(());
        }
        if interrupt.requested() {
            interrupted = true;
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    };
    let res = (|| {
        crate::runtime::integrator::check_settings(scene.t_end, scene.dt, &scene.integrator)?;
        let n_steps = step_count(scene.t_end, scene.dt)?;
        let mut s = Stepping::new(scene)?;
        if sample(&s, &mut out).is_continue() {
            for _ in 0..n_steps {
                s.step(step_length(s.stepper().state().t, scene.t_end, scene.dt))?;
                if sample(&s, &mut out).is_break() {
                    break;
                }
            }
        }
        Ok(s.into_stepper().finish())
    })();
    if interrupted {
        return Err(crate::runtime::Error::Interrupted);
    }
    out.wall = start.elapsed().as_secs_f64();
    match res {
        Ok(s) => {
            out.steps = s.steps;
            out.newton_iterations = s.newton_iterations;
            out.jacobians = s.jacobians;
            out.restarts = s.restarts;
            out.splits = s.splits;
            out.last = Some(s.last);
            out.rotations = super::frames::body_rotations(scene, &s.rotations);
            out.warnings = super::frames::warnings(scene, &out.rotations);
        }
        Err(e) => match e {
            crate::runtime::Error::Diverged { .. }
            | crate::runtime::Error::NoConvergence { .. }
            | crate::runtime::Error::NonFinite { .. }
            | crate::runtime::Error::Unstable { .. }
            | crate::runtime::Error::Singular { .. }
            | crate::runtime::Error::StepFailed { .. } => {
                out.steps = steps;
                out.newton_iterations = iterations;
                out.jacobians = jacobians;
                out.failed = Some(e.to_string());
            }
            other => return Err(other),
        },
    }
    Ok(out)
}

/// The evaluation of a scene's outputs at a state (a run's samples, a
/// static state): marker workspaces, and each angle's last value so that
/// an angle output is continuous over a run (unwrapped by whole turns; the
/// first value in `(−π, π]`).
pub(super) struct Recorder {
    kins: Vec<(MarkerKin, Option<MarkerKin>)>,
    pub(super) prev_angle: Vec<f64>,
}

impl Recorder {
    /// The workspaces of `scene`'s outputs (allocates once).
    pub(super) fn new(scene: &Scene) -> Self {
        let sys = &scene.system;
        Self {
            kins: scene
                .outputs
                .iter()
                .map(|o| {
                    (
                        sys.marker_kin(&o.marker),
                        o.relative_to.as_ref().map(|m| sys.marker_kin(m)),
                    )
                })
                .collect(),
            prev_angle: vec![f64::NAN; scene.outputs.len()],
        }
    }

    /// Every output of `scene` at `(q, q̇)` through `push(i, value)`, in
    /// order: positions, velocities, deflections and angles from the
    /// markers, energies from `asm` at the state, the work of the applied
    /// loads and the dissipated energy as given (`(work, dissipated)`, the
    /// integrals so far).
    pub(super) fn record(
        &mut self,
        scene: &Scene,
        asm: &mut Assembly<'_, Box<dyn Body>>,
        q: &[f64],
        qd: &[f64],
        (work, dissipated): (f64, f64),
        mut push: impl FnMut(usize, f64),
    ) {
        let mut energy = None;
        for (i, o) in scene.outputs.iter().enumerate() {
            let value = match &o.kind {
                OutputKind::Energy(EnergyPart::Work) => work,
                OutputKind::Energy(EnergyPart::Dissipated) => dissipated,
                OutputKind::Energy(part) => {
                    let e = *energy.get_or_insert_with(|| asm.energy(q, qd));
                    match part {
                        EnergyPart::Total => e.total(),
                        EnergyPart::Kinetic => e.kinetic,
                        EnergyPart::Elastic => e.elastic,
                        EnergyPart::Gravity => e.gravity,
                        EnergyPart::Springs => e.springs,
                        EnergyPart::Work | EnergyPart::Dissipated => unreachable!(),
                    }
                }
                kind => {
                    let (k, rel) = &mut self.kins[i];
                    k.eval(&o.marker, q);
                    match kind {
                        OutputKind::Position(c) => k.pos[*c],
                        OutputKind::Velocity(c) => k.velocity(qd)[*c],
                        OutputKind::Deflection(c) => match rel {
                            // On an outboard segment: from the undeformed
                            // point in the root segment's frame, in its axes.
                            Some(r) => {
                                r.eval(o.relative_to.as_ref().expect("relative"), q);
                                r.axes[*c].dot(&(k.pos - r.pos))
                            }
                            None => o
                                .marker
                                .shape
                                .entries
                                .iter()
                                .enumerate()
                                .map(|(j, (_, s, _))| s[*c] * q[k.idx[k.n_frame + j]])
                                .sum(),
                        },
                        OutputKind::Angle => {
                            let x = k.axes[0];
                            let raw = match rel {
                                Some(r) => {
                                    r.eval(o.relative_to.as_ref().expect("relative"), q);
                                    x.dot(&r.axes[1]).atan2(x.dot(&r.axes[0]))
                                }
                                None => x.y.atan2(x.x),
                            };
                            let p = self.prev_angle[i];
                            let tau = std::f64::consts::TAU;
                            let a = if p.is_nan() {
                                raw
                            } else {
                                raw + tau * ((p - raw) / tau).round()
                            };
                            self.prev_angle[i] = a;
                            a
                        }
                        OutputKind::Energy(_) => unreachable!(),
                    }
                }
            };
            push(i, value);
        }
    }
}
