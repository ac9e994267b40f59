//! `[[forces]]`: point (global or follower) forces, spring-dampers,
//! rotational spring-dampers and constant torques between markers.

use super::markers::Markers;
use super::{fin_f64, vec_n, Ctx};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::RawForce;
use ffr_spec::scene::{ForceKind, ForceSpec, MarkerPoint, MarkerSpec};
use toml::Spanned;

pub(super) fn force(c: &Ctx, b: &Markers, f: &RawForce) -> Result<ForceSpec, Error> {
    let r = f;
    let need = |v: &'_ Option<Spanned<String>>, what: &str| -> Result<MarkerSpec, Error> {
        let s = v.as_ref().ok_or_else(|| {
            c.err(
                f.span(),
                format!("a `{}` force needs `{what}`", f.kind.get_ref()),
            )
        })?;
        b.marker(s)
    };
    let numr = |v: &Option<Spanned<f64>>, what: &str| -> Result<f64, Error> {
        v.as_ref()
            .ok_or_else(|| {
                c.err(
                    f.span(),
                    format!("a `{}` force needs `{what}`", r.kind.get_ref()),
                )
            })
            .and_then(|x| fin_f64(c, x, what))
    };
    let opt = |v: &Option<Spanned<f64>>, what: &str| -> Result<f64, Error> {
        v.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, what))
    };
    let ends = || -> Result<(), Error> {
        let (Some(sa), Some(sb)) = (&r.a, &r.b) else {
            return Ok(());
        };
        let (ma, mb) = (b.point(sa)?, b.point(sb)?);
        let kind = q(r.kind.get_ref());
        let same = |why: String| {
            Err(c.err(
                sb.span(),
                format!(
                    "the `{kind}` force's ends `a` = `{}` and `b` = `{}` {why}: such a force does nothing (it would still report energy); give two ends that move relative to each other",
                    q(sa.get_ref()),
                    q(sb.get_ref())
                ),
            ))
        };
        let rigid_ends = |x: &MarkerPoint| match x {
            MarkerPoint::Origin(i) | MarkerPoint::Point(i, _) => Some(*i),
            _ => None,
        };
        match (&ma, &mb) {
            (MarkerPoint::Ground(_), MarkerPoint::Ground(_)) => {
                same("are both fixed to the ground".into())
            }
            (MarkerPoint::Axis(i, x), MarkerPoint::Axis(j, y)) if i == j && x == y => {
                same(format!("are the same point of body `{}`", b.names[*i]))
            }
            (MarkerPoint::Node(i, x), MarkerPoint::Node(j, y)) if i == j && x == y => {
                same(format!("are the same node of body `{}`", b.names[*i]))
            }
            _ => match (rigid_ends(&ma), rigid_ends(&mb)) {
                (Some(i), Some(j)) if i == j => same(format!(
                    "are both fixed in the frame of body `{}`",
                    b.names[i]
                )),
                _ => Ok(()),
            },
        }
    };
    let nonneg = |v: &Option<Spanned<f64>>, what: &str| -> Result<(), Error> {
        match v {
            Some(x) if *x.get_ref() < 0.0 => Err(c.err(
                x.span(),
                format!("`{what}` must be ≥ 0, found {:?}", x.get_ref()),
            )),
            _ => Ok(()),
        }
    };
    match r.kind.get_ref().as_str() {
        "spring-damper" => {
            nonneg(&r.stiffness, "stiffness")?;
            nonneg(&r.damping, "damping")?;
            nonneg(&r.rest_length, "rest_length")?;
        }
        "rotational-spring-damper" => {
            nonneg(&r.stiffness, "stiffness")?;
            nonneg(&r.damping, "damping")?;
        }
        _ => {}
    }
    let kind = match r.kind.get_ref().as_str() {
        "point" => {
            let at = r.at.as_ref().ok_or_else(|| c.err(f.span(), "a `point` force needs `at`"))?;
            let m = b.marker(at)?;
            if let MarkerPoint::Ground(_) = m.point {
                return Err(c.err(
                    at.span(),
                    format!(
                        "a `point` force at the ground (`{}`) does nothing: put it on a body",
                        q(at.get_ref())
                    ),
                ));
            }
            let fv = r.force.as_ref().ok_or_else(|| c.err(f.span(), "a `point` force needs `force = [Fx, Fy(, Fz)]` (N)"))?;
            let force = vec_n(c, fv, b.dim, "force")?;
            let follower = match r.axes.as_ref().map(|a| a.get_ref().as_str()) {
                None | Some("global") => false,
                Some("body") => true,
                Some(other) => return Err(c.err(r.axes.as_ref().expect("some").span(), format!("`axes` is \"global\" or \"body\", found `{other}`", other = q(other)))),
            };
            ForceKind::Point { at: m, force, follower }
        }
        "spring-damper" => {
            ends()?;
            let (a, bb) = (need(&r.a, "a")?, need(&r.b, "b")?);
            ForceKind::SpringDamper {
                a,
                b: bb,
                stiffness: numr(&r.stiffness, "stiffness")?,
                damping: opt(&r.damping, "damping")?,
                rest_length: numr(&r.rest_length, "rest_length")?,
            }
        }
        "rotational-spring-damper" => {
            ends()?;
            let (a, bb) = (need(&r.a, "a")?, need(&r.b, "b")?);
            ForceKind::RotationalSpringDamper {
                a,
                b: bb,
                stiffness: numr(&r.stiffness, "stiffness")?,
                damping: opt(&r.damping, "damping")?,
                rest_angle: opt(&r.rest_angle, "rest_angle")?,
            }
        }
        "torque" => {
            ends()?;
            let (a, bb) = (need(&r.a, "a")?, need(&r.b, "b")?);
            ForceKind::Torque {
                a,
                b: bb,
                torque: numr(&r.torque, "torque")?,
            }
        }
        other => return Err(c.err(r.kind.span(), format!("unknown force kind `{other}`: expected point, spring-damper, rotational-spring-damper or torque", other = q(other)))),
    };
    Ok(ForceSpec {
        kind,
        at: c.loc(f.span()),
    })
}
