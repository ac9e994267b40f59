//! `[[joints]]`: ground, fixed, revolute, spherical and prismatic joints,
//! their drives and motors; a revolute joint to the ground with an angle
//! drive folds into the body's prescribed frame coordinates.

use super::fin_f64;
use super::markers::MarkerRef;
use super::profiles::profile;
use super::profiles::profile_at;
use super::{Ctx, Env, Parts};
use crate::codegen::scene::quoted as q;
use crate::codegen::scene::RawScene;
use crate::codegen::scene::{RawMotor, RawTarget};
use crate::runtime::nalgebra::Vector3;
use crate::runtime::BodyId;
use crate::runtime::Driver;
use crate::runtime::TorqueLaw;
use crate::scene::SceneError;
use std::ops::Range;
use std::sync::Arc;
use toml::Spanned;

/// Add the scene's joints to the system; returns where each constraint of
/// the system was written (`spans[k]` for constraint `k`; a joint with a
/// drive adds two), to locate the initial state's refusals.
pub(super) fn add_joints(
    c: &Ctx,
    raw: &RawScene,
    env: &Env,
    parts: &mut Parts,
) -> Result<Vec<Range<usize>>, SceneError> {
    let (dim, t_end, folded, b) = (env.dim, env.t_end, &env.folded, &env.markers);
    let names = &b.names;
    let Parts { sys, notes, .. } = parts;
    // Joints; `joint_spans[k]` is where constraint `k` of the system was
    // written (a joint with a drive adds two).
    let mut joint_spans: Vec<Range<usize>> = Vec::new();
    for (ji, jr) in raw.joints.iter().enumerate() {
        let j = jr;
        if let Some(prev) = ji.checked_sub(1) {
            let span = raw.joints[prev].span();
            joint_spans.resize(sys.constraints().len(), span);
        }
        let kind = jr.kind.get_ref().as_str();
        let bm = b.marker(sys, &jr.b)?;
        if kind == "ground" {
            if jr.a.is_some() || jr.drive.is_some() || jr.motor.is_some() {
                return Err(c.err(j.span(), "a `ground` joint fixes body `b` where it starts: it takes no `a`, `drive` or `motor`"));
            }
            let MarkerRef::Origin(bid) = b.marker_ref(&jr.b)? else {
                return Err(c.err(
                    jr.b.span(),
                    "a `ground` joint takes a body name as `b` (it fixes the body's frame)",
                ));
            };
            sys.ground(bid)
                .map_err(|e| c.err(j.span(), e.to_string()))?;
            notes.push(format!(
                "body `{}`: frame fixed by a ground joint (prescribed coordinates)",
                names[bid.0]
            ));
            continue;
        }
        let a = jr.a.as_ref().ok_or_else(|| {
            c.err(
                j.span(),
                format!("a `{kind}` joint needs markers `a` and `b`"),
            )
        })?;
        let am = b.marker(sys, a)?;
        if let Some(bi) = folded.iter().position(|f| *f == Some(ji)) {
            // Revolute to the ground at the body's frame origin, angle drive:
            // prescribe the frame (origin fixed, angle driven).
            let bid = BodyId(bi);
            let drive = profile(
                c,
                jr.drive.as_ref().expect("checked"),
                "angle",
                t_end,
                &format!("the drive of {}", joint_name(ji, jr)),
            )?;
            let entry = sys.body_entry(bid);
            let (o, d) = (entry.offset, entry.d);
            let (q0, _) = sys.initial_coords();
            let origin =
                Vector3::from_iterator((0..3).map(|k| if k < d { q0[o + k] } else { 0.0 }));
            let MarkerRef::Ground(p) = b.marker_ref(a)? else {
                unreachable!()
            };
            if (origin - p).norm() > 1e-12 * (1.0 + p.norm()) {
                return Err(c.err(a.span(), format!("the revolute joint's ground point {:?} is not at body `{}`'s frame origin {:?}: put the body's `position` at the joint", &p.as_slice()[..dim], names[bi], &origin.as_slice()[..dim])));
            }
            sys.prescribe_rotation_about_z(bid, drive)
                .map_err(|e| c.err(j.span(), e.to_string()))?;
            notes.push(format!(
                "body `{}`: revolute joint to the ground with an angle drive folded into prescribed frame coordinates ({})",
                names[bi],
                if b.rigid[bi] { "no equations left" } else { "elastic equations only" }
            ));
            continue;
        }
        if kind == "spherical" && dim == 2 {
            return Err(c.err(jr.kind.span(), "a `spherical` joint needs a spatial scene (dimension = 3); a planar scene has ground, fixed, revolute and prismatic joints"));
        }
        let res = match kind {
            "revolute" => sys.revolute(am.clone(), bm.clone()),
            "fixed" => sys.fixed(am.clone(), bm.clone()),
            "spherical" => sys.spherical(am.clone(), bm.clone()),
            "prismatic" => sys.prismatic(am.clone(), bm.clone()),
            other => {
                return Err(c.err(jr.kind.span(), format!("unknown joint kind `{other}`: expected ground, fixed, revolute, spherical or prismatic", other = q(other))));
            }
        };
        res.map_err(|e| c.err(jr.kind.span(), e.to_string()))?;
        if let Some(d) = &jr.drive {
            match kind {
                "revolute" => {
                    let f = profile(c, d, "angle", t_end, &format!("the drive of {}", joint_name(ji, jr)))?;
                    sys.prescribe_rotation(am.clone(), bm.clone(), f)
                }
                "prismatic" => {
                    let f = profile(c, d, "slide", t_end, &format!("the drive of {}", joint_name(ji, jr)))?;
                    sys.prescribe_slide(am.clone(), bm.clone(), f)
                }
                _ => return Err(c.err(d.span(), format!("a `{kind}` joint has no drive: drives are for revolute (angle) and prismatic (slide) joints"))),
            }
            .map_err(|e| c.err(d.span(), e.to_string()))?;
        }
        if let Some(m) = &jr.motor {
            if kind != "revolute" {
                return Err(c.err(
                    m.span(),
                    "motors act in revolute joints (a torque about the joint axis)",
                ));
            }
            let law = motor(c, m, t_end, &joint_name(ji, jr))?;
            sys.add_torque(am, bm, law)
                .map_err(|e| c.err(m.span(), e.to_string()))?;
        }
    }
    if let Some(last) = raw.joints.last() {
        joint_spans.resize(sys.constraints().len(), last.span());
    }
    Ok(joint_spans)
}

/// How messages name joint `i` (0-based): `joint 2 (revolute, a =
/// `hub`, b = `arm`)`.
fn joint_name(i: usize, j: &crate::codegen::scene::RawJoint) -> String {
    format!(
        "joint {} (`{}`{}, b = `{}`)",
        i + 1,
        q(j.kind.get_ref()),
        j.a.as_ref()
            .map_or(String::new(), |a| format!(", a = `{}`", q(a.get_ref()))),
        q(j.b.get_ref())
    )
}

fn motor(c: &Ctx, m: &Spanned<RawMotor>, t_end: f64, joint: &str) -> Result<TorqueLaw, SceneError> {
    let r = m.get_ref();
    match (&r.torque, &r.target) {
        (Some(t), None) => {
            let tau = fin_f64(c, t, "torque")?;
            if r.kp.is_some() || r.kd.is_some() {
                return Err(c.err(
                    m.span(),
                    "a motor has `torque` (constant) or `target` with `kp`, `kd` (PD), not both",
                ));
            }
            Ok(TorqueLaw::Torque(Arc::new(move |_| tau)))
        }
        (None, Some(target)) => {
            let drv = match target.get_ref() {
                RawTarget::Angle(x) if x.is_finite() => Driver::constant(*x),
                RawTarget::Angle(x) => {
                    return Err(c.err(
                        target.span(),
                        format!("motor `target` must be a finite angle, found {x:?}"),
                    ))
                }
                RawTarget::Profile(p) => profile_at(
                    c,
                    target.span(),
                    p,
                    "angle",
                    t_end,
                    &format!("the motor target of {joint}"),
                )?,
            };
            let kp =
                r.kp.as_ref()
                    .ok_or_else(|| c.err(m.span(), "a PD motor needs `kp` (N m/rad)"))
                    .and_then(|x| fin_f64(c, x, "kp"))?;
            let kd = r.kd.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "kd"))?;
            for (what, v, x) in [("kp", &r.kp, kp), ("kd", &r.kd, kd)] {
                if let (Some(v), true) = (v, x < 0.0) {
                    return Err(c.err(
                        v.span(),
                        format!("`{what}` (a PD gain) must be ≥ 0, found {x:?}"),
                    ));
                }
            }
            Ok(TorqueLaw::Pd {
                target: drv,
                kp,
                kd,
            })
        }
        _ => Err(c.err(
            m.span(),
            "a motor is `{ torque = τ }` or `{ target = φ, kp = …, kd = … }`",
        )),
    }
}
