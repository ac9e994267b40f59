//! `[[inputs]]`: named inputs a caller sets between steps — a torque in a
//! revolute joint, a force along a direction at a marker, an acceleration
//! added to a joint's drive — with a start value and an optional profile.

use super::forces::force_profile;
use super::markers::Markers;
use super::{fin_f64, vec_n, Ctx};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::{RawInput, RawScene};
use ffr_spec::scene::{InputKind, InputSpec, JointKind, JointSpec, MarkerPoint};

/// Whether `name` is one of the names `linearize` gives joints, forces and
/// drives (`jointN`, `forceN`, `driveN`).
fn reserved(name: &str) -> bool {
    ["joint", "force", "drive"].iter().any(|p| {
        name.strip_prefix(p)
            .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// The scene's inputs, in file order.
pub(super) fn inputs(
    c: &Ctx,
    raw: &RawScene,
    b: &Markers,
    joints: &[JointSpec],
    t_end: f64,
) -> Result<Vec<InputSpec>, Error> {
    let mut out: Vec<InputSpec> = Vec::new();
    for r in &raw.inputs {
        let spec = input(c, r, b, joints, t_end)?;
        if let InputKind::DriveAcceleration { joint } = spec.kind {
            if let Some(other) = out.iter().find(|i| i.kind == spec.kind) {
                return Err(c.err(
                    r.joint.as_ref().map_or(r.kind.span(), |j| j.span()),
                    format!(
                        "input `{}`: joint {}'s drive already has the input `{}`: one drive-acceleration input per drive",
                        q(&spec.name),
                        joint + 1,
                        q(&other.name)
                    ),
                ));
            }
        }
        if out.iter().any(|i| i.name == spec.name) {
            return Err(c.err(
                r.name.span(),
                format!(
                    "a second input named `{}`: input names are unique",
                    q(&spec.name)
                ),
            ));
        }
        out.push(spec);
    }
    Ok(out)
}

fn input(
    c: &Ctx,
    r: &RawInput,
    b: &Markers,
    joints: &[JointSpec],
    t_end: f64,
) -> Result<InputSpec, Error> {
    let name = r.name.get_ref();
    let qn = q(name);
    if name.is_empty() || name.chars().any(char::is_control) {
        return Err(c.err(
            r.name.span(),
            format!("input name `{qn}`: a name is not empty and has no control characters"),
        ));
    }
    if reserved(name) {
        return Err(c.err(
            r.name.span(),
            format!("input name `{qn}` is one of the names `linearize` gives joints, forces and drives (`jointN`, `forceN`, `driveN`): choose another"),
        ));
    }
    let kind_s = r.kind.get_ref().as_str();
    // Keys the kind does not take.
    let refuse = |has: bool, key: &str| -> Result<(), Error> {
        if has {
            Err(c.err(
                r.kind.span(),
                format!("input `{qn}`: a `{}` input takes no `{key}`", q(kind_s)),
            ))
        } else {
            Ok(())
        }
    };
    // Joint `joint = N` (1-based).
    let joint = || -> Result<(usize, &JointSpec), Error> {
        let j = r.joint.as_ref().ok_or_else(|| {
            c.err(
                r.kind.span(),
                format!(
                    "input `{qn}`: a `{kind_s}` input needs `joint = N` (1-based in [[joints]])"
                ),
            )
        })?;
        let n = *j.get_ref();
        if n < 1 || n as u64 > joints.len() as u64 {
            return Err(c.err(
                j.span(),
                format!(
                    "input `{qn}`: `joint = {n}`: the scene's joints are 1 to {} (1-based, in file order)",
                    joints.len()
                ),
            ));
        }
        let k = (n - 1) as usize;
        Ok((k, &joints[k]))
    };
    let kind = match kind_s {
        "torque" => {
            refuse(r.at.is_some(), "at")?;
            refuse(r.direction.is_some(), "direction")?;
            refuse(r.axes.is_some(), "axes")?;
            let (k, j) = joint()?;
            let span = r.joint.as_ref().expect("checked").span();
            if j.kind != JointKind::Revolute {
                return Err(c.err(
                    span,
                    format!(
                        "input `{qn}`: joint {} is a {} joint: a torque input needs a revolute joint",
                        k + 1,
                        format!("{:?}", j.kind).to_lowercase()
                    ),
                ));
            }
            if j.drive.is_some() || j.folds.is_some() {
                return Err(c.err(
                    span,
                    format!(
                        "input `{qn}`: joint {} is driven (its angle is prescribed): a torque in it does nothing; a `drive-acceleration` input changes a drive's motion",
                        k + 1
                    ),
                ));
            }
            InputKind::Torque { joint: k }
        }
        "drive-acceleration" => {
            refuse(r.at.is_some(), "at")?;
            refuse(r.direction.is_some(), "direction")?;
            refuse(r.axes.is_some(), "axes")?;
            let (k, j) = joint()?;
            if j.drive.is_none() {
                return Err(c.err(
                    r.joint.as_ref().expect("checked").span(),
                    format!(
                        "input `{qn}`: joint {} has no drive: a `drive-acceleration` input adds an acceleration to a joint's `drive`",
                        k + 1
                    ),
                ));
            }
            InputKind::DriveAcceleration { joint: k }
        }
        "force" => {
            refuse(r.joint.is_some(), "joint")?;
            let at = r.at.as_ref().ok_or_else(|| {
                c.err(
                    r.kind.span(),
                    format!("input `{qn}`: a `force` input needs `at = \"MARKER\"`"),
                )
            })?;
            let m = b.marker(at)?;
            if let MarkerPoint::Ground(_) = m.point {
                return Err(c.err(
                    b.at(at)?.1,
                    format!(
                        "input `{qn}`: a force at the ground (`{}`) does nothing: put it on a body",
                        q(&m.text)
                    ),
                ));
            }
            let dv = r.direction.as_ref().ok_or_else(|| {
                c.err(
                    r.kind.span(),
                    format!("input `{qn}`: a `force` input needs `direction = [dx, dy(, dz)]` (the force per unit input)"),
                )
            })?;
            let direction = vec_n(c, dv, b.dim, "direction")?;
            if direction.iter().all(|x| *x == 0.0) {
                return Err(c.err(
                    dv.span(),
                    format!("input `{qn}`: `direction` is zero: the force is the input times this vector"),
                ));
            }
            let follower = match r.axes.as_ref().map(|a| a.get_ref().as_str()) {
                None | Some("global") => false,
                Some("body") => true,
                Some(other) => {
                    return Err(c.err(
                        r.axes.as_ref().expect("some").span(),
                        format!("`axes` is \"global\" or \"body\", found `{}`", q(other)),
                    ))
                }
            };
            InputKind::Force {
                at: m,
                direction,
                follower,
            }
        }
        other => {
            return Err(c.err(
                r.kind.span(),
                format!(
                    "input `{qn}`: unknown kind `{}`: expected torque, force or drive-acceleration",
                    q(other)
                ),
            ))
        }
    };
    if let (Some(s), Some(_)) = (&r.start, &r.profile) {
        return Err(c.err(
            s.span(),
            format!("input `{qn}`: `start` and `profile` both give the input's value before a caller sets it: give one (with a profile the value at t = 0 is the profile's)"),
        ));
    }
    let start = match &r.start {
        Some(s) => fin_f64(c, s, "start")?,
        None => 0.0,
    };
    let profile = match &r.profile {
        None => None,
        Some(p) => {
            let who = format!("input `{qn}`");
            let scale = match &kind {
                InputKind::Force { direction, .. } => *direction,
                _ => [1.0, 0.0, 0.0],
            };
            Some(force_profile(c, p, t_end, &who, &scale)?)
        }
    };
    Ok(InputSpec {
        name: name.clone(),
        kind,
        start,
        profile,
        at: c.loc(r.name.span()),
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn linearize_names_are_reserved() {
        for n in ["joint1", "force12", "drive3"] {
            assert!(super::reserved(n), "{n}");
        }
        for n in ["joint", "jointx", "tau", "force1a", "Joint1"] {
            assert!(!super::reserved(n), "{n}");
        }
    }
}
