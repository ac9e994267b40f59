//! A loaded scene, ready to run: its system, integrator, steps and output
//! columns, and how its flexible bodies were made.

use crate::codegen::scene::FlexBodyModel;
use crate::kernels::BeamSpec;
use crate::runtime::{Body, Integrator, Marker, System};

/// What an output column records.
#[derive(Clone, Debug, PartialEq)]
pub enum OutputKind {
    /// Global position of a marker (component 0, 1, 2).
    Position(usize),
    /// Elastic displacement of a marker in its body's frame.
    Deflection(usize),
    /// Global velocity of a marker.
    Velocity(usize),
    /// The angle of the marker's x axis in the global x–y plane, or, with a
    /// reference marker `a`, about `a`'s z axis (`atan2(x·y_a, x·x_a)`),
    /// unwrapped along the run.
    Angle,
    /// An energy: total, kinetic, elastic, gravity or springs; or the
    /// work done on the system so far by point forces and motors, or taken
    /// out by dampers (trapezoidal rule over the steps).
    Energy(EnergyPart),
}

/// Which energy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyPart {
    /// `T + V`.
    Total,
    /// `T`.
    Kinetic,
    /// Elastic.
    Elastic,
    /// Gravitational.
    Gravity,
    /// Springs.
    Springs,
    /// `∫ P_applied dt`: work of the point forces and motors since `t = 0`.
    Work,
    /// `∫ P_dissipated dt`: energy taken out by the dampers since `t = 0`.
    Dissipated,
}

/// An output column.
#[derive(Clone, Debug)]
pub struct Output {
    /// Column name.
    pub name: String,
    /// What it records.
    pub kind: OutputKind,
    /// Where (ground for energies).
    pub marker: Marker,
    /// Reference marker of a relative angle.
    pub relative_to: Option<Marker>,
}

/// How a flexible body of a scene is made.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexSpec {
    /// What the generator needs (options, what the scene fixes).
    pub model: FlexBodyModel,
    /// The beam (shape resolved against the scene file, mesh, parameters).
    pub beam: BeamSpec,
}

/// The most values a scene run records (`t` and every output at every
/// step), checked at load time: 2²⁵ values (256 MiB as numbers, about 0.7 GB as CSV text).
pub const MAX_RECORDED_VALUES: usize = 1 << 25;

/// A loaded scene, ready to run.
pub struct Scene {
    /// The file it came from.
    pub origin: String,
    /// Its description line, if any.
    pub description: Option<String>,
    /// The system.
    pub system: System<Box<dyn Body>>,
    /// End time (s).
    pub t_end: f64,
    /// Step (s).
    pub dt: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Output columns (after `t`).
    pub outputs: Vec<Output>,
    /// The flexible bodies as built.
    pub flex: Vec<FlexSpec>,
    /// How each body runs: `compiled`, `tape`, `rigid`.
    pub kernels: Vec<(String, String)>,
    /// What the loader folded in or left out (one line each).
    pub notes: Vec<String>,
}
