//! The names a simulation uses: `use ffr::prelude::*;`.

pub use crate::flex_body;
pub use crate::runtime::spec::{Formalism, Params, Reference, Stiffening};
pub use crate::runtime::{
    Body, CompiledBody, Driver, GeneralizedAlpha, Integrator, KernelBody, Marker, Pose, RigidBody,
    Rk4Baumgarte, System, TorqueLaw,
};
pub use crate::{Error, Result};

#[cfg(feature = "scene-files")]
pub use crate::kernels::BeamSpec;
#[cfg(feature = "scene")]
pub use crate::scene::{Scene, SceneRun};
