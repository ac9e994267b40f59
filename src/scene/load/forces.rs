//! `[[forces]]`: point forces (global or follower), torques,
//! spring–dampers and rotational spring–dampers.

use super::markers::MarkerRef;
use super::markers::Markers;
use super::Ctx;
use super::{fin_f64, vec_n};
use crate::codegen::scene::quoted as q;
use crate::codegen::scene::RawForce;
use crate::runtime::{Body, System, TorqueLaw};
use crate::scene::SceneError;
use std::sync::Arc;
use toml::Spanned;

pub(super) fn force(
    c: &Ctx,
    b: &Markers,
    sys: &mut System<Box<dyn Body>>,
    f: &RawForce,
) -> Result<(), SceneError> {
    let r = f;
    fn need<'v>(
        c: &Ctx,
        f: &RawForce,
        v: &'v Option<Spanned<String>>,
        what: &str,
    ) -> Result<&'v Spanned<String>, SceneError> {
        v.as_ref().ok_or_else(|| {
            c.err(
                f.span(),
                format!("a `{}` force needs `{what}`", f.kind.get_ref()),
            )
        })
    }
    let numr = |v: &Option<Spanned<f64>>, what: &str| -> Result<f64, SceneError> {
        v.as_ref()
            .ok_or_else(|| {
                c.err(
                    f.span(),
                    format!("a `{}` force needs `{what}`", r.kind.get_ref()),
                )
            })
            .and_then(|x| fin_f64(c, x, what))
    };
    // The two ends of a spring, damper or torque element: they must be able
    // to move relative to each other, or the element does nothing (its
    // energy would be reported all the same).
    let ends = |c: &Ctx| -> Result<(), SceneError> {
        let (Some(sa), Some(sb)) = (&r.a, &r.b) else {
            return Ok(());
        };
        let (ma, mb) = (b.marker_ref(sa)?, b.marker_ref(sb)?);
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
        let rigid_ends = |x: &MarkerRef| match x {
            MarkerRef::Origin(i) | MarkerRef::Point(i, _) => Some(*i),
            _ => None,
        };
        match (&ma, &mb) {
            (MarkerRef::Ground(_), MarkerRef::Ground(_)) => {
                same("are both fixed to the ground".into())
            }
            (MarkerRef::Axis(i, x), MarkerRef::Axis(j, y)) if i == j && x == y => {
                same(format!("are the same point of body `{}`", b.names[i.0]))
            }
            _ => match (rigid_ends(&ma), rigid_ends(&mb)) {
                (Some(i), Some(j)) if i == j => same(format!(
                    "are both fixed in the frame of body `{}`",
                    b.names[i.0]
                )),
                _ => Ok(()),
            },
        }
    };
    // Non-negative coefficients, checked here so that the message is located.
    let nonneg = |v: &Option<Spanned<f64>>, what: &str| -> Result<(), SceneError> {
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
    match r.kind.get_ref().as_str() {
        "point" => {
            let at = need(c, f, &r.at, "at")?;
            if let MarkerRef::Ground(_) = b.marker_ref(at)? {
                return Err(c.err(
                    at.span(),
                    format!(
                        "a `point` force at the ground (`{}`) does nothing: put it on a body",
                        q(at.get_ref())
                    ),
                ));
            }
            let m = b.marker(sys, at)?;
            let fv = r.force.as_ref().ok_or_else(|| c.err(f.span(), "a `point` force needs `force = [Fx, Fy(, Fz)]` (N)"))?;
            let fv = vec_n(c, fv, b.dim, "force")?;
            let res = match r.axes.as_ref().map(|a| a.get_ref().as_str()) {
                None | Some("global") => sys.add_point_force(m, move |_| fv),
                Some("body") => sys.add_follower_force(m, move |_| fv),
                Some(other) => return Err(c.err(r.axes.as_ref().expect("some").span(), format!("`axes` is \"global\" or \"body\", found `{other}`", other = q(other)))),
            };
            res.map_err(|e| c.err(f.span(), e.to_string()))
        }
        "spring-damper" => {
            ends(c)?;
            let (a, bb) = (b.marker(sys, need(c, f, &r.a, "a")?)?, b.marker(sys, need(c, f, &r.b, "b")?)?);
            sys.add_spring_damper(a, bb, numr(&r.stiffness, "stiffness")?, r.damping.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "damping"))?, numr(&r.rest_length, "rest_length")?)
                .map_err(|e| c.err(f.span(), e.to_string()))
        }
        "rotational-spring-damper" => {
            ends(c)?;
            let (a, bb) = (b.marker(sys, need(c, f, &r.a, "a")?)?, b.marker(sys, need(c, f, &r.b, "b")?)?);
            let law = TorqueLaw::SpringDamper {
                stiffness: numr(&r.stiffness, "stiffness")?,
                damping: r.damping.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "damping"))?,
                rest_angle: r.rest_angle.as_ref().map_or(Ok(0.0), |x| fin_f64(c, x, "rest_angle"))?,
            };
            sys.add_torque(a, bb, law).map_err(|e| c.err(f.span(), e.to_string()))
        }
        "torque" => {
            ends(c)?;
            let (a, bb) = (b.marker(sys, need(c, f, &r.a, "a")?)?, b.marker(sys, need(c, f, &r.b, "b")?)?);
            let tau = numr(&r.torque, "torque")?;
            sys.add_torque(a, bb, TorqueLaw::Torque(Arc::new(move |_| tau))).map_err(|e| c.err(f.span(), e.to_string()))
        }
        other => Err(c.err(r.kind.span(), format!("unknown force kind `{other}`: expected point, spring-damper, rotational-spring-damper or torque", other = q(other)))),
    }
}
