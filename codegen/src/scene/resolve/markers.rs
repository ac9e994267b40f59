//! Markers as a scene writes them: a point on the ground, a body's frame
//! origin, a point on a beam's axis, a point fixed in a body's frame.

use super::Ctx;
use crate::error::Error;
use crate::scene::quoted as q;
use ffr_spec::scene::{MarkerPoint, MarkerSpec};
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
    pub(super) fn marker(&self, s: &Spanned<String>) -> Result<MarkerSpec, Error> {
        Ok(MarkerSpec {
            point: self.point(s)?,
            text: s.get_ref().clone(),
            at: self.c.loc(s.span()),
        })
    }

    /// The point the marker written as `s` names.
    pub(super) fn point(&self, s: &Spanned<String>) -> Result<MarkerPoint, Error> {
        let text = s.get_ref().trim();
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
            return Ok(MarkerPoint::Ground(p));
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
                        s.span(),
                        format!(
                            "`{text}`: `node=` needs a 0-based node index; {}",
                            allowed(),
                            text = q(text)
                        ),
                    )
                })?;
                if !self.fe[i] {
                    return Err(self.c.err(
                        s.span(),
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
                            s.span(),
                            format!(
                                "`{text}`: `x=` needs a number; {}",
                                allowed(),
                                text = q(text)
                            ),
                        )
                    })?;
                if self.fe[i] {
                    return Err(self.c.err(
                        s.span(),
                        format!("`{text}`: `{name}` is an FE body and has no axis; name one of its nodes, `{name}@node=N`", text = q(text), name = q(name)),
                    ));
                }
                if self.rigid[i] {
                    return Err(self.c.err(
                        s.span(),
                        format!("`{text}`: `{name}` is rigid and has no axis; give a body-frame point `{name}@[x, y{}]`", if self.dim == 3 { ", z" } else { "" }, text = q(text)),
                    ));
                }
                Ok(MarkerPoint::Axis(i, x))
            }
            Some(r) => point(r).map(|p| MarkerPoint::Point(i, p)).ok_or_else(|| {
                self.c.err(
                    s.span(),
                    format!("`{text}`: not a marker; {}", allowed(), text = q(text)),
                )
            }),
        }
    }
}
