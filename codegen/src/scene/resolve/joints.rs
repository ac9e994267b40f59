//! `[[joints]]`: ground, fixed, revolute, spherical and prismatic joints,
//! their drives and motors; a revolute joint to the ground with an angle
//! drive at a body's frame origin is marked to fold into the body's
//! prescribed frame coordinates.

use super::fin_f64;
use super::markers::Markers;
use super::profiles::{profile, profile_at};
use super::Ctx;
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::{RawJoint, RawMotor, RawScene, RawTarget};
use ffr_spec::scene::{JointKind, JointSpec, MarkerPoint, MotorSpec, ProfileSpec};
use toml::Spanned;

/// The scene's joints, in file order.
pub(super) fn joints(
    c: &Ctx,
    raw: &RawScene,
    t_end: f64,
    b: &Markers,
) -> Result<Vec<JointSpec>, Error> {
    // Which bodies' frames are folded into prescribed coordinates.
    let folding = raw.folded();
    let folded: Vec<Option<usize>> = b.names.iter().map(|n| folding.get(n).copied()).collect();
    let mut out = Vec::new();
    for (ji, jr) in raw.joints.iter().enumerate() {
        let kind_s = jr.kind.get_ref().as_str();
        let bm = b.marker(&jr.b)?;
        let at = c.loc(jr.span());
        let kind_at = c.loc(jr.kind.span());
        if kind_s == "ground" {
            if jr.a.is_some() || jr.drive.is_some() || jr.motor.is_some() {
                return Err(c.err(jr.span(), "a `ground` joint fixes body `b` where it starts: it takes no `a`, `drive` or `motor`"));
            }
            let MarkerPoint::Origin(_) = bm.point else {
                return Err(c.err(
                    b.at(&jr.b)?.1,
                    "a `ground` joint takes a body name as `b` (it fixes the body's frame)",
                ));
            };
            if bm.axes.is_some() {
                return Err(c.err(
                    jr.b.span(),
                    "a `ground` joint fixes body `b`'s frame where it starts: its marker takes no `axes`",
                ));
            }
            out.push(JointSpec {
                kind: JointKind::Ground,
                at,
                kind_at,
                a: None,
                b: bm,
                drive: None,
                motor: None,
                folds: None,
            });
            continue;
        }
        let a = jr.a.as_ref().ok_or_else(|| {
            c.err(
                jr.span(),
                format!("a `{kind_s}` joint needs markers `a` and `b`"),
            )
        })?;
        let am = b.marker(a)?;
        if let Some(bi) = folded.iter().position(|f| *f == Some(ji)) {
            // Revolute to the ground at the body's frame origin, angle drive:
            // the frame is prescribed (origin fixed, angle driven).
            let d = jr.drive.as_ref().expect("a folded joint has a drive");
            let drive = profile(
                c,
                d,
                "angle",
                t_end,
                &format!("the drive of {}", joint_name(ji, jr)),
            )?;
            out.push(JointSpec {
                kind: JointKind::Revolute,
                at,
                kind_at,
                a: Some(am),
                b: bm,
                drive: Some((drive, c.loc(d.span()))),
                motor: None,
                folds: Some(bi),
            });
            continue;
        }
        if kind_s == "spherical" && b.dim == 2 {
            return Err(c.err(jr.kind.span(), "a `spherical` joint needs a spatial scene (dimension = 3); a planar scene has ground, fixed, revolute and prismatic joints"));
        }
        let kind = match kind_s {
            "revolute" => JointKind::Revolute,
            "fixed" => JointKind::Fixed,
            "spherical" => JointKind::Spherical,
            "prismatic" => JointKind::Prismatic,
            other => {
                return Err(c.err(jr.kind.span(), format!("unknown joint kind `{other}`: expected ground, fixed, revolute, spherical or prismatic", other = q(other))));
            }
        };
        let drive = match &jr.drive {
            None => None,
            Some(d) => {
                let key = match kind {
                    JointKind::Revolute => "angle",
                    JointKind::Prismatic => "slide",
                    _ => return Err(c.err(d.span(), format!("a `{kind_s}` joint has no drive: drives are for revolute (angle) and prismatic (slide) joints"))),
                };
                let f = profile(
                    c,
                    d,
                    key,
                    t_end,
                    &format!("the drive of {}", joint_name(ji, jr)),
                )?;
                Some((f, c.loc(d.span())))
            }
        };
        let motor = match &jr.motor {
            None => None,
            Some(m) => {
                if kind != JointKind::Revolute {
                    return Err(c.err(
                        m.span(),
                        "motors act in revolute joints (a torque about the joint axis)",
                    ));
                }
                Some((motor(c, m, t_end, &joint_name(ji, jr))?, c.loc(m.span())))
            }
        };
        out.push(JointSpec {
            kind,
            at,
            kind_at,
            a: Some(am),
            b: bm,
            drive,
            motor,
            folds: None,
        });
    }
    Ok(out)
}

/// How messages name joint `i` (0-based): `joint 2 (revolute, a =
/// `hub`, b = `arm`)`.
fn joint_name(i: usize, j: &RawJoint) -> String {
    format!(
        "joint {} (`{}`{}, b = `{}`)",
        i + 1,
        q(j.kind.get_ref()),
        j.a.as_ref().map_or(String::new(), |a| format!(
            ", a = `{}`",
            q(a.get_ref().text().unwrap_or(""))
        )),
        q(j.b.get_ref().text().unwrap_or(""))
    )
}

fn motor(c: &Ctx, m: &Spanned<RawMotor>, t_end: f64, joint: &str) -> Result<MotorSpec, Error> {
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
            Ok(MotorSpec::Torque(tau))
        }
        (None, Some(target)) => {
            let drv = match target.get_ref() {
                RawTarget::Angle(x) if x.is_finite() => ProfileSpec::Constant(*x),
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
            Ok(MotorSpec::Pd {
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
