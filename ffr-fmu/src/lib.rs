//! A scene as an FMI 2.0 Co-Simulation unit (FMU).
//!
//! `ffr fmu SCENE.toml --out NAME.fmu` writes the FMU: `modelDescription.xml`
//! ([`description::Manifest::model_description`]), this crate's shared
//! library as `binaries/linux64/NAME.so` (built by `cargo build --release -p
//! ffr-fmu`), and the scene with every file it reads under `resources/`,
//! with the manifest [`description::MANIFEST`] the library reads at
//! instantiation. The library ([`ffi`]) implements the FMI 2.0
//! Co-Simulation functions over [`ffr::scene::Simulation`]
//! ([`instance::Instance`]): whole scene steps per `fmi2DoStep`, inputs held
//! between communication points, exact `fmi2GetFMUstate` /
//! `fmi2SetFMUstate`, a failed step as `fmi2Discard` with the run's
//! message. See docs/in-the-loop.md ("FMU").

pub mod description;
pub mod ffi;
pub mod instance;

#[cfg(test)]
mod tests;
