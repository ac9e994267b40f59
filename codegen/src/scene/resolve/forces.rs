//! `[[forces]]`: point (global or follower) forces, spring-dampers,
//! rotational spring-dampers and constant torques between markers.

use super::markers::Markers;
use super::profiles::profile_at;
use super::{fin_f64, vec_n, Ctx};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::{RawForce, RawForceProfile, RawMarker};
use ffr_spec::scene::{
    ForceKind, ForceProfile, ForceSpec, MarkerPoint, MarkerSpec, ProfileSpec, MAX_PROFILE_ROWS,
};
use toml::Spanned;

/// The `i`-th force (0-based) of a scene that ends at `t_end`.
pub(super) fn force(
    c: &Ctx,
    b: &Markers,
    f: &RawForce,
    i: usize,
    t_end: f64,
) -> Result<ForceSpec, Error> {
    let r = f;
    let need = |v: &'_ Option<Spanned<RawMarker>>, what: &str| -> Result<MarkerSpec, Error> {
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
                    q(sa.get_ref().text().unwrap_or("")),
                    q(sb.get_ref().text().unwrap_or(""))
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
                    b.at(at)?.1,
                    format!(
                        "a `point` force at the ground (`{}`) does nothing: put it on a body",
                        q(&m.text)
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
            let profile = match &r.profile {
                None => None,
                Some(p) => {
                    let who = format!("force {} (`point` at `{}`)", i + 1, q(&m.text));
                    Some(force_profile(c, p, t_end, &who, &force)?)
                }
            };
            ForceKind::Point { at: m, force, follower, profile }
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

/// A point force's `profile`: a drive profile's value (`kind = …`, checked
/// as drives are, up to `t_end`) or a table of `[t, f]` rows; `f(t) force`
/// must stay within the range of f64.
pub(super) fn force_profile(
    c: &Ctx,
    p: &Spanned<RawForceProfile>,
    t_end: f64,
    who: &str,
    force: &[f64; 3],
) -> Result<ForceProfile, Error> {
    let r = p.get_ref();
    let (profile, bound) = match (&r.kind, &r.table) {
        (Some(_), Some(t)) => {
            return Err(c.err(
                t.span(),
                "a force's `profile` is `kind = \"PROFILE\"` (a drive profile) or `table = [[t, f], …]`, not both",
            ))
        }
        (None, None) => {
            return Err(c.err(
                p.span(),
                "a force's `profile` needs `kind = \"PROFILE\"` (spin-up, constant-rate, constant or harmonic, with that profile's keys) or `table = [[t0, f0], [t1, f1], …]`",
            ))
        }
        (Some(_), None) => {
            let d = profile_at(c, p.span(), &r.as_drive(), "angle", t_end, who)?;
            (ForceProfile::Drive(d), value_bound(&d, t_end))
        }
        (None, Some(t)) => {
            let rows = &t.get_ref().0;
            if rows.is_empty() {
                return Err(c.err(
                    t.span(),
                    "a profile `table` needs at least one row [time, value]",
                ));
            }
            // Checked while read; again here for a table built otherwise.
            if rows.len() > MAX_PROFILE_ROWS {
                return Err(c.err(
                    t.span(),
                    format!("a profile `table` has more than {MAX_PROFILE_ROWS} rows (MAX_PROFILE_ROWS)"),
                ));
            }
            let mut out: Vec<[f64; 2]> = Vec::with_capacity(rows.len());
            let mut bound = 0.0_f64;
            for (k, row) in rows.iter().enumerate() {
                let w = row.get_ref();
                let n = k + 1;
                if w.len != 2 {
                    return Err(c.err(
                        row.span(),
                        format!(
                            "row {n} of the profile `table` has {} value{}: each row is [time, value]",
                            w.len,
                            if w.len == 1 { "" } else { "s" }
                        ),
                    ));
                }
                let [t, f] = w.values;
                if !t.is_finite() {
                    return Err(c.err(
                        row.span(),
                        format!("row {n} of the profile `table`: the time {t:?} is not a finite number"),
                    ));
                }
                if !f.is_finite() {
                    return Err(c.err(
                        row.span(),
                        format!("row {n} of the profile `table`: the value {f:?} is not a finite number"),
                    ));
                }
                if let Some(prev) = out.last() {
                    if !(t > prev[0]) {
                        return Err(c.err(
                            row.span(),
                            format!(
                                "row {n} of the profile `table`: the time {t:?} is not after row {k}'s {:?}: the times must increase strictly",
                                prev[0]
                            ),
                        ));
                    }
                }
                bound = bound.max(f.abs());
                out.push([t, f]);
            }
            let span = out[out.len() - 1][0] - out[0][0];
            if !span.is_finite() {
                return Err(c.err(
                    t.span(),
                    format!(
                        "the profile `table`'s times span {:?} to {:?}: an interval beyond the range of f64",
                        out[0][0],
                        out[out.len() - 1][0]
                    ),
                ));
            }
            (ForceProfile::Table(out), bound)
        }
    };
    let fmax = force.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if !(bound * fmax).is_finite() {
        return Err(c.err(
            p.span(),
            format!(
                "{who}: the profile's value reaches {bound:?} and the force has a component of {fmax:?}: f(t) force is beyond the range of f64"
            ),
        ));
    }
    Ok(profile)
}

/// A bound of `|f(t)|` on `[0, t_end]` (the bounds the drives check).
fn value_bound(p: &ProfileSpec, t_end: f64) -> f64 {
    match *p {
        ProfileSpec::SpinUp { omega, ramp, start } => start.abs() + omega.abs() * (t_end + ramp),
        ProfileSpec::ConstantRate { start, rate } => start.abs() + rate.abs() * t_end,
        ProfileSpec::Constant(v) => v.abs(),
        ProfileSpec::Harmonic {
            start, amplitude, ..
        } => start.abs() + amplitude.abs(),
    }
}
