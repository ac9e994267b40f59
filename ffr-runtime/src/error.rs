//! Errors of model assembly and time integration.

/// Everything that can go wrong building or integrating a system.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A body's data is unusable (sizes, non-finite values, dimension).
    #[error("invalid body {body}: {reason}")]
    InvalidBody {
        /// Index of the body in the system (or in the call).
        body: usize,
        /// What is wrong.
        reason: String,
    },
    /// A joint, force, marker or parameter is unusable.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The (augmented) system matrix could not be factorized.
    #[error("singular {what} at t = {t} s ({detail}): check for redundant or missing constraints and for coordinates without inertia (a `free` reference body, a body with no mass, a user shape whose coordinates carry no mass)")]
    Singular {
        /// Which matrix.
        what: &'static str,
        /// Time.
        t: f64,
        /// Where the factorization failed.
        detail: String,
    },
    /// Newton iterations of an implicit step failed.
    #[error("step {step} at t = {t:.6} s did not converge: residual {residual:.3e} after {iterations} Newton iterations (dt = {dt:e} s); try a smaller step or more numerical damping (lower rho_inf)")]
    NoConvergence {
        /// Step index (0-based: the step starting at `t`).
        step: usize,
        /// Time at the start of the step.
        t: f64,
        /// Norm of the scaled residual at the last iterate.
        residual: f64,
        /// Newton iterations spent.
        iterations: usize,
        /// The step size.
        dt: f64,
    },
    /// A generalized-α step failed from both Newton starts and after
    /// halving it `halvings` times.
    #[error("step {step} at t = {t:.6} s failed even when restarted from rest and halved {halvings} times (to dt = {dt_min:e} s; there: {why}): {advice}", why = cause.short(), advice = step_failed_advice(cause))]
    StepFailed {
        /// Step index (0-based: the step starting at `t`).
        step: usize,
        /// Time at the start of the step.
        t: f64,
        /// How often the step was halved.
        halvings: u32,
        /// The shortest step tried.
        dt_min: f64,
        /// The failure of the shortest step.
        cause: Box<Error>,
    },
    /// A NaN or infinity appeared in the state.
    #[error("non-finite {what} at step {step}, t = {t:.6} s: the solution diverged; try a smaller step or lower rho_inf")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// Step index.
        step: usize,
        /// Time at the start of the step.
        t: f64,
    },
    /// The equations were evaluated at a state where they are no longer
    /// finite (typically an explicit integrator above its stability limit).
    #[error("non-finite {what} at t = {t:.6} s: the solution diverged; try a smaller step (an explicit integrator needs dt below about 2.8/ω_max of the stiffest elastic mode) or the implicit generalized-α")]
    Unstable {
        /// What was not finite.
        what: &'static str,
        /// Time of the evaluation.
        t: f64,
    },
    /// A joint that the initial state cannot satisfy, or that repeats what
    /// other joints already impose (found when the initial state is made
    /// consistent).
    #[error("{kind} joint #{joint}: {reason}")]
    Joint {
        /// Index of the joint in [`crate::System::constraints`].
        joint: usize,
        /// Its kind (`revolute`, …).
        kind: String,
        /// What is wrong.
        reason: String,
    },
    /// The run was stopped by the divergence monitor: its result would not
    /// be valid although every number is still finite.
    #[error("the run diverged at t = {t:.6} s (step {step}): {reason}")]
    Diverged {
        /// Steps completed.
        step: usize,
        /// Time reached.
        t: f64,
        /// Which bound was exceeded, with the numbers.
        reason: String,
    },
    /// A static equilibrium or steady state was not found
    /// ([`crate::statics`]): the loads have none that load stepping
    /// reaches (a mechanism, a limit or bifurcation point, no
    /// convergence), or the one reached is not unique or not stable.
    #[error("no {what} found at t = {t} s: {reason}")]
    NoEquilibrium {
        /// `static equilibrium` or `steady state`.
        what: &'static str,
        /// The time of the loads and prescribed motions.
        t: f64,
        /// Why, where (the coordinate or joint), and how far the load
        /// stepping got.
        reason: String,
    },
    /// The caller asked the computation to stop ([`crate::Interrupt`]).
    #[error("interrupted")]
    Interrupted,
    /// Initial conditions could not be made consistent with the constraints.
    #[error(
        "inconsistent initial conditions: constraint violation {violation:.3e} after projection"
    )]
    Inconsistent {
        /// Remaining `‖Φ‖`.
        violation: f64,
    },
}

impl Error {
    /// What went wrong in a few words (no advice).
    pub fn short(&self) -> String {
        match self {
            Error::NoConvergence {
                residual,
                iterations,
                ..
            } => format!(
                "no convergence, residual {residual:.3e} after {iterations} Newton iterations"
            ),
            Error::NonFinite { what, .. } => format!("non-finite {what}"),
            Error::Singular { what, detail, .. } => format!("singular {what} ({detail})"),
            other => other.to_string(),
        }
    }
}

/// What to try after a step failed at its shortest length for `cause`:
/// equations that are not finite even for the shortest step restarted from
/// rest come from values too large for `f64` (a stiffness, gain, load or
/// speed) or a force without bound, which no smaller step mends; other
/// failures may be the step's.
fn step_failed_advice(cause: &Error) -> &'static str {
    match cause {
        Error::NonFinite { .. } | Error::Unstable { .. } => {
            "the equations are not finite even for the shortest step from rest: a value of the scene (a stiffness, gain, load, speed or mass) too large for double precision, or a force that grows without bound; a smaller step does not help"
        }
        _ => {
            "look for a load on a coordinate with almost no inertia, a force that grows without bound, or contradictory constraints, or try a smaller step or lower rho_inf"
        }
    }
}

/// Result with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
