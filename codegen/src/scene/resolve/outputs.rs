//! `[[outputs]]`: position, deflection, velocity, angle and energy columns.

use super::markers::Markers;
use super::Ctx;
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::RawOutput;
use ffr_spec::scene::{EnergyPart, MarkerPoint, OutputKind, OutputSpec};

pub(super) fn output(c: &Ctx, b: &Markers, o: &RawOutput) -> Result<OutputSpec, Error> {
    let r = o;
    let name = r.name.get_ref().clone();
    if name.is_empty()
        || name
            .chars()
            .any(|ch| ch == ',' || ch == '"' || ch.is_control())
    {
        return Err(c.err(r.name.span(), "an output name must be non-empty without commas, quotes or control characters (it is a CSV column)"));
    }
    let comp = |dflt: Option<usize>| -> Result<usize, Error> {
        match &r.component {
            None => dflt.ok_or_else(|| {
                c.err(
                    o.span(),
                    format!(
                        "output `{}` needs `component = \"x\"`, `\"y\"`{}",
                        q(&name),
                        if b.dim == 3 { " or `\"z\"`" } else { "" }
                    ),
                )
            }),
            Some(s) => match s.get_ref().as_str() {
                "x" => Ok(0),
                "y" => Ok(1),
                "z" if b.dim == 3 => Ok(2),
                other => Err(c.err(
                    s.span(),
                    format!(
                        "`component` is x, y{} — found `{other}`",
                        if b.dim == 3 { " or z" } else { "" },
                        other = q(other)
                    ),
                )),
            },
        }
    };
    let at = || {
        r.at.as_ref().ok_or_else(|| {
            c.err(
                o.span(),
                format!("output `{}` needs `at = \"MARKER\"`", q(&name)),
            )
        })
    };
    let kind = match r.kind.get_ref().as_str() {
        "position" => OutputKind::Position(comp(None)?),
        "deflection" => OutputKind::Deflection(comp(None)?),
        "velocity" => OutputKind::Velocity(comp(None)?),
        "angle" => OutputKind::Angle,
        "energy" => {
            let part = match r.component.as_ref().map(|s| s.get_ref().as_str()) {
                None | Some("total") => EnergyPart::Total,
                Some("kinetic") => EnergyPart::Kinetic,
                Some("elastic") => EnergyPart::Elastic,
                Some("gravity") => EnergyPart::Gravity,
                Some("springs") => EnergyPart::Springs,
                Some("work") => EnergyPart::Work,
                Some("dissipated") => EnergyPart::Dissipated,
                Some(other) => return Err(c.err(r.component.as_ref().expect("some").span(), format!("energy `component` is total, kinetic, elastic, gravity, springs, work or dissipated — found `{other}`", other = q(other)))),
            };
            return Ok(OutputSpec { name, kind: OutputKind::Energy(part), at: None, relative_to: None });
        }
        other => return Err(c.err(r.kind.span(), format!("unknown output kind `{other}`: expected position, deflection, angle, velocity or energy", other = q(other)))),
    };
    let marker = b.marker(at()?)?;
    if matches!(kind, OutputKind::Deflection(_)) && matches!(marker.point, MarkerPoint::Ground(_)) {
        return Err(c.err(
            b.at(at()?)?.1,
            "a deflection is measured on a body, not on the ground",
        ));
    }
    let relative_to = match &r.a {
        Some(a) if kind == OutputKind::Angle => Some(b.marker(a)?),
        Some(a) => {
            return Err(c.err(
                a.span(),
                "`a` (a reference marker) is only for angle outputs",
            ))
        }
        None => None,
    };
    Ok(OutputSpec {
        name,
        kind,
        at: Some(marker),
        relative_to,
    })
}
