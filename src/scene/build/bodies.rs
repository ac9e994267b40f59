//! `[bodies.NAME]`: rigid and flexible bodies (with their kernels from the
//! provider), poses, damping, initial velocities and elastic states.

use super::{err, v3, Parts};
use crate::runtime::nalgebra::{Matrix3, Unit, UnitQuaternion, Vector2};
use crate::runtime::spec::scene::{BodyKind, BodySpec, FlexSpec, Orientation, SceneSpec};
use crate::runtime::spec::text::quoted as q;
use crate::runtime::spec::Param;
use crate::runtime::{Body, KernelBody, Pose, Rayleigh, RigidBody};
use crate::scene::provider::KernelProvider;
use crate::SceneError;

/// Add the scene's bodies to the system, in file order (body `i` of the
/// spec is `BodyId(i)`); then the further segments of the bodies run as
/// segments (`NAME[2]`, …, with their cut joints: the system's first
/// constraints); then the bodies' damping, velocities and elastic states.
pub(super) fn add_bodies(
    spec: &SceneSpec,
    provider: &dyn KernelProvider,
    parts: &mut Parts,
) -> Result<(), SceneError> {
    let dim = spec.dim;
    let mut ids = Vec::with_capacity(spec.bodies.len());
    for b in &spec.bodies {
        let name = &b.name;
        let pose = match b.orientation {
            Orientation::Planar(a) => Pose::planar(b.position[0], b.position[1], a),
            Orientation::Identity => Pose::spatial(v3(b.position), UnitQuaternion::identity()),
            Orientation::AxisAngle { axis, angle } => Pose::spatial(
                v3(b.position),
                UnitQuaternion::from_axis_angle(&Unit::new_normalize(v3(axis)), angle),
            ),
        };
        let boxed: Box<dyn Body> = match &b.kind {
            BodyKind::Rigid {
                mass,
                inertia,
                centre,
            } => {
                let rbody = if dim == 2 {
                    RigidBody::planar(*mass, inertia[2][2], Vector2::new(centre[0], centre[1]))
                } else {
                    let m = inertia;
                    let m3 = Matrix3::new(
                        m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1],
                        m[2][2],
                    );
                    RigidBody::spatial(*mass, m3, v3(*centre))
                }
                .map_err(|e| err(&b.at, format!("body `{name}`: {e}")))?;
                parts.kernels.push((name.clone(), "rigid".to_string()));
                Box::new(rbody)
            }
            BodyKind::Flexible(f) => {
                parts.flex.push(f.clone());
                flexible(name, &b.at, &f.segment(0), dim, provider, parts)?
            }
            BodyKind::Fe(f) => fe_body(b, f, parts)?,
        };
        let id = parts
            .sys
            .add_body(name, boxed, pose)
            .map_err(|e| err(&b.at, e.to_string()))?;
        ids.push(id);
    }
    for (b, &id) in spec.bodies.iter().zip(&ids) {
        let BodyKind::Flexible(f) = &b.kind else {
            continue;
        };
        if f.segments <= 1 {
            continue;
        }
        let at = f.segments_at.as_ref().unwrap_or(&b.at);
        let rest = (1..f.segments)
            .map(|k| {
                let s = f.segment(k);
                flexible(&s.name, at, &s, dim, provider, parts)
            })
            .collect::<Result<Vec<_>, _>>()?;
        parts
            .sys
            .add_segments(id, rest, &f.segment_bounds())
            .map_err(|e| err(at, e.to_string()))?;
        // The whole body as one (`segments = 1`), for what asks for the
        // body as a whole: its modes, invariants, export.
        let whole = FlexSpec {
            segments: 1,
            ..f.clone()
        };
        let kernels = parts.kernels.len();
        let body = flexible(&b.name, at, &whole, dim, provider, parts)?;
        parts.kernels.truncate(kernels);
        parts.unsplit.push((b.name.clone(), body));
        parts.notes.push(format!(
            "body `{}`: {} segments of {} elements, joined at x = {}",
            b.name,
            f.segments,
            f.elements / f.segments,
            f.segment_bounds()[1..f.segments]
                .iter()
                .map(|x| format!("{x}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    for (b, &id) in spec.bodies.iter().zip(&ids) {
        let name = &b.name;
        let sys = &mut parts.sys;
        if let Some((alpha, beta, at)) = &b.damping {
            let r = Rayleigh {
                alpha: *alpha,
                beta: *beta,
            };
            sys.set_damping(id, r).map_err(|e| err(at, e.to_string()))?;
        }
        let (v, w) = (v3(b.velocity), v3(b.omega));
        if v.norm() > 0.0 || w.norm() > 0.0 {
            sys.set_velocity(id, v, w)
                .map_err(|e| err(&b.at, e.to_string()))?;
        }
        if let Some(el) = &b.elastic {
            let labels = sys.body(id).layout().labels.clone();
            let by_label = |entries: &[(String, f64, crate::runtime::spec::Location)]| {
                let mut out = vec![0.0; labels.len()];
                for (k, x, at) in entries {
                    let Some(i) = labels.iter().position(|l| l == k) else {
                        return Err(err(
                            at,
                            format!(
                                "body `{name}` has no elastic coordinate `{}`; its coordinates are {}",
                                q(k),
                                labels.join(", ")
                            ),
                        ));
                    };
                    out[i] = *x;
                }
                Ok(out)
            };
            let q_f = by_label(&el.q)?;
            let qd_f = by_label(&el.qd)?;
            sys.set_elastic(id, &q_f, &qd_f)
                .map_err(|e| err(&el.at, e.to_string()))?;
        }
    }
    Ok(())
}

/// A flexible body (or one segment of one) on the provider's kernels
/// (reduced when it is modal); `at` is where the body is written.
pub(super) fn flexible(
    name: &str,
    at: &crate::runtime::spec::Location,
    f: &FlexSpec,
    dim: usize,
    provider: &dyn KernelProvider,
    parts: &mut Parts,
) -> Result<Box<dyn Body>, SceneError> {
    let (kernels, path) = provider
        .kernels(f)
        .map_err(|e| err(&f.shape_at, format!("body `{name}`: {e}")))?;
    if kernels.info().dim > dim {
        return Err(err(
            &f.shape_at,
            format!(
                "body `{name}`: shape `{}` is spatial; a planar scene needs a planar shape",
                q(&f.shape_name)
            ),
        ));
    }
    let kb = match &f.sections {
        None => {
            // A parameter the body uses must be given (a missing one would
            // be reported as zero).
            let used = &kernels.info().params_used;
            if let Some(missing) = Param::FIELDS
                .iter()
                .enumerate()
                .find(|(i, p)| !f.given[*i] && used.contains(p))
            {
                let names: Vec<&str> = used.iter().map(|p| p.field()).collect();
                return Err(err(
                    &f.params_at,
                    format!(
                        "body `{name}`: `params` needs `{}`: shape `{}` in this scene uses {}",
                        missing.1.field(),
                        q(&f.shape_name),
                        names.join(", ")
                    ),
                ));
            }
            // A value the body uses that is not valid, at `params`.
            f.params
                .validate_only(used)
                .map_err(|e| err(&f.params_at, format!("body `{name}`: {e}")))?;
            match &f.nodes {
                None => KernelBody::new(kernels, f.params, f.elements, f.reference),
                Some(nodes) => KernelBody::with_nodes(kernels, f.params, nodes, f.reference),
            }
        }
        Some(table) => {
            if kernels.info().dim == 2 {
                if let Some((i, s)) = table.stations.iter().enumerate().find(|(_, s)| s.twist != 0.0) {
                    return Err(err(
                        &table.at,
                        format!(
                            "body `{name}`: station {i} has twist {:?}: a planar shape (`{}`) bends in x–y only, so its sections cannot be twisted",
                            s.twist,
                            q(&f.shape_name)
                        ),
                    ));
                }
            }
            KernelBody::with_sections(
                kernels,
                &table.stations,
                f.elements,
                f.nodes.as_deref(),
                f.reference,
            )
        }
    }
    .map_err(|e| err(at, format!("body `{name}`: {e}")))?;
    let kb = if f.masses.is_empty() {
        kb
    } else {
        let (length, dim) = (kb.params().length, kb.layout().dim);
        for m in &f.masses {
            m.mass
                .check(length, dim)
                .map_err(|e| err(&m.at, format!("body `{name}`: attached mass: {e}")))?;
        }
        let masses: Vec<_> = f.masses.iter().map(|m| m.mass).collect();
        kb.with_masses(&masses)
            .map_err(|e| err(at, format!("body `{name}`: {e}")))?
    };
    let boxed: Box<dyn Body> = match &f.modal {
        None => {
            parts.kernels.push((name.to_string(), path.to_string()));
            Box::new(kb)
        }
        Some((settings, modes_at)) => {
            let baked = provider.modal(f);
            let generated = baked.and_then(|_| provider.modal_kernels(f));
            let when = match (&baked, &generated) {
                (Some(_), Some(_)) => "reduced when compiled, generated inertia kernels",
                (Some(_), None) => "reduced when compiled",
                _ => "reduced at load",
            };
            let mb = match baked {
                // Reduced when the scene was compiled.
                Some(consts) => consts
                    .data()
                    .and_then(|d| match generated {
                        Some(k) => crate::runtime::ModalBody::with_kernels(Box::new(kb), d, k),
                        None => crate::runtime::ModalBody::new(Box::new(kb), d),
                    })
                    .map(|mb| Box::new(mb) as Box<dyn Body>)
                    .map_err(crate::Error::from),
                None => reduce(f, settings, kb),
            }
            .map_err(|e| err(modes_at, format!("body `{name}`: {e}")))?;
            parts.kernels.push((
                name.to_string(),
                format!(
                    "modal, {} modes, {when} ({path} full body for markers)",
                    mb.layout().nf
                ),
            ));
            mb
        }
    };
    Ok(boxed)
}

/// The modal body of `f` (its full body `kb` places markers).
#[cfg(feature = "scene-files")]
fn reduce(
    f: &FlexSpec,
    settings: &crate::runtime::spec::scene::ModalSettings,
    kb: KernelBody<Box<dyn crate::runtime::ElementKernels>>,
) -> crate::Result<Box<dyn Body>> {
    if f.nodes.is_some() || f.sections.is_some() || !f.masses.is_empty() {
        return Err(crate::Error::Invalid(
            "a modal body needs equal elements of a uniform section; a graded mesh, a section table or attached masses are not reduced yet".into(),
        ));
    }
    let mb = crate::modal::ReducibleBody::from_parts(
        &f.shape,
        f.elements,
        f.reference,
        f.options.formalism,
        f.params,
    )
    .and_then(|r| r.runtime_body(settings, f.options.stiffening, Box::new(kb)))?;
    Ok(Box::new(mb))
}

/// Without the `scene-files` feature there is no run-time reduction.
#[cfg(not(feature = "scene-files"))]
fn reduce(
    _: &FlexSpec,
    _: &crate::runtime::spec::scene::ModalSettings,
    _: KernelBody<Box<dyn crate::runtime::ElementKernels>>,
) -> crate::Result<Box<dyn Body>> {
    Err(crate::Error::Invalid(
        "a modal body is reduced at run time: it needs the `scene-files` feature of ffr".into(),
    ))
}

/// An FE body (`fe = {…}`): its files read and checked, its invariants with
/// the reference condition, reduced as its settings say, run as a modal
/// body whose full body ([`crate::runtime::NodalBody`]) places markers at
/// nodes. File errors name the file (and `file:line:col` inside it),
/// prefixed with where `fe` is written; the interface and the mode count are
/// checked against the files here, at `interface` and `modes`.
#[cfg(feature = "scene-files")]
fn fe_body(
    b: &BodySpec,
    f: &crate::runtime::spec::scene::FeSpec,
    parts: &mut Parts,
) -> Result<Box<dyn Body>, SceneError> {
    use crate::codegen::fe::{FeBody, FeReference};
    let name = &b.name;
    let model = crate::fe::model(f).map_err(|e| err(&f.fe_at, format!("FE body `{name}`: {e}")))?;
    let n = model.len();
    if let Some(bad) = f.interface.iter().find(|&&i| i >= n) {
        return Err(err(
            &f.interface_at,
            format!(
                "FE body `{name}`: interface node {bad} out of range: the node file has {n} nodes (0 to {})",
                n - 1
            ),
        ));
    }
    let (settings, modes_at) = &f.modal;
    if let Some(bad) = settings.boundary.iter().find(|&&i| i >= n) {
        return Err(err(
            modes_at,
            format!(
                "FE body `{name}`: boundary node {bad} out of range: the node file has {n} nodes (0 to {})",
                n - 1
            ),
        ));
    }
    let reference = crate::fe::reference(f);
    let body = FeBody::new(model, reference, &f.interface)
        .map_err(|e| err(&f.interface_at, format!("FE body `{name}`: {e}")))?;
    let available = if settings.boundary.is_empty() {
        body.available_modes()
    } else {
        let fixed = 3 * settings.boundary.len();
        body.nf().saturating_sub(fixed)
    };
    if settings.modes > available {
        return Err(err(
            modes_at,
            format!(
                "FE body `{name}`: `modes` = {} is more than the body has: {available} {} ({} elastic coordinates{})",
                settings.modes,
                if settings.boundary.is_empty() {
                    "elastic modes"
                } else {
                    "fixed-interface modes"
                },
                body.nf(),
                match (reference, settings.boundary.is_empty()) {
                    (FeReference::Free, true) => " less 6 rigid motions".to_string(),
                    (_, false) => format!(" less {} on the boundary nodes", 3 * settings.boundary.len()),
                    _ => String::new(),
                }
            ),
        ));
    }
    let reduced = body
        .modal_model(settings)
        .map_err(|e| err(modes_at, format!("FE body `{name}`: {e}")))?;
    let description = crate::fe::describe(&body);
    let data = crate::modal::modal_data(&reduced, description.clone());
    let k = reduced.len();
    let nodes = body.model.nodes.iter().map(|p| [p.x, p.y, p.z]).collect();
    let full = crate::runtime::NodalBody::new(
        crate::modal::to_runtime(&body.invariants),
        nodes,
        &body.dofs,
        body.dof_names.clone(),
        description,
    )
    .and_then(|full| crate::runtime::ModalBody::new(Box::new(full), data))
    .map_err(|e| err(modes_at, format!("FE body `{name}`: {e}")))?;
    parts.kernels.push((
        name.clone(),
        format!("modal, {k} modes, reduced at load (FE body, {n} nodes)"),
    ));
    parts.fe.push(f.clone());
    Ok(Box::new(full))
}

/// Without the `scene-files` feature there are no FE bodies (their files are
/// read when the scene is built).
#[cfg(not(feature = "scene-files"))]
fn fe_body(
    b: &BodySpec,
    f: &crate::runtime::spec::scene::FeSpec,
    _: &mut Parts,
) -> Result<Box<dyn Body>, SceneError> {
    Err(err(
        &f.fe_at,
        format!(
            "FE body `{}`: FE bodies are read at run time: they need the `scene-files` feature of ffr",
            b.name
        ),
    ))
}
