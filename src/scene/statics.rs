//! The static equilibrium of a scene (`ffr static`, `scene.static()` in
//! Python): its loads at `t = 0` — gravity, point forces, motor torques —
//! with prescribed coordinates and drives held at their `t = 0` values,
//! solved by the runtime's load-stepped Newton ([`crate::runtime::statics`],
//! the solver `linearize --at static` and the Campbell steady state use),
//! and the scene's outputs at that state as `ffr run` evaluates them.
//!
//! At the static state velocities are zero, so are the kinetic energy,
//! the work of the applied loads and the dissipated energy (the values of
//! a run's first row, `t = 0`); positions, deflections, angles (in
//! `(−π, π]`) and the elastic, gravity and spring energies are those of
//! the state.

use super::model::Scene;
use super::run::Recorder;
use crate::runtime::linear::SteadyMotion;
use crate::runtime::statics::{equilibrium_interruptible, Equilibrium};
pub use crate::runtime::statics::{StaticOptions, MAX_STEPS};
use crate::runtime::{Assembly, Interrupt, State};

/// A scene's static equilibrium and its outputs.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneStatic {
    /// The output names, in the scene's order (the columns of a run after `t`).
    pub names: Vec<String>,
    /// The value of each output at the static state.
    pub values: Vec<f64>,
    /// Load increments used.
    pub steps: usize,
    /// Newton iterations, in all.
    pub iterations: usize,
    /// The state (`t = 0`, `q̇ = q̈ = 0`, the multipliers: the reactions).
    pub state: State,
    /// The largest elastic section rotation of each flexible body there.
    pub rotations: Vec<super::frames::BodyRotation>,
    /// Warnings about a valid result outside the model's accuracy
    /// ([`super::frames::warnings`]).
    pub warnings: Vec<String>,
}

/// The static equilibrium of `scene` under its loads at `t = 0`, from its
/// consistent initial state, with the load stepping of `options`, and its
/// outputs there. No equilibrium, a mechanism, an unstable equilibrium or
/// an output that is not finite is an error saying so.
pub fn solve(scene: &Scene, options: &StaticOptions) -> crate::Result<SceneStatic> {
    solve_interruptible(scene, options, Interrupt::NEVER)
}

/// [`solve`], polling `interrupt` at every Newton iteration: when it asks
/// to stop, [`crate::runtime::Error::Interrupted`].
pub fn solve_interruptible(
    scene: &Scene,
    options: &StaticOptions,
    interrupt: Interrupt<'_>,
) -> crate::Result<SceneStatic> {
    let sys = &scene.system;
    let start = sys.initial_state(0.0)?;
    let Equilibrium {
        state,
        steps,
        iterations,
    } = equilibrium_interruptible(sys, 0.0, &start, SteadyMotion::Rest, options, interrupt)?;
    let mut asm = Assembly::new(sys)?;
    let mut recorder = Recorder::new(scene);
    let mut values = vec![f64::NAN; scene.outputs.len()];
    recorder.record(scene, &mut asm, &state.q, &state.v, (0.0, 0.0), |i, v| {
        values[i] = v
    });
    let names: Vec<String> = scene.outputs.iter().map(|o| o.name.clone()).collect();
    if let Some((n, v)) = names.iter().zip(&values).find(|(_, v)| !v.is_finite()) {
        return Err(format!(
            "output `{n}` is {v} at the static equilibrium, not a finite number: the result is not valid"
        )
        .into());
    }
    let raw = crate::runtime::monitor::elastic_rotations(sys, 0.0, &state.q)?;
    let rotations = super::frames::body_rotations(scene, &raw);
    let warnings = super::frames::warnings(scene, &rotations);
    Ok(SceneStatic {
        names,
        values,
        steps,
        iterations,
        state,
        rotations,
        warnings,
    })
}
