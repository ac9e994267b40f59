//! A loaded scene, ready to run: its system, integrator, steps and output
//! columns, and how its flexible bodies were made.

use crate::runtime::spec::scene::FlexSpec;
pub use crate::runtime::spec::scene::{EnergyPart, OutputKind, MAX_RECORDED_VALUES};
use crate::runtime::{Body, Integrator, Marker, System};

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
    /// The flexible bodies as described (in body order).
    pub flex: Vec<FlexSpec>,
    /// How each body runs: `compiled`, `tape`, `rigid`.
    pub kernels: Vec<(String, String)>,
    /// What the loader folded in or left out (one line each).
    pub notes: Vec<String>,
}
