//! `[bodies.NAME]`: rigid and flexible bodies, their poses, damping,
//! initial velocities and elastic states.

use super::{fin_f64, pos_f64, sections, vec_n, Ctx};
use crate::error::Error;
use crate::scene::quoted as q;
use crate::scene::{FlexBodyModel, RawBody, RawFe, RawLabelled, RawScene};
use ffr_spec::scene::{
    BodyKind, BodySpec, ElasticSpec, FeSpec, FlexSpec, ModalSettings, Orientation,
};
use ffr_spec::text::Num;
use ffr_spec::{Param, Params, Reference};
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// The scene's bodies, in file order.
pub(super) fn bodies(
    c: &Ctx,
    raw: &RawScene,
    dim: usize,
    base: &Path,
    models: &[FlexBodyModel],
) -> Result<Vec<BodySpec>, Error> {
    let mut out = Vec::new();
    for (name, rb) in &raw.bodies {
        let name_s = name.get_ref();
        let span = rb.span().unwrap_or(0..0);
        let (position, orientation) = pose(c, rb, dim)?;
        let kind = if let Some(m) = &rb.mass {
            for (k, v) in [
                ("shape", rb.shape.is_some()),
                ("elements", rb.elements.is_some()),
                ("params", rb.params.is_some()),
                ("masses", rb.masses.is_some()),
            ] {
                if v {
                    return Err(c.err(span.clone(), format!("body `{name_s}` has `mass` (rigid) and `{k}` (flexible): give one kind")));
                }
            }
            let mass = pos_f64(c, m, "mass")?;
            let centre = match &rb.centre {
                Some(v) => vec_n(c, v, dim, "centre")?,
                None => [0.0; 3],
            };
            let inertia = rb.inertia.as_ref().ok_or_else(|| c.err(span.clone(), format!("rigid body `{name_s}` needs `inertia` (planar: a number about the centre of mass; spatial: [Ixx, Iyy, Izz] or a 3×3 table)")))?;
            let inertia = if dim == 2 {
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
                [[0.0; 3], [0.0; 3], [0.0, 0.0, j]]
            } else {
                inertia3(c, inertia)?
            };
            BodyKind::Rigid {
                mass,
                inertia,
                centre,
            }
        } else if let Some(fe) = &rb.fe {
            fe_body(c, name_s, rb, fe, dim, base)?
        } else {
            let shape = rb.shape.as_ref().ok_or_else(|| c.err(span.clone(), format!("body `{name_s}` needs `shape = \"beam2\"` (flexible) or `mass = …` (rigid)")))?;
            let (n, nodes) = mesh(c, name_s, rb, span.clone())?;
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
                .expect("every flexible body has a model");
            let modal = modal_settings(c, name_s, rb, n)?;
            let (params, given, params_span, sections) = match &rb.sections {
                None => {
                    let (p, g, s, rho_j) = parse_params(c, name_s, rb, span.clone())?;
                    let table = match rho_j {
                        None => None,
                        Some((x, at)) => Some(uniform_table(c, name_s, &p, x, at)?),
                    };
                    (p, g, s, table)
                }
                Some(v) => {
                    if let Some(p) = &rb.params {
                        return Err(c.err(
                            p.span(),
                            format!("body `{name_s}` has `params` and `sections`: give one (`params`: a uniform beam; `sections`: properties along the span, the length is the last station's x)"),
                        ));
                    }
                    match sections::sections(c, name_s, v, base)? {
                        // One uniform section in the material form: the
                        // uniform body of its parameters.
                        (_, Some(p)) => (p, [true; 8], v.span(), None),
                        (table, None) => {
                            let length = table.stations.last().expect("two stations or more").x;
                            let mut p = [0.0; 8];
                            p[0] = length;
                            let mut given = [false; 8];
                            given[0] = true;
                            (Params::from_array(p), given, v.span(), Some(table))
                        }
                    }
                }
            };
            if let (true, Some(m)) = (nodes.is_some() || rb.sections.is_some(), &rb.modes) {
                return Err(c.err(
                    m.span(),
                    format!("body `{name_s}`: a modal body needs equal elements of a uniform section (`elements = N`, `params`); a graded mesh (`nodes`) or a section table (`sections`) is not reduced yet"),
                ));
            }
            if let Some((xs, at)) = &nodes {
                ffr_spec::check_nodes(xs, params.length)
                    .map_err(|e| c.err(at.clone(), format!("body `{name_s}`: {e}")))?;
            }
            let masses = attached_masses(c, name_s, rb, params.length)?;
            if let (false, Some(m)) = (masses.is_empty(), &rb.modes) {
                return Err(c.err(
                    m.span(),
                    format!("body `{name_s}`: a modal body with attached masses (`masses`) is not reduced yet: remove `modes` or the masses"),
                ));
            }
            let (segments, segments_at) = match &rb.segments {
                None => (1, None),
                Some(s) => {
                    let k = ffr_spec::check_segments(*s.get_ref(), n)
                        .map_err(|e| c.err(s.span(), format!("body `{name_s}`: {e}")))?;
                    if let (true, Some(el)) = (k > 1, &rb.elastic) {
                        return Err(c.err(
                            el.span(),
                            format!("body `{name_s}` runs as {k} segments: an initial elastic state (`elastic`) names the coordinates of one frame and is not available for a segmented body; start it undeformed or use `segments = 1`"),
                        ));
                    }
                    (k, Some(c.loc(s.span())))
                }
            };
            let shape_s = shape.get_ref();
            let resolved = if crate::Shape::builtin(shape_s).is_some() {
                shape_s.clone()
            } else {
                base.join(shape_s).display().to_string()
            };
            BodyKind::Flexible(FlexSpec {
                name: name_s.clone(),
                shape: resolved,
                shape_name: shape_s.clone(),
                shape_at: c.loc(shape.span()),
                elements: n,
                nodes: nodes.map(|(xs, _)| xs),
                reference,
                // The scene's model: what it fixes, carried unchanged.
                options: model.options,
                params,
                given,
                params_at: c.loc(params_span),
                modal: modal.map(|(s, span)| (s, c.loc(span))),
                sections,
                masses,
                segments,
                segments_at,
            })
        };
        let rigid = rigid_body(rb);
        let damping = match &rb.damping {
            None => None,
            Some(d) => {
                if rigid {
                    return Err(c.err(
                        d.span(),
                        format!("body `{name_s}` is rigid: `damping` is for elastic coordinates"),
                    ));
                }
                let alpha = d
                    .get_ref()
                    .alpha
                    .as_ref()
                    .map_or(Ok(0.0), |x| fin_f64(c, x, "alpha"))?;
                let beta = d
                    .get_ref()
                    .beta
                    .as_ref()
                    .map_or(Ok(0.0), |x| fin_f64(c, x, "beta"))?;
                Some((alpha, beta, c.loc(d.span())))
            }
        };
        let velocity = match &rb.velocity {
            Some(v) => vec_n(c, v, dim, "velocity")?,
            None => [0.0; 3],
        };
        let omega = match &rb.omega {
            None => [0.0; 3],
            Some(o) => match (dim, o.get_ref()) {
                (2, toml::Value::Float(x)) => [0.0, 0.0, *x],
                (2, toml::Value::Integer(x)) => [0.0, 0.0, *x as f64],
                (3, toml::Value::Array(a)) if a.len() == 3 => {
                    let xs: Option<Vec<f64>> = a
                        .iter()
                        .map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
                        .collect();
                    let xs = xs.ok_or_else(|| c.err(o.span(), "`omega` must be three numbers"))?;
                    [xs[0], xs[1], xs[2]]
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
        let elastic = match &rb.elastic {
            None => None,
            Some(el) => {
                if rigid {
                    return Err(c.err(
                        el.span(),
                        format!("body `{name_s}` is rigid: `elastic` is the initial state of a flexible body"),
                    ));
                }
                let entries =
                    |t: &Option<Spanned<RawLabelled>>,
                     what: &str|
                     -> Result<Vec<(String, f64, ffr_spec::Location)>, Error> {
                        let mut out = Vec::new();
                        for (k, x) in t.iter().flat_map(|t| t.get_ref()) {
                            let v = fin_f64(c, x, &format!("{what}.{}", k.get_ref()))?;
                            out.push((k.get_ref().clone(), v, c.loc(k.span())));
                        }
                        Ok(out)
                    };
                Some(ElasticSpec {
                    at: c.loc(el.span()),
                    q: entries(&el.get_ref().q, "q")?,
                    qd: entries(&el.get_ref().qd, "qd")?,
                })
            }
        };
        out.push(BodySpec {
            name: name_s.clone(),
            at: c.loc(span),
            kind,
            position,
            orientation,
            damping,
            velocity,
            omega,
            elastic,
        });
    }
    Ok(out)
}

/// The largest node index an FE body's keys may name before its node file
/// is read (the reader's bound on nodes; the file's own count is checked
/// when the scene is built).
const MAX_FE_NODE_INDEX: i64 = 1 << 20;

/// A body from finite-element matrices (`fe = {…}`): the files resolved
/// against the scene file's directory, `reference` (`clamped` with
/// `interface` nodes, or `free`), the reduction (`modes` required;
/// Craig–Bampton on `boundary_nodes`). What needs the files (node counts,
/// mode counts) is checked when the scene is built.
fn fe_body(
    c: &Ctx,
    name: &str,
    rb: &RawBody,
    fe: &Spanned<RawFe>,
    dim: usize,
    base: &Path,
) -> Result<BodyKind, Error> {
    let raw = fe.get_ref();
    if dim != 3 {
        return Err(c.err(
            fe.span(),
            format!("FE body `{name}`: an FE body is spatial (three translations per node): use `dimension = 3`"),
        ));
    }
    if let Some(m) = &rb.masses {
        return Err(c.err(
            m.first().map_or(fe.span(), |m| m.span()),
            format!("FE body `{name}`: attached masses (`masses`) are on a beam's axis; put the mass into the FE model's mass matrix"),
        ));
    }
    let file = |v: &Spanned<String>, what: &str| -> Result<String, Error> {
        let s = v.get_ref();
        if s.trim().is_empty() {
            return Err(c.err(
                v.span(),
                format!("FE body `{name}`: `fe.{what}` is an empty path"),
            ));
        }
        Ok(base.join(s).display().to_string())
    };
    let nodes = file(&raw.nodes, "nodes")?;
    let mass = file(&raw.mass, "mass")?;
    let stiffness = file(&raw.stiffness, "stiffness")?;
    let stiffness_scale = match &raw.stiffness_scale {
        None => 1.0,
        Some(v) => pos_f64(c, v, "fe.stiffness_scale")?,
    };
    let free = match rb.reference.as_ref().map(|r| (r.get_ref().as_str(), r.span())) {
        None | Some(("clamped", _)) => false,
        Some(("free", _)) => true,
        Some((other, span)) => {
            return Err(c.err(
                span,
                format!(
                    "FE body `{name}`: `reference` is \"clamped\" (the frame fixed to the interface nodes) or \"free\" (free-free modes), found `{}`",
                    q(other)
                ),
            ))
        }
    };
    let interface = match &rb.interface {
        None => Vec::new(),
        Some(v) => {
            let mut out = Vec::new();
            for &i in v.get_ref() {
                if !(0..MAX_FE_NODE_INDEX).contains(&i) {
                    return Err(c.err(
                        v.span(),
                        format!("FE body `{name}`: interface node {i} is not a 0-based node index"),
                    ));
                }
                if out.contains(&(i as usize)) {
                    return Err(c.err(
                        v.span(),
                        format!("FE body `{name}`: interface node {i} appears twice"),
                    ));
                }
                out.push(i as usize);
            }
            out
        }
    };
    if let (true, Some(v)) = (free, &rb.interface) {
        return Err(c.err(
            v.span(),
            format!("FE body `{name}`: `interface` names the nodes a clamped body's frame is fixed to; a free body (`reference = \"free\"`) keeps every node free and has no interface: remove `interface`, or use `reference = \"clamped\"`"),
        ));
    }
    if !free && interface.is_empty() {
        return Err(c.err(
            rb.interface.as_ref().map_or(fe.span(), |v| v.span()),
            format!("FE body `{name}`: a clamped FE body needs `interface = [i, j, …]`, the nodes its frame is fixed to (0-based rows of the node file); or `reference = \"free\"`"),
        ));
    }
    let Some(modes) = &rb.modes else {
        return Err(c.err(
            fe.span(),
            format!("FE body `{name}` needs `modes = K`: an FE body runs reduced to its K lowest normal modes (plus static modes)"),
        ));
    };
    if let Some(b) = &rb.boundary_nodes {
        if let Some(i) = b
            .get_ref()
            .iter()
            .find(|i| !(0..MAX_FE_NODE_INDEX).contains(*i))
        {
            return Err(c.err(
                b.span(),
                format!("FE body `{name}`: boundary node {i} is not a 0-based node index"),
            ));
        }
    }
    // The beams' checks of `modes`, `reduction`, `modal_damping`; the
    // boundary is FE nodes, checked here and against the node file when
    // the scene is built.
    let (mut settings, modes_span) =
        modal_settings(c, name, rb, MAX_FE_NODE_INDEX as usize)?.expect("`modes` is given");
    if rb
        .reduction
        .as_ref()
        .is_some_and(|r| r.get_ref() == "craig-bampton")
    {
        if free {
            return Err(c.err(
                rb.reduction.as_ref().map_or(modes.span(), |r| r.span()),
                format!("FE body `{name}`: Craig–Bampton on a free FE body is not available: its constraint modes contain the rigid motions the frame already has; use `reference = \"clamped\"` with `boundary_nodes`"),
            ));
        }
        let Some(b) = &rb.boundary_nodes else {
            return Err(c.err(
                rb.reduction.as_ref().map_or(modes.span(), |r| r.span()),
                format!("FE body `{name}`: `reduction = \"craig-bampton\"` needs `boundary_nodes = [i, …]`: FE nodes (not interface nodes, which are fixed to the frame) whose displacements are kept as constraint modes"),
            ));
        };
        if let Some(i) = settings.boundary.iter().find(|i| interface.contains(i)) {
            return Err(c.err(
                b.span(),
                format!("FE body `{name}`: boundary node {i} is an interface node: its displacements are fixed to the frame of a clamped body"),
            ));
        }
    }
    settings.boundary.sort_unstable();
    settings.boundary.dedup();
    Ok(BodyKind::Fe(FeSpec {
        name: name.to_string(),
        nodes,
        mass,
        stiffness,
        stiffness_scale,
        fe_at: c.loc(fe.span()),
        free,
        interface,
        interface_at: c.loc(rb.interface.as_ref().map_or(fe.span(), |v| v.span())),
        modal: (settings, c.loc(modes_span)),
    }))
}

/// The mesh a flexible body asks for: `elements = N` equal elements, or
/// `nodes = [0.0, …, L]` (a graded mesh: the nodes and where they are
/// written, checked once the parameters give `length`).
#[allow(clippy::type_complexity)]
fn mesh(
    c: &Ctx,
    name: &str,
    rb: &RawBody,
    span: Range<usize>,
) -> Result<(usize, Option<(Vec<f64>, Range<usize>)>), Error> {
    let max = ffr_spec::MAX_ELEMENTS;
    match (&rb.elements, &rb.nodes) {
        (Some(_), Some(nodes)) => Err(c.err(
            nodes.span(),
            format!("body `{name}` has `elements` and `nodes`: give one (`elements = N`: equal elements; `nodes = [0.0, …, L]`: a graded mesh)"),
        )),
        (None, None) => Err(c.err(
            span,
            format!("flexible body `{name}` needs `elements = N` (equal elements) or `nodes = [0.0, …, L]` (a graded mesh)"),
        )),
        (Some(elements), None) => {
            let n = *elements.get_ref();
            if !(1..=max as i64).contains(&n) {
                return Err(c.err(
                    elements.span(),
                    format!("`elements` must be 1 to {max}, found {n}"),
                ));
            }
            Ok((n as usize, None))
        }
        (None, Some(nodes)) => {
            // Checked with the parameters' `length` (`ffr_spec::check_nodes`).
            let xs = nodes.get_ref();
            Ok((xs.len().saturating_sub(1), Some((xs.clone(), nodes.span()))))
        }
    }
}

const PARAMS: &str = "length, rho, area, iy, iz, e, g, j";

/// The uniform `params`, which they give, where they are written, and the
/// polar mass moment `rho_j` (kg m) when given.
#[allow(clippy::type_complexity)]
fn parse_params(
    c: &Ctx,
    body: &str,
    raw: &RawBody,
    span: Range<usize>,
) -> Result<(Params, [bool; 8], Range<usize>, Option<(f64, Range<usize>)>), Error> {
    let Some(p) = &raw.params else {
        return Err(c.err(
            span,
            format!("flexible body `{body}` needs `params = {{ {PARAMS} }}` (SI units)"),
        ));
    };
    let mut v = [0.0; 8];
    let mut given = [false; 8];
    let mut rho_j = None;
    for (k, val) in p.get_ref() {
        if k.get_ref() == "rho_j" {
            let x = fin_f64(c, val, "rho_j")?;
            if x < 0.0 {
                return Err(c.err(val.span(), format!("`rho_j` must be ≥ 0, found {x:?}")));
            }
            rho_j = Some((x, k.span()));
            continue;
        }
        let Some(i) = Param::FIELDS.iter().position(|f| f.field() == k.get_ref()) else {
            return Err(c.err(
                k.span(),
                format!(
                    "unknown parameter `{}`: expected one of {PARAMS}, rho_j",
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
    Ok((Params::from_array(v), given, p.span(), rho_j))
}

/// Uniform `params` with a polar mass moment `rho_j` of their own: the
/// one-section table (two equal stations, x = 0 and L) the varying-section
/// kernels read, since the uniform kernels tie the polar moment to
/// `ρ (I_y + I_z)`.
fn uniform_table(
    c: &Ctx,
    body: &str,
    p: &Params,
    rho_j: f64,
    at: Range<usize>,
) -> Result<ffr_spec::scene::SectionTable, Error> {
    for (what, v) in [("rho", p.rho), ("area", p.area), ("e", p.e)] {
        if !(v > 0.0) {
            return Err(c.err(
                at.clone(),
                format!("body `{body}`: with `rho_j`, `params` needs `{what}` > 0 (found {v:?}): the section is read as a one-section table of rho, area, iy, iz, e, g, j"),
            ));
        }
    }
    let station = |x: f64| ffr_spec::scene::Station {
        x,
        mass: p.rho * p.area,
        ea: p.e * p.area,
        ei_y: p.e * p.iy,
        ei_z: p.e * p.iz,
        gj: p.g * p.j,
        rho_iy: p.rho * p.iy,
        rho_iz: p.rho * p.iz,
        rho_j,
        twist: 0.0,
    };
    Ok(ffr_spec::scene::SectionTable {
        stations: vec![station(0.0), station(p.length)],
        at: c.loc(at),
    })
}

/// `[[bodies.NAME.masses]]`: each mass's `x` on the axis (`0 ≤ x ≤
/// length`), `mass ≥ 0` and `inertia` (none: zero; a number: `J_zz` of a
/// planar body; `[Jxx, Jyy, Jzz]` or a 3×3 table). That the inertia is a
/// rigid body's, for the body's dimension, is checked where the body is built.
fn attached_masses(
    c: &Ctx,
    name: &str,
    rb: &RawBody,
    length: f64,
) -> Result<Vec<ffr_spec::scene::MassSpec>, Error> {
    let Some(list) = &rb.masses else {
        return Ok(Vec::new());
    };
    if list.len() > MAX_ATTACHED_MASSES {
        return Err(c.err(
            list[0].span(),
            format!(
                "body `{name}` has {} attached masses; at most {MAX_ATTACHED_MASSES}",
                list.len()
            ),
        ));
    }
    let mut out = Vec::new();
    for m in list {
        let raw = m.get_ref();
        let x = fin_f64(c, &raw.x, "x")?;
        if !(0.0..=length).contains(&x) {
            return Err(c.err(
                raw.x.span(),
                format!("body `{name}`: the attached mass's x = {} is not on the axis, which runs from x = 0 to x = {} m", Num(x), Num(length)),
            ));
        }
        let mass = fin_f64(c, &raw.mass, "mass")?;
        if mass < 0.0 {
            return Err(c.err(
                raw.mass.span(),
                format!("body `{name}`: an attached `mass` must not be negative, found {mass}"),
            ));
        }
        let num = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
        let inertia = match &raw.inertia {
            None => [[0.0; 3]; 3],
            Some(v) => match num(v.get_ref()) {
                Some(j) => [[0.0; 3], [0.0; 3], [0.0, 0.0, j]],
                None => inertia3(c, v)?,
            },
        };
        out.push(ffr_spec::scene::MassSpec {
            mass: ffr_spec::AttachedMass { x, mass, inertia },
            at: c.loc(m.span()),
        });
    }
    Ok(out)
}

/// The most masses one body may carry (a bound on what a scene allocates).
const MAX_ATTACHED_MASSES: usize = 10_000;

fn rigid_body(rb: &RawBody) -> bool {
    rb.mass.is_some()
}

fn inertia3(c: &Ctx, v: &Spanned<toml::Value>) -> Result<[[f64; 3]; 3], Error> {
    let num = |x: &toml::Value| x.as_float().or_else(|| x.as_integer().map(|i| i as f64));
    let bad = || {
        c.err(v.span(), "spatial `inertia` is [Ixx, Iyy, Izz] or a 3×3 table [[…], […], […]] (kg m², about the centre of mass)")
    };
    let a = v.get_ref().as_array().ok_or_else(bad)?;
    if a.len() == 3 && a.iter().all(|x| num(x).is_some()) {
        let d: Vec<f64> = a.iter().map(|x| num(x).expect("checked")).collect();
        return Ok([[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]]);
    }
    if a.len() == 3 {
        let mut m = [[0.0; 3]; 3];
        for (i, row) in a.iter().enumerate() {
            let r = row.as_array().filter(|r| r.len() == 3).ok_or_else(bad)?;
            for (j, x) in r.iter().enumerate() {
                m[i][j] = num(x).ok_or_else(bad)?;
            }
        }
        return Ok(m);
    }
    Err(bad())
}

fn pose(c: &Ctx, rb: &RawBody, dim: usize) -> Result<([f64; 3], Orientation), Error> {
    let p = match &rb.position {
        Some(v) => {
            let p = vec_n(c, v, dim, "position")?;
            if let Some(x) = p.iter().find(|x| x.abs() > ffr_spec::scene::MAX_COORDINATE) {
                return Err(c.err(
                    v.span(),
                    format!(
                        "`position`: the coordinate {} is beyond ±{:e} m (MAX_COORDINATE), where f64 cannot resolve the motion: place the scene near the origin",
                        Num(*x),
                        ffr_spec::scene::MAX_COORDINATE
                    ),
                ));
            }
            p
        }
        None => [0.0; 3],
    };
    if dim == 2 {
        if let Some(o) = &rb.orientation {
            return Err(c.err(o.span(), "a planar body has `angle`, not `orientation`"));
        }
        let a = rb
            .angle
            .as_ref()
            .map_or(Ok(0.0), |x| fin_f64(c, x, "angle"))?;
        Ok((p, Orientation::Planar(a)))
    } else {
        if let Some(a) = &rb.angle {
            return Err(c.err(
                a.span(),
                "a spatial body has `orientation = { axis = [x, y, z], angle = … }`, not `angle`",
            ));
        }
        let o = match &rb.orientation {
            None => Orientation::Identity,
            Some(o) => {
                let axis = vec_n(c, &o.get_ref().axis, 3, "axis")?;
                if axis.iter().all(|x| *x == 0.0) {
                    return Err(c.err(o.get_ref().axis.span(), "`axis` must not be zero"));
                }
                let angle = fin_f64(c, &o.get_ref().angle, "angle")?;
                Orientation::AxisAngle { axis, angle }
            }
        };
        Ok((p, o))
    }
}

/// The modal reduction a flexible body's keys ask for (`modes`, `reduction`,
/// `boundary_nodes`, `static_modes`, `modal_damping`), with the span errors
/// about it point at; `None` without `modes`.
#[allow(clippy::type_complexity)]
fn modal_settings(
    c: &Ctx,
    name: &str,
    rb: &RawBody,
    elements: usize,
) -> Result<Option<(ModalSettings, Range<usize>)>, Error> {
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
        ModalSettings {
            modes: k as usize,
            boundary,
            static_modes: rb.static_modes.as_ref().is_none_or(|s| *s.get_ref()),
            damping,
        },
        modes.span(),
    )))
}
