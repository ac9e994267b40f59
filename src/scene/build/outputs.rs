//! `[[outputs]]`: the columns, with their markers looked up.

use super::marker;
use crate::runtime::nalgebra::Vector3;
use crate::runtime::spec::scene::{MarkerPoint, OutputKind, OutputSpec};
use crate::runtime::{Body, BodyId, Marker, System};
use crate::scene::model::Output;
use crate::SceneError;

pub(super) fn output(sys: &System<Box<dyn Body>>, o: &OutputSpec) -> Result<Output, SceneError> {
    let m = match &o.at {
        Some(m) => marker(sys, m)?,
        // Energies are the whole system's.
        None => Marker::ground(Vector3::zeros()),
    };
    let mut relative_to = o.relative_to.as_ref().map(|a| marker(sys, a)).transpose()?;
    // A deflection on an outboard segment is measured in the body's root
    // frame: from the undeformed point (x, 0, 0) of the root segment's
    // frame, in its axes (the root segment's own deflections are its
    // elastic coordinates, the same thing).
    if let (OutputKind::Deflection(_), Some(MarkerPoint::Axis(b, x))) =
        (o.kind, o.at.as_ref().map(|m| m.point))
    {
        if m.body.is_some_and(|mb| sys.is_outboard_segment(mb)) {
            relative_to = Some(Marker::at(BodyId(b), Vector3::new(x, 0.0, 0.0)));
        }
    }
    Ok(Output {
        name: o.name.clone(),
        kind: o.kind,
        marker: m,
        relative_to,
    })
}
