//! `[bodies.NAME]`: rigid and flexible bodies, their poses, damping,
//! initial velocities and elastic states.

use super::{fin_f64, pos_f64, vec_n, Ctx, Env, Parts};
use crate::codegen::scene::quoted as q;
use crate::codegen::scene::RawBody;
use crate::codegen::scene::RawScene;
use crate::kernels::BeamSpec;
use crate::runtime::nalgebra::{Matrix3, Unit, UnitQuaternion};
use crate::runtime::nalgebra::{Vector2, Vector3};
use crate::runtime::spec::Params;
use crate::runtime::spec::{Param, Reference};
use crate::runtime::Pose;
use crate::runtime::{Body, KernelBody, Rayleigh, RigidBody};
use crate::scene::{FlexSpec, SceneError};
use std::ops::Range;
use toml::Spanned;

/// Add the scene's bodies to the system, in file order.
pub(super) fn add_bodies(
    c: &Ctx,
    raw: &RawScene,
    env: &Env,
    parts: &mut Parts,
) -> Result<(), SceneError> {
    let (dim, base, provider, models) = (env.dim, env.base, env.provider, env.models);
    let Parts {
        sys,
        kernels: kernels_used,
        flex,
        ..
    } = parts;
    for (name, body) in &raw.bodies {
        let (name_s, rb) = (name.get_ref(), body);
        let span = body.span().unwrap_or(0..0);
        let pose = pose(c, rb, dim, span.clone())?;
        let boxed: Box<dyn Body> = if let Some(m) = &rb.mass {
            for (k, v) in [
                ("shape", rb.shape.is_some()),
                ("elements", rb.elements.is_some()),
                ("params", rb.params.is_some()),
            ] {
                if v {
                    return Err(c.err(span.clone(), format!("body `{name_s}` has `mass` (rigid) and `{k}` (flexible): give one kind")));
                }
            }
            let mass = pos_f64(c, m, "mass")?;
            let com = match &rb.centre {
                Some(v) => vec_n(c, v, dim, "centre")?,
                None => Vector3::zeros(),
            };
            let inertia = rb.inertia.as_ref().ok_or_else(|| c.err(span.clone(), format!("rigid body `{name_s}` needs `inertia` (planar: a number about the centre of mass; spatial: [Ixx, Iyy, Izz] or a 3×3 table)")))?;
            let rbody = if dim == 2 {
                let j = inertia
                    .get_ref()
                    .as_float()
                    .or_else(|| inertia.get_ref().as_integer().map(|i| i as f64))
                    .ok_or_else(|| {
                        c.err(
                            inertia.span(),
                            "planar `inertia` is one number (kg m², about the centre of mass)",
                        )
                    })?;
                RigidBody::planar(mass, j, Vector2::new(com.x, com.y))
            } else {
                let m3 = inertia3(c, inertia)?;
                RigidBody::spatial(mass, m3, com)
            }
            .map_err(|e| c.err(span.clone(), format!("body `{name_s}`: {e}")))?;
            kernels_used.push((name_s.clone(), "rigid".to_string()));
            Box::new(rbody)
        } else {
            let shape = rb.shape.as_ref().ok_or_else(|| c.err(span.clone(), format!("body `{name_s}` needs `shape = \"beam2\"` (flexible) or `mass = …` (rigid)")))?;
            let elements = rb.elements.as_ref().ok_or_else(|| {
                c.err(
                    span.clone(),
                    format!("flexible body `{name_s}` needs `elements = N`"),
                )
            })?;
            let n = *elements.get_ref();
            if !(1..=ffr_spec_max() as i64).contains(&n) {
                return Err(c.err(
                    elements.span(),
                    format!("`elements` must be 1 to {}, found {n}", ffr_spec_max()),
                ));
            }
            let reference = match &rb.reference {
                Some(r) => r.get_ref().parse::<Reference>().map_err(|_| {
                    c.err(
                        r.span(),
                        format!(
                            "unknown reference condition `{}`: expected clamped, pinned or free",
                            q(r.get_ref())
                        ),
                    )
                })?,
                None => Reference::Clamped,
            };
            let model = models
                .iter()
                .find(|m| &m.name == name_s)
                .expect("every flexible body has a model")
                .clone();
            let stiffening = model.options.stiffening;
            let modal = modal_settings(c, name_s, rb, n as usize)?;
            let (params, given, params_span) = parse_params(c, name_s, rb, span.clone())?;
            let shape_s = shape.get_ref();
            let resolved = if crate::codegen::Shape::builtin(shape_s).is_some() {
                shape_s.clone()
            } else {
                base.join(shape_s).display().to_string()
            };
            let beam = BeamSpec {
                shape: resolved,
                elements: n as usize,
                reference,
                // The scene's model: what it fixes, carried unchanged.
                options: model.options,
                params,
                force_tape: false,
            };
            let spec = FlexSpec { model, beam };
            let (kernels, path) = provider
                .kernels(&spec)
                .map_err(|e| c.err(shape.span(), format!("body `{name_s}`: {e}")))?;
            let dimension = kernels.info().dim;
            if dimension > dim {
                return Err(c.err(shape.span(), format!("body `{name_s}`: shape `{shape_s}` is spatial; a planar scene needs a planar shape", shape_s = q(shape_s))));
            }
            // A parameter the body uses must be given (a missing one would
            // be reported as zero).
            let used = &kernels.info().params_used;
            if let Some(missing) = Param::FIELDS
                .iter()
                .enumerate()
                .find(|(i, f)| !given[*i] && used.contains(f))
            {
                let names: Vec<&str> = used.iter().map(|p| p.field()).collect();
                return Err(c.err(
                    params_span,
                    format!(
                        "body `{name_s}`: `params` needs `{}`: shape `{shape_s}` in this scene uses {}",
                        missing.1.field(),
                        names.join(", "), shape_s = q(shape_s)),
                ));
            }
            let kb = KernelBody::new(kernels, params, n as usize, reference)
                .map_err(|e| c.err(span.clone(), format!("body `{name_s}`: {e}")))?;
            let boxed: Box<dyn Body> = match &modal {
                None => {
                    kernels_used.push((name_s.clone(), path.to_string()));
                    Box::new(kb)
                }
                Some((settings, modes_span)) => {
                    let b = &spec.beam;
                    let mb = crate::modal::ReducibleBody::from_parts(
                        &b.shape,
                        b.elements,
                        b.reference,
                        b.options.formalism,
                        b.params,
                    )
                    .and_then(|r| r.runtime_body(settings, stiffening, Box::new(kb)))
                    .map_err(|e| c.err(modes_span.clone(), format!("body `{name_s}`: {e}")))?;
                    kernels_used.push((
                        name_s.clone(),
                        format!(
                            "modal, {} modes ({path} full body for markers)",
                            mb.layout().nf
                        ),
                    ));
                    Box::new(mb)
                }
            };
            flex.push(spec);
            boxed
        };
        let id = sys
            .add_body(name_s, boxed, pose)
            .map_err(|e| c.err(span.clone(), e.to_string()))?;
        if let Some(d) = &rb.damping {
            if rigid_body(rb) {
                return Err(c.err(
                    d.span(),
                    format!("body `{name_s}` is rigid: `damping` is for elastic coordinates"),
                ));
            }
            let r = Rayleigh {
                alpha: d
                    .get_ref()
                    .alpha
                    .as_ref()
                    .map_or(Ok(0.0), |x| fin_f64(c, x, "alpha"))?,
                beta: d
                    .get_ref()
                    .beta
                    .as_ref()
                    .map_or(Ok(0.0), |x| fin_f64(c, x, "beta"))?,
            };
            sys.set_damping(id, r)
                .map_err(|e| c.err(d.span(), e.to_string()))?;
        }
        let v = match &rb.velocity {
            Some(v) => vec_n(c, v, dim, "velocity")?,
            None => Vector3::zeros(),
        };
        let w = match &rb.omega {
            None => Vector3::zeros(),
            Some(o) => match (dim, o.get_ref()) {
                (2, toml::Value::Float(x)) => Vector3::new(0.0, 0.0, *x),
                (2, toml::Value::Integer(x)) => Vector3::new(0.0, 0.0, *x as f64),
                (3, toml::Value::Array(a)) if a.len() == 3 => {
                    let xs: Option<Vec<f64>> = a
                        .iter()
                        .map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
                        .collect();
                    let xs = xs.ok_or_else(|| c.err(o.span(), "`omega` must be three numbers"))?;
                    Vector3::new(xs[0], xs[1], xs[2])
                }
                _ => {
                    return Err(c.err(
                        o.span(),
                        if dim == 2 {
                            "planar `omega` is one number (rad/s about z)"
                        } else {
                            "spatial `omega` is [ωx, ωy, ωz] (rad/s, global)"
                        },
                    ))
                }
            },
        };
        if v.norm() > 0.0 || w.norm() > 0.0 {
            sys.set_velocity(id, v, w)
                .map_err(|e| c.err(span.clone(), e.to_string()))?;
        }
        if let Some(el) = &rb.elastic {
            if rigid_body(rb) {
                return Err(c.err(
                    el.span(),
                    format!("body `{name_s}` is rigid: `elastic` is the initial state of a flexible body"),
                ));
            }
            let labels = sys.body(id).layout().labels.clone();
            let by_label = |t: &Option<Spanned<crate::codegen::scene::RawLabelled>>,
                            what: &str|
             -> Result<Vec<f64>, SceneError> {
                let mut out = vec![0.0; labels.len()];
                for (k, x) in t.iter().flat_map(|t| t.get_ref()) {
                    let Some(i) = labels.iter().position(|l| l == k.get_ref()) else {
                        return Err(c.err(
                            k.span(),
                            format!(
                                "body `{name_s}` has no elastic coordinate `{}`; its coordinates are {}",
                                q(k.get_ref()),
                                labels.join(", ")
                            ),
                        ));
                    };
                    out[i] = fin_f64(c, x, &format!("{what}.{}", k.get_ref()))?;
                }
                Ok(out)
            };
            let q_f = by_label(&el.get_ref().q, "q")?;
            let qd_f = by_label(&el.get_ref().qd, "qd")?;
            sys.set_elastic(id, &q_f, &qd_f)
                .map_err(|e| c.err(el.span(), e.to_string()))?;
        }
    }
    Ok(())
}

const PARAMS: &str = "length, rho, area, iy, iz, e, g, j";

fn parse_params(
    c: &Ctx,
    body: &str,
    raw: &RawBody,
    span: Range<usize>,
) -> Result<(Params, [bool; 8], Range<usize>), SceneError> {
    let Some(p) = &raw.params else {
        return Err(c.err(
            span,
            format!("flexible body `{body}` needs `params = {{ {PARAMS} }}` (SI units)"),
        ));
    };
    let mut v = [0.0; 8];
    let mut given = [false; 8];
    for (k, val) in p.get_ref() {
        let Some(i) = Param::FIELDS.iter().position(|f| f.field() == k.get_ref()) else {
            return Err(c.err(
                k.span(),
                format!(
                    "unknown parameter `{}`: expected one of {PARAMS}",
                    q(k.get_ref())
                ),
            ));
        };
        v[i] = fin_f64(c, val, k.get_ref())?;
        given[i] = true;
    }
    if !given[0] {
        return Err(c.err(p.span(), format!("body `{body}`: `params` needs `length`")));
    }
    Ok((Params::from_array(v), given, p.span()))
}

fn rigid_body(rb: &RawBody) -> bool {
    rb.mass.is_some()
}

fn ffr_spec_max() -> usize {
    crate::runtime::spec::MAX_ELEMENTS
}

fn inertia3(c: &Ctx, v: &Spanned<toml::Value>) -> Result<Matrix3<f64>, SceneError> {
    let num = |x: &toml::Value| x.as_float().or_else(|| x.as_integer().map(|i| i as f64));
    let bad = || {
        c.err(v.span(), "spatial `inertia` is [Ixx, Iyy, Izz] or a 3×3 table [[…], […], […]] (kg m², about the centre of mass)")
    };
    let a = v.get_ref().as_array().ok_or_else(bad)?;
    if a.len() == 3 && a.iter().all(|x| num(x).is_some()) {
        let d: Vec<f64> = a.iter().map(|x| num(x).expect("checked")).collect();
        return Ok(Matrix3::from_diagonal(&Vector3::new(d[0], d[1], d[2])));
    }
    if a.len() == 3 {
        let mut m = Matrix3::zeros();
        for (i, row) in a.iter().enumerate() {
            let r = row.as_array().filter(|r| r.len() == 3).ok_or_else(bad)?;
            for (j, x) in r.iter().enumerate() {
                m[(i, j)] = num(x).ok_or_else(bad)?;
            }
        }
        return Ok(m);
    }
    Err(bad())
}

fn pose(c: &Ctx, rb: &RawBody, dim: usize, span: Range<usize>) -> Result<Pose, SceneError> {
    let p = match &rb.position {
        Some(v) => vec_n(c, v, dim, "position")?,
        None => Vector3::zeros(),
    };
    if dim == 2 {
        if let Some(o) = &rb.orientation {
            return Err(c.err(o.span(), "a planar body has `angle`, not `orientation`"));
        }
        let a = rb
            .angle
            .as_ref()
            .map_or(Ok(0.0), |x| fin_f64(c, x, "angle"))?;
        Ok(Pose::planar(p.x, p.y, a))
    } else {
        if let Some(a) = &rb.angle {
            return Err(c.err(
                a.span(),
                "a spatial body has `orientation = { axis = [x, y, z], angle = … }`, not `angle`",
            ));
        }
        let q = match &rb.orientation {
            None => UnitQuaternion::identity(),
            Some(o) => {
                let ax = vec_n(c, &o.get_ref().axis, 3, "axis")?;
                if ax.norm() == 0.0 {
                    return Err(c.err(o.get_ref().axis.span(), "`axis` must not be zero"));
                }
                let ang = fin_f64(c, &o.get_ref().angle, "angle")?;
                UnitQuaternion::from_axis_angle(&Unit::new_normalize(ax), ang)
            }
        };
        let _ = span;
        Ok(Pose::spatial(p, q))
    }
}

/// The modal reduction a flexible body's keys ask for (`modes`, `reduction`,
/// `boundary_nodes`, `static_modes`, `modal_damping`), with the span errors
/// about it point at; `None` without `modes`.
#[allow(clippy::type_complexity)]
fn modal_settings(
    c: &Ctx,
    name: &str,
    rb: &crate::codegen::scene::RawBody,
    elements: usize,
) -> Result<Option<(crate::modal::ModalSettings, std::ops::Range<usize>)>, SceneError> {
    let Some(modes) = &rb.modes else {
        for (key, span) in [
            ("reduction", rb.reduction.as_ref().map(|x| x.span())),
            (
                "boundary_nodes",
                rb.boundary_nodes.as_ref().map(|x| x.span()),
            ),
            ("static_modes", rb.static_modes.as_ref().map(|x| x.span())),
            ("modal_damping", rb.modal_damping.as_ref().map(|x| x.span())),
        ] {
            if let Some(span) = span {
                return Err(c.err(
                    span,
                    format!("body `{name}`: `{key}` needs `modes = K` (a modal body)"),
                ));
            }
        }
        return Ok(None);
    };
    let k = *modes.get_ref();
    if !(1..=4096).contains(&k) {
        return Err(c.err(
            modes.span(),
            format!("body `{name}`: `modes` must be a positive number of normal modes, found {k}"),
        ));
    }
    let cb = match rb
        .reduction
        .as_ref()
        .map(|r| (r.get_ref().as_str(), r.span()))
    {
        None | Some(("modal", _)) => false,
        Some(("craig-bampton", _)) => true,
        Some((other, span)) => {
            return Err(c.err(
                span,
                format!(
                    "body `{name}`: `reduction` is \"modal\" or \"craig-bampton\", found `{other}`",
                    other = q(other)
                ),
            ))
        }
    };
    let boundary = match (&rb.boundary_nodes, cb) {
        (Some(b), false) => {
            return Err(c.err(
                b.span(),
                format!("body `{name}`: `boundary_nodes` is for `reduction = \"craig-bampton\"`"),
            ))
        }
        (Some(b), true) => {
            let mut out = Vec::new();
            for &node in b.get_ref() {
                if !(0..=elements as i64).contains(&node) {
                    return Err(c.err(
                        b.span(),
                        format!("body `{name}`: boundary node {node} out of range: the body has nodes 0 to {elements}"),
                    ));
                }
                out.push(node as usize);
            }
            if out.is_empty() {
                return Err(c.err(
                    b.span(),
                    format!("body `{name}`: `boundary_nodes` is empty"),
                ));
            }
            out
        }
        (None, true) => vec![elements],
        (None, false) => Vec::new(),
    };
    let damping = match &rb.modal_damping {
        None => Vec::new(),
        Some(v) => {
            let num = |x: &toml::Value| x.as_float().or_else(|| x.as_integer().map(|i| i as f64));
            let zs: Option<Vec<f64>> = match v.get_ref() {
                toml::Value::Array(a) => a.iter().map(num).collect(),
                x => num(x).map(|z| vec![z]),
            };
            let zs = zs
                .filter(|zs| !zs.is_empty() && zs.iter().all(|z| z.is_finite() && *z >= 0.0))
                .ok_or_else(|| {
                    c.err(
                        v.span(),
                        format!("body `{name}`: `modal_damping` is a ratio ζ ≥ 0 for every normal mode, or a list of one per normal mode"),
                    )
                })?;
            zs
        }
    };
    Ok(Some((
        crate::modal::ModalSettings {
            modes: k as usize,
            boundary,
            static_modes: rb.static_modes.as_ref().is_none_or(|s| *s.get_ref()),
            damping,
        },
        modes.span(),
    )))
}
