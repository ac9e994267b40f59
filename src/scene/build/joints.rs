//! `[[joints]]`: ground, fixed, revolute, spherical and prismatic joints,
//! their drives and motors; a revolute joint to the ground with an angle
//! drive at a body's frame origin folds into the body's prescribed frame
//! coordinates.

use super::{driver, err, marker, torque_law, Parts};
use crate::runtime::nalgebra::Vector3;
use crate::runtime::spec::scene::{BodyKind, JointKind, MarkerPoint, SceneSpec};
use crate::runtime::spec::Location;
use crate::runtime::BodyId;
use crate::SceneError;

/// Add the scene's joints to the system; returns where each constraint of
/// the system was written (`sites[k]` for constraint `k`; a joint with a
/// drive adds two), to locate the initial state's refusals.
/// Joint `ji`'s driver `d`, perturbed by its `drive-acceleration` input if
/// it has one (inputs are the system's first, in file order).
fn perturbed(spec: &SceneSpec, ji: usize, d: crate::runtime::Driver) -> crate::runtime::Driver {
    use crate::runtime::spec::scene::InputKind;
    match spec
        .inputs
        .iter()
        .position(|i| i.kind == InputKind::DriveAcceleration { joint: ji })
    {
        Some(k) => d.with_input(k),
        None => d,
    }
}

pub(super) fn add_joints(spec: &SceneSpec, parts: &mut Parts) -> Result<Vec<Location>, SceneError> {
    let dim = spec.dim;
    let Parts { sys, notes, .. } = parts;
    // The cut joints of segmented bodies come first (added with the
    // bodies): located at each body's `segments`.
    let mut sites: Vec<Location> = spec
        .bodies
        .iter()
        .flat_map(|b| match &b.kind {
            BodyKind::Flexible(f) if f.segments > 1 => {
                let at = f.segments_at.clone().unwrap_or_else(|| b.at.clone());
                vec![at; f.segments - 1]
            }
            _ => Vec::new(),
        })
        .collect();
    debug_assert_eq!(sites.len(), sys.constraints().len());
    for (ji, j) in spec.joints.iter().enumerate() {
        if let Some(prev) = ji.checked_sub(1) {
            sites.resize(sys.constraints().len(), spec.joints[prev].at.clone());
        }
        let bm = marker(sys, &j.b)?;
        if j.kind == JointKind::Ground {
            let MarkerPoint::Origin(b) = j.b.point else {
                return Err(err(
                    &j.b.at,
                    "a `ground` joint takes a body name as `b` (it fixes the body's frame)",
                ));
            };
            sys.ground(BodyId(b))
                .map_err(|e| err(&j.at, e.to_string()))?;
            notes.push(format!(
                "body `{}`: frame fixed by a ground joint (prescribed coordinates)",
                spec.bodies[b].name
            ));
            continue;
        }
        let a = j.a.as_ref().ok_or_else(|| {
            err(
                &j.at,
                format!("a `{}` joint needs markers `a` and `b`", j.kind.name()),
            )
        })?;
        let am = marker(sys, a)?;
        if let Some(bi) = j.folds {
            // Revolute to the ground at the body's frame origin, angle drive:
            // prescribe the frame (origin fixed, angle driven).
            let bid = BodyId(bi);
            let (profile, _) = j.drive.as_ref().expect("a folded joint has a drive");
            let drive = perturbed(spec, ji, driver(profile));
            let entry = sys.body_entry(bid);
            let (o, d) = (entry.offset, entry.d);
            let (q0, _) = sys.initial_coords();
            let origin =
                Vector3::from_iterator((0..3).map(|k| if k < d { q0[o + k] } else { 0.0 }));
            let MarkerPoint::Ground(p) = a.point else {
                return Err(err(&a.at, "a folded joint's `a` is a ground point"));
            };
            let p = super::v3(p);
            let name = &spec.bodies[bi].name;
            if (origin - p).norm() > 1e-12 * (1.0 + p.norm()) {
                return Err(err(&a.at, format!("the revolute joint's ground point {:?} is not at body `{name}`'s frame origin {:?}: put the body's `position` at the joint", &p.as_slice()[..dim], &origin.as_slice()[..dim])));
            }
            sys.prescribe_rotation_about_z(bid, drive)
                .map_err(|e| err(&j.at, e.to_string()))?;
            let rigid = matches!(spec.bodies[bi].kind, BodyKind::Rigid { .. });
            notes.push(format!(
                "body `{name}`: revolute joint to the ground with an angle drive folded into prescribed frame coordinates ({})",
                if rigid { "no equations left" } else { "elastic equations only" }
            ));
            continue;
        }
        let res = match j.kind {
            JointKind::Revolute => sys.revolute(am.clone(), bm.clone()),
            JointKind::Fixed => sys.fixed(am.clone(), bm.clone()),
            JointKind::Spherical => sys.spherical(am.clone(), bm.clone()),
            JointKind::Prismatic => sys.prismatic(am.clone(), bm.clone()),
            JointKind::Ground => unreachable!("handled above"),
        };
        res.map_err(|e| err(&j.kind_at, e.to_string()))?;
        if let Some((profile, at)) = &j.drive {
            let f = perturbed(spec, ji, driver(profile));
            match j.kind {
                JointKind::Revolute => sys.prescribe_rotation(am.clone(), bm.clone(), f),
                JointKind::Prismatic => sys.prescribe_slide(am.clone(), bm.clone(), f),
                _ => {
                    return Err(err(
                        at,
                        "drives are for revolute (angle) and prismatic (slide) joints",
                    ))
                }
            }
            .map_err(|e| err(at, e.to_string()))?;
        }
        if let Some((m, at)) = &j.motor {
            if j.kind != JointKind::Revolute {
                return Err(err(
                    at,
                    "motors act in revolute joints (a torque about the joint axis)",
                ));
            }
            sys.add_torque(am, bm, torque_law(m))
                .map_err(|e| err(at, e.to_string()))?;
        }
    }
    if let Some(last) = spec.joints.last() {
        sites.resize(sys.constraints().len(), last.at.clone());
    }
    Ok(sites)
}
