//! Markers as a scene writes them: a point on the ground, a body's frame
//! origin, a point on a beam's axis, a point fixed in a body's frame.

use super::Ctx;
use crate::codegen::scene::quoted as q;
use crate::runtime::nalgebra::Vector3;
use crate::runtime::{Body, BodyId, Marker, System};
use crate::scene::SceneError;
use toml::Spanned;

/// A marker in the scene's syntax.
#[derive(Clone, Debug)]
pub(super) enum MarkerRef {
    Ground(Vector3<f64>),
    Origin(BodyId),
    Axis(BodyId, f64),
    Point(BodyId, Vector3<f64>),
}

/// The markers of a scene (`ground@[x, y]`, `NAME`, `NAME@x=…`,
/// `NAME@[x, y]`), resolved against its bodies.
pub(super) struct Markers<'a> {
    pub(super) c: &'a Ctx<'a>,
    pub(super) dim: usize,
    pub(super) names: Vec<String>,
    pub(super) rigid: Vec<bool>,
}

impl Markers<'_> {
    pub(super) fn marker_ref(&self, s: &Spanned<String>) -> Result<MarkerRef, SceneError> {
        let text = s.get_ref().trim();
        let allowed = || {
            format!(
                "a marker is `ground@[x, y{}]`, `NAME` (a body's frame origin), `NAME@x=…` (a point on a beam's axis) or `NAME@[x, y{}]` (a point fixed in a body's frame); bodies: {}",
                if self.dim == 3 { ", z" } else { "" },
                if self.dim == 3 { ", z" } else { "" },
                self.names.join(", ")
            )
        };
        let (name, rest) = match text.split_once('@') {
            Some((n, r)) => (n.trim(), Some(r.trim())),
            None => (text, None),
        };
        let point = |r: &str| -> Option<Vector3<f64>> {
            let inner = r.strip_prefix('[')?.strip_suffix(']')?;
            let xs: Vec<f64> = inner
                .split(',')
                .map(|x| x.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<_>>()?;
            if xs.len() != self.dim {
                return None;
            }
            let mut v = Vector3::zeros();
            v.as_mut_slice()[..self.dim].copy_from_slice(&xs);
            Some(v)
        };
        if name == "ground" {
            let p = rest.and_then(point).ok_or_else(|| {
                self.c.err(
                    s.span(),
                    format!(
                        "`{text}`: the ground needs a point, `ground@[x, y{}]`; {}",
                        if self.dim == 3 { ", z" } else { "" },
                        allowed(),
                        text = q(text)
                    ),
                )
            })?;
            return Ok(MarkerRef::Ground(p));
        }
        let Some(i) = self.names.iter().position(|n| n == name) else {
            return Err(self.c.err(
                s.span(),
                format!(
                    "`{text}`: no body named `{name}`; {}",
                    allowed(),
                    text = q(text),
                    name = q(name)
                ),
            ));
        };
        let b = BodyId(i);
        match rest {
            None => Ok(MarkerRef::Origin(b)),
            Some(r) if r.starts_with("x=") || r.starts_with("x =") => {
                let v = r.split_once('=').map(|(_, v)| v.trim()).unwrap_or("");
                let x: f64 = v
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| {
                        self.c.err(
                            s.span(),
                            format!(
                                "`{text}`: `x=` needs a number; {}",
                                allowed(),
                                text = q(text)
                            ),
                        )
                    })?;
                if self.rigid[i] {
                    return Err(self.c.err(
                        s.span(),
                        format!("`{text}`: `{name}` is rigid and has no axis; give a body-frame point `{name}@[x, y{}]`", if self.dim == 3 { ", z" } else { "" }, text = q(text)),
                    ));
                }
                Ok(MarkerRef::Axis(b, x))
            }
            Some(r) => point(r).map(|p| MarkerRef::Point(b, p)).ok_or_else(|| {
                self.c.err(
                    s.span(),
                    format!("`{text}`: not a marker; {}", allowed(), text = q(text)),
                )
            }),
        }
    }

    pub(super) fn marker(
        &self,
        sys: &System<Box<dyn Body>>,
        s: &Spanned<String>,
    ) -> Result<Marker, SceneError> {
        Ok(match self.marker_ref(s)? {
            MarkerRef::Ground(p) => Marker::ground(p),
            MarkerRef::Origin(b) => Marker::origin(b),
            MarkerRef::Point(b, p) => Marker::at(b, p),
            MarkerRef::Axis(b, x) => sys
                .point(b, x)
                .map_err(|e| self.c.err(s.span(), format!("`{}`: {e}", q(s.get_ref()))))?,
        })
    }
}
