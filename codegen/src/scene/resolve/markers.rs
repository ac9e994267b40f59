//! Markers as a scene writes them: a point on the ground, a body's frame
//! origin, a point on a beam's axis, a point fixed in a body's frame.

use super::{fin_f64, vec_n, Ctx};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::{RawMarker, RawMarkerAxes};
use ffr_spec::scene::{MarkerPoint, MarkerSpec, Orientation};
use std::ops::Range;
use toml::Spanned;

/// The markers of a scene (`ground@[x, y]`, `NAME`, `NAME@x=…`,
/// `NAME@[x, y]`), resolved against its bodies.
pub(super) struct Markers<'a> {
    pub(super) c: &'a Ctx<'a>,
    pub(super) dim: usize,
    pub(super) names: Vec<String>,
    pub(super) rigid: Vec<bool>,
    /// Which bodies are FE bodies (`fe = {…}`; markers `NAME@node=N`).
    pub(super) fe: Vec<bool>,
}

impl Markers<'_> {
    /// The marker written as `s`.
    pub(super) fn marker(&self, s: &Spanned<RawMarker>) -> Result<MarkerSpec, Error> {
        let (text, span) = self.at(s)?;
        let axes = match s.get_ref() {
            RawMarker::Table(t) => match &t.axes {
                Some(a) => self.axes(a)?,
                None => None,
            },
            RawMarker::Text(_) => None,
        };
        Ok(MarkerSpec {
            point: self.point_at(text, span.clone())?,
            text: text.to_string(),
            at: self.c.loc(span),
            axes,
        })
    }

    /// The point the marker written as `s` names.
    pub(super) fn point(&self, s: &Spanned<RawMarker>) -> Result<MarkerPoint, Error> {
        let (text, span) = self.at(s)?;
        self.point_at(text, span)
    }

    /// The marker's point as written and where: the string, or a table's
    /// `at` (a table without one is an error at the table).
    pub(super) fn at<'s>(
        &self,
        s: &'s Spanned<RawMarker>,
    ) -> Result<(&'s str, Range<usize>), Error> {
        match s.get_ref() {
            RawMarker::Text(t) => Ok((t.as_str(), s.span())),
            RawMarker::Table(t) => t
                .at
                .as_ref()
                .map(|a| (a.get_ref().as_str(), a.span()))
                .ok_or_else(|| {
                    self.c.err(
                        s.span(),
                        format!(
                            "a marker table needs `at = \"MARKER\"` (the point: `NAME@x=…`, `NAME@[x, y{}]`, `ground@[…]`, …) and may give `axes = {{ {} }}`",
                            if self.dim == 3 { ", z" } else { "" },
                            if self.dim == 3 { "axis = [x, y, z], angle = …" } else { "angle = …" }
                        ),
                    )
                }),
        }
    }

    /// A marker's own axes: planar a rotation about z, spatial about a
    /// non-zero axis; `None` for an angle of 0 (checked like any other: the
    /// marker's own axes are then its section's or body's, and it runs as
    /// the marker without `axes`, bit for bit).
    fn axes(&self, a: &Spanned<RawMarkerAxes>) -> Result<Option<Orientation>, Error> {
        let r = a.get_ref();
        let angle = r
            .angle
            .as_ref()
            .ok_or_else(|| {
                self.c.err(
                    a.span(),
                    if self.dim == 3 {
                        "a marker's `axes` needs `axis = [x, y, z]` and `angle` (rad): the rotation from its body's (or section's) axes to the marker's"
                    } else {
                        "a marker's `axes` needs `angle` (rad): the rotation about z from its body's (or section's) axes to the marker's"
                    },
                )
            })
            .and_then(|x| fin_f64(self.c, x, "angle"))?;
        if self.dim == 2 {
            if let Some(axis) = &r.axis {
                return Err(self.c.err(
                    axis.span(),
                    "a planar marker's `axes` turn about z: they take `angle` only, not `axis`",
                ));
            }
            return Ok((angle != 0.0).then_some(Orientation::Planar(angle)));
        }
        let axis_raw = r.axis.as_ref().ok_or_else(|| {
            self.c.err(
                a.span(),
                "a spatial marker's `axes` need `axis = [x, y, z]` (the rotation axis) as well as `angle`",
            )
        })?;
        let axis = vec_n(self.c, axis_raw, 3, "axis")?;
        // Its length must be a positive finite number (the rotation uses
        // the unit axis).
        let n2 = axis.iter().map(|x| x * x).sum::<f64>();
        if !(n2 > 0.0 && n2.is_finite()) {
            let why = if axis.iter().all(|x| *x == 0.0) {
                "is zero"
            } else if n2 > 0.0 {
                "is too long (its squared length overflows): scale it down"
            } else {
                "is too short (its squared length underflows to 0): scale it up"
            };
            return Err(self.c.err(
                axis_raw.span(),
                format!("`axis` = {axis:?} {why}: the rotation needs a direction"),
            ));
        }
        Ok((angle != 0.0).then_some(Orientation::AxisAngle { axis, angle }))
    }

    /// The point the marker text `text` at `span` names.
    fn point_at(&self, text: &str, span: Range<usize>) -> Result<MarkerPoint, Error> {
        let text = text.trim();
        let allowed = || {
            format!(
                "a marker is `ground@[x, y{}]`, `NAME` (a body's frame origin), `NAME@x=…` (a point on a beam's axis), `NAME@node=N` (a node of an FE body) or `NAME@[x, y{}]` (a point fixed in a body's frame); bodies: {}",
                if self.dim == 3 { ", z" } else { "" },
                if self.dim == 3 { ", z" } else { "" },
                self.names.join(", ")
            )
        };
        let (name, rest) = match text.split_once('@') {
            Some((n, r)) => (n.trim(), Some(r.trim())),
            None => (text, None),
        };
        let point = |r: &str| -> Option<[f64; 3]> {
            let inner = r.strip_prefix('[')?.strip_suffix(']')?;
            let xs: Vec<f64> = inner
                .split(',')
                .map(|x| x.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<_>>()?;
            if xs.len() != self.dim {
                return None;
            }
            let mut v = [0.0; 3];
            v[..self.dim].copy_from_slice(&xs);
            Some(v)
        };
        let far = |p: [f64; 3]| -> Result<[f64; 3], Error> {
            match p.iter().find(|x| x.abs() > ffr_spec::scene::MAX_COORDINATE) {
                None => Ok(p),
                Some(x) => Err(self.c.err(
                    span.clone(),
                    format!(
                        "`{text}`: the coordinate {} is beyond ±{:e} m (MAX_COORDINATE), where f64 cannot resolve the motion: place the scene near the origin",
                        ffr_spec::text::Num(*x),
                        ffr_spec::scene::MAX_COORDINATE,
                        text = q(text)
                    ),
                )),
            }
        };
        if name == "ground" {
            let p = rest.and_then(point).ok_or_else(|| {
                self.c.err(
                    span.clone(),
                    format!(
                        "`{text}`: the ground needs a point, `ground@[x, y{}]`; {}",
                        if self.dim == 3 { ", z" } else { "" },
                        allowed(),
                        text = q(text)
                    ),
                )
            })?;
            return Ok(MarkerPoint::Ground(far(p)?));
        }
        let Some(i) = self.names.iter().position(|n| n == name) else {
            return Err(self.c.err(
                span.clone(),
                format!(
                    "`{text}`: no body named `{name}`; {}",
                    allowed(),
                    text = q(text),
                    name = q(name)
                ),
            ));
        };
        match rest {
            None => Ok(MarkerPoint::Origin(i)),
            Some(r) if r.starts_with("node") => {
                let v = r
                    .strip_prefix("node")
                    .map(str::trim_start)
                    .and_then(|r| r.strip_prefix('='))
                    .map(str::trim)
                    .unwrap_or("");
                let n: usize = v.parse().ok().filter(|n| *n < 1 << 20).ok_or_else(|| {
                    self.c.err(
                        span.clone(),
                        format!(
                            "`{text}`: `node=` needs a 0-based node index; {}",
                            allowed(),
                            text = q(text)
                        ),
                    )
                })?;
                if !self.fe[i] {
                    return Err(self.c.err(
                        span.clone(),
                        format!("`{text}`: `{name}` is not an FE body; `@node=N` names a node of a body with `fe = {{…}}`", text = q(text), name = q(name)),
                    ));
                }
                Ok(MarkerPoint::Node(i, n))
            }
            Some(r) if r.starts_with("x=") || r.starts_with("x =") => {
                let v = r.split_once('=').map(|(_, v)| v.trim()).unwrap_or("");
                let x: f64 = v
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| {
                        self.c.err(
                            span.clone(),
                            format!(
                                "`{text}`: `x=` needs a number; {}",
                                allowed(),
                                text = q(text)
                            ),
                        )
                    })?;
                if self.fe[i] {
                    return Err(self.c.err(
                        span.clone(),
                        format!("`{text}`: `{name}` is an FE body and has no axis; name one of its nodes, `{name}@node=N`", text = q(text), name = q(name)),
                    ));
                }
                if self.rigid[i] {
                    return Err(self.c.err(
                        span.clone(),
                        format!("`{text}`: `{name}` is rigid and has no axis; give a body-frame point `{name}@[x, y{}]`", if self.dim == 3 { ", z" } else { "" }, text = q(text)),
                    ));
                }
                Ok(MarkerPoint::Axis(i, x))
            }
            Some(r) => {
                let p = point(r).ok_or_else(|| {
                    self.c.err(
                        span.clone(),
                        format!("`{text}`: not a marker; {}", allowed(), text = q(text)),
                    )
                })?;
                Ok(MarkerPoint::Point(i, far(p)?))
            }
        }
    }
}
