//! `[[outputs]]`: the columns, with their markers looked up.

use super::marker;
use crate::runtime::nalgebra::Vector3;
use crate::runtime::spec::scene::OutputSpec;
use crate::runtime::{Body, Marker, System};
use crate::scene::model::Output;
use crate::SceneError;

pub(super) fn output(sys: &System<Box<dyn Body>>, o: &OutputSpec) -> Result<Output, SceneError> {
    let m = match &o.at {
        Some(m) => marker(sys, m)?,
        // Energies are the whole system's.
        None => Marker::ground(Vector3::zeros()),
    };
    let relative_to = o.relative_to.as_ref().map(|a| marker(sys, a)).transpose()?;
    Ok(Output {
        name: o.name.clone(),
        kind: o.kind,
        marker: m,
        relative_to,
    })
}
