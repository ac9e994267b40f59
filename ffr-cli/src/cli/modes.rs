//! `ffr modes` and `ffr export`: the reductions of [`ffr::modal`] printed
//! (as text or the JSON of `--json`) and written in MBDyn's modal `.fem` or
//! SID (see docs/export.md).

use super::{invariants_json, BodyArgs, ExportFormat, ParamArgs, SceneBodyArgs};
use crate::output;
use ffr::codegen::export::{mbdyn_fem, sid, ExportBody};
use ffr::codegen::modal::{ModalBasis, ModeKind};
use ffr::invariants::check_invariants;
use ffr::modal::{finite, to_runtime, ReducibleBody};
use ffr::runtime::spec::{Formalism, Reference};
use serde_json::{json, Value};
use std::error::Error;
use std::path::Path;

/// The body the shared `--shape/--elements/--reference/--formalism` and
/// parameter arguments describe, checked as [`ReducibleBody::from_parts`]
/// checks it.
pub fn reducible(body: &BodyArgs, params: &ParamArgs) -> Result<ReducibleBody, Box<dyn Error>> {
    if body.tape {
        return Err(
            "--tape does not apply here: modes and export use the exact invariants, not the element kernels"
                .into(),
        );
    }
    Ok(ReducibleBody::from_parts(
        &body.shape,
        body.elements as usize,
        body.reference,
        body.formalism,
        params.values(),
    )?)
}

/// The reduction as the JSON object of `ffr modes --json`: `reduction`,
/// `omega` (rad/s) and `hz` of the normal modes, `labels` of every mode
/// (normal modes first, then Craig–Bampton's constraint modes
/// `constraint_<dof>`), `dofs`, `phi` (n_f rows of k), `modal_mass`,
/// `modal_stiffness` (k × k) and `invariants`, the projected invariants keyed
/// like `ffr invariants --json` (with `dofs` the mode labels).
pub fn modes_json(body: &ReducibleBody, basis: &ModalBasis) -> Value {
    reduction_json(&body.description(), &body.dofs, &body.invariants, basis)
}

/// [`modes_json`] of any body: its description, coordinate labels and full
/// invariants (a beam's or an FE body's).
fn reduction_json(
    description: &str,
    dofs: &[String],
    invariants: &ffr::codegen::modal::Invariants,
    basis: &ModalBasis,
) -> Value {
    let rows = |m: &ffr::runtime::nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
            .collect()
    };
    let projected = invariants.project(&basis.phi);
    json!({
        "body": description,
        "reduction": basis.reduction_name(),
        "omega": basis.frequencies,
        "hz": basis.frequencies.iter().map(|w| w / std::f64::consts::TAU).collect::<Vec<_>>(),
        "labels": basis.labels,
        "dofs": dofs,
        "phi": rows(&basis.phi),
        "modal_mass": rows(&basis.modal_mass),
        "modal_stiffness": rows(&basis.modal_stiffness),
        "invariants": invariants_json(&to_runtime(&projected), &basis.labels),
    })
}

/// The FE body `name` of the scene at `path`, if it is one.
fn fe_from_scene(
    scene: &ffr::scene::Scene,
    name: &str,
) -> Result<Option<ffr::codegen::fe::FeBody>, Box<dyn Error>> {
    match scene.fe.iter().find(|f| f.name == name) {
        None => Ok(None),
        Some(f) => Ok(Some(
            ffr::fe::body(f).map_err(|e| format!("FE body `{name}`: {e}"))?,
        )),
    }
}

/// An FE body's basis as the command line asks: modal truncation to
/// `count` modes (all elastic modes when `None`), or with `boundary` FE
/// nodes Craig–Bampton with `count` fixed-interface modes (all when `None`);
/// every number checked finite as for beams.
fn fe_basis(
    body: &ffr::codegen::fe::FeBody,
    count: Option<usize>,
    boundary: &[usize],
    flag: &str,
) -> Result<ModalBasis, Box<dyn Error>> {
    use ffr::codegen::modal::Reduction;
    let available = if boundary.is_empty() {
        body.available_modes()
    } else {
        let mut nodes = boundary.to_vec();
        nodes.sort_unstable();
        nodes.dedup();
        let fixed = body
            .dofs
            .iter()
            .filter(|d| nodes.binary_search(&(*d / 3)).is_ok())
            .count();
        body.nf() - fixed
    };
    let k = count.unwrap_or(available);
    if (boundary.is_empty() && k == 0) || k > available {
        return Err(format!(
            "{flag} must be between {} and {available} for this FE body ({} elastic coordinates{}), found {k}",
            if boundary.is_empty() { 1 } else { 0 },
            body.nf(),
            if boundary.is_empty() {
                if available < body.nf() { " less 6 rigid motions" } else { "" }
            } else {
                " less those of the boundary nodes"
            }
        )
        .into());
    }
    let reduction = if boundary.is_empty() {
        Reduction::Modal { modes: k }
    } else {
        Reduction::CraigBampton {
            boundary_nodes: boundary.to_vec(),
            modes: k,
        }
    };
    let basis = body.reduce(&reduction)?;
    for (j, w) in basis.frequencies.iter().enumerate() {
        finite(|| format!("omega[{j}]"), *w)?;
    }
    for (name, m) in [
        ("phi", &basis.phi),
        ("modal_mass", &basis.modal_mass),
        ("modal_stiffness", &basis.modal_stiffness),
    ] {
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                finite(|| format!("{name}[{i}][{j}]"), m[(i, j)])?;
            }
        }
    }
    Ok(basis)
}

/// The body of `--scene FILE --body NAME` ([`ReducibleBody::of_scene_body`]),
/// and the runtime body whose point shapes draw its modes (`--vtk`): the
/// scene's when it has the reduction's coordinates, else (a modal body of
/// the scene) the same beam with nodal coordinates.
fn reducible_from_scene(
    scene: ffr::scene::Scene,
    name: &str,
) -> Result<(ReducibleBody, DrawnBeam), Box<dyn Error>> {
    let (id, f) = scene.flex_body(name)?;
    let (whole, _) = scene.whole_body(name)?;
    let b = ReducibleBody::of_scene_body(f, whole)?;
    let drawn = if f.segments <= 1 && scene.system.body(id).layout().nf == b.dofs.len() {
        DrawnBeam::Scene(Box::new(scene), id)
    } else {
        let f = f.clone();
        DrawnBeam::Beam(beam_of(
            &f.shape,
            f.elements,
            f.reference,
            f.options.formalism,
            f.params,
        )?)
    };
    Ok((b, drawn))
}

/// The runtime body whose point shapes draw mode shapes.
enum DrawnBeam {
    /// A body of a scene.
    Scene(Box<ffr::scene::Scene>, ffr::runtime::BodyId),
    /// A beam made for it.
    Beam(Box<dyn ffr::runtime::Body>),
}

impl DrawnBeam {
    fn body(&self) -> &dyn ffr::runtime::Body {
        match self {
            DrawnBeam::Scene(s, id) => s.system.body(*id).as_ref(),
            DrawnBeam::Beam(b) => b.as_ref(),
        }
    }
}

/// The runtime beam of these flags (its point shapes draw mode shapes).
fn beam_of(
    shape: &str,
    elements: usize,
    reference: Reference,
    formalism: Formalism,
    params: ffr::runtime::spec::Params,
) -> Result<Box<dyn ffr::runtime::Body>, Box<dyn Error>> {
    let mut spec = ffr::BeamSpec::new(shape, elements, params).formalism(formalism);
    spec.reference = reference;
    Ok(Box::new(spec.body()?))
}

/// Write each mode of `basis` as an animation into `dir` (see
/// [`ffr::scene::vtk::write_modes`]); `name` names the files.
pub fn write_mode_animations(
    dir: &Path,
    name: &str,
    b: &ReducibleBody,
    body: &dyn ffr::runtime::Body,
    basis: &ModalBasis,
) -> Result<Vec<ffr::scene::vtk::VtkWritten>, Box<dyn Error>> {
    use ffr::scene::vtk::{equal_nodes, write_modes, ModeShape};
    if body.layout().nf != b.dofs.len() {
        return Err(format!(
            "the body drawn has {} elastic coordinates, the reduction {}",
            body.layout().nf,
            b.dofs.len()
        )
        .into());
    }
    let nodes = b
        .nodes
        .clone()
        .unwrap_or_else(|| equal_nodes(b.spec.elements, b.params.length));
    let modes: Vec<ModeShape> = (0..basis.len())
        .map(|j| ModeShape {
            label: basis.labels[j].clone(),
            omega: basis.frequencies.get(j).copied(),
            phi: basis.phi.column(j).iter().copied().collect(),
        })
        .collect();
    Ok(write_modes(
        dir,
        name,
        body,
        &nodes,
        b.params.length,
        &modes,
    )?)
}

/// Write each mode of an FE body's `basis` as an animation into `dir` (see
/// [`ffr::scene::vtk::write_node_modes`]: the nodes drawn by the node shapes
/// of the body on its nodal coordinates, the rows of `phi`); `name` names
/// the files.
pub fn write_fe_mode_animations(
    dir: &Path,
    name: &str,
    fe: &ffr::codegen::fe::FeBody,
    basis: &ModalBasis,
) -> Result<Vec<ffr::scene::vtk::VtkWritten>, Box<dyn Error>> {
    use ffr::scene::vtk::{write_node_modes, ModeShape};
    let nodes = fe.model.nodes.iter().map(|p| [p.x, p.y, p.z]).collect();
    let body = ffr::runtime::NodalBody::new(
        to_runtime(&fe.invariants),
        nodes,
        &fe.dofs,
        fe.dof_names.clone(),
        ffr::fe::describe(fe),
    )?;
    let modes: Vec<ModeShape> = (0..basis.len())
        .map(|j| ModeShape {
            label: basis.labels[j].clone(),
            omega: basis.frequencies.get(j).copied(),
            phi: basis.phi.column(j).iter().copied().collect(),
        })
        .collect();
    Ok(write_node_modes(dir, name, &body, &modes)?)
}

/// `ffr modes`: print the frequencies (or, with `json`, the whole reduction).
/// A scene's FE body (`--scene … --body …`) is reduced on its FE nodes
/// (`--boundary`: FE node indices).
pub fn modes(
    body: &BodyArgs,
    params: &ParamArgs,
    from_scene: &SceneBodyArgs,
    count: Option<usize>,
    boundary: &[usize],
    json: bool,
    vtk: Option<&Path>,
) -> Result<(), Box<dyn Error>> {
    // With --vtk, each mode as an animation (beams here; FE bodies with
    // write_fe_mode_animations).
    let write_vtk = |b: &ReducibleBody,
                     drawn: DrawnBeam,
                     name: &str,
                     basis: &ModalBasis|
     -> Result<(), Box<dyn Error>> {
        let Some(dir) = vtk else { return Ok(()) };
        let stem = ffr::scene::vtk::series_name(
            &Path::new(name)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| name.to_string()),
        );
        let written = write_mode_animations(dir, &stem, b, drawn.body(), basis)?;
        // With --json, standard output is the JSON object alone.
        if !json {
            crate::outln!(
                "wrote {} mode animations ({} frames each) to {}: {}_mode*.pvd",
                written.len(),
                ffr::scene::vtk::FRAMES_PER_PERIOD,
                dir.display(),
                stem
            )?;
        }
        Ok(())
    };
    let (description, dofs, invariants, basis, free) =
        match (&from_scene.scene, &from_scene.body_name) {
            (Some(path), Some(name)) => {
                let scene = ffr::scene::load(path)?;
                match fe_from_scene(&scene, name)? {
                    Some(fe) => {
                        let basis = fe_basis(&fe, count, boundary, "--count")?;
                        if let Some(dir) = vtk {
                            let written = write_fe_mode_animations(dir, name, &fe, &basis)?;
                            if !json {
                                crate::outln!(
                                    "wrote {} mode animations ({} frames each) to {}: {}_mode*.pvd",
                                    written.len(),
                                    ffr::scene::vtk::FRAMES_PER_PERIOD,
                                    dir.display(),
                                    ffr::scene::vtk::series_name(name)
                                )?;
                            }
                        }
                        let free = fe.reference == ffr::codegen::fe::FeReference::Free;
                        (
                            ffr::fe::describe(&fe),
                            fe.dof_names,
                            fe.invariants,
                            basis,
                            free,
                        )
                    }
                    None => {
                        let (b, drawn) = reducible_from_scene(scene, name)?;
                        let basis = b.reduce(count, boundary, "--count")?;
                        write_vtk(&b, drawn, name, &basis)?;
                        let free = b.spec.reference == Reference::Free;
                        (b.description(), b.dofs, b.invariants, basis, free)
                    }
                }
            }
            _ => {
                let b = reducible(body, params)?;
                let basis = b.reduce(count, boundary, "--count")?;
                if vtk.is_some() {
                    let drawn = DrawnBeam::Beam(beam_of(
                        &body.shape,
                        body.elements as usize,
                        body.reference,
                        body.formalism,
                        params.values(),
                    )?);
                    write_vtk(&b, drawn, &body.shape, &basis)?;
                }
                let free = b.spec.reference == Reference::Free;
                (b.description(), b.dofs, b.invariants, basis, free)
            }
        };
    if json {
        crate::outln!(
            "{}",
            serde_json::to_string(&reduction_json(&description, &dofs, &invariants, &basis))?
        )?;
        return Ok(());
    }
    crate::outln!("{description}")?;
    if boundary.is_empty() {
        crate::outln!(
            "modal truncation: the {} lowest modes of K_ff φ = ω² m_ff φ, mass-normalized{}",
            basis.len(),
            if free {
                " (rigid-body motions removed)"
            } else {
                ""
            }
        )?;
    } else {
        crate::outln!(
            "Craig-Bampton: {} fixed-interface normal modes (boundary nodes fixed), mass-normalized, and {} static constraint modes",
            basis.frequencies.len(),
            basis.len() - basis.frequencies.len()
        )?;
    }
    if !basis.frequencies.is_empty() {
        crate::outln!("{:>5} {:>24} {:>24}", "mode", "omega (rad/s)", "f (Hz)")?;
    }
    for (j, w) in basis.frequencies.iter().enumerate() {
        crate::outln!(
            "{:>5} {:>24} {:>24}",
            j + 1,
            output::number(*w),
            output::number(w / std::f64::consts::TAU)
        )?;
    }
    let constraint = &basis.labels[basis.frequencies.len()..];
    if !constraint.is_empty() {
        crate::outln!("constraint modes: {}", constraint.join(" "))?;
    }
    Ok(())
}

/// Every number an export writes finite (the basis and the projected
/// invariants are checked by [`ReducibleBody::reduce`]): the nodes'
/// positions, mode shapes, lumped masses and inertias.
fn check_export(e: &ExportBody) -> ffr::Result<()> {
    for n in &e.nodes {
        let node = n.node;
        for (c, v) in n.position.iter().enumerate() {
            finite(|| format!("node {node} position[{c}]"), *v)?;
        }
        for (what, m) in [("translation", &n.translation), ("rotation", &n.rotation)] {
            for (i, v) in m.iter().enumerate() {
                finite(
                    || format!("node {node} {what}[{}] of mode {}", i % 3, i / 3 + 1),
                    *v,
                )?;
            }
        }
        finite(|| format!("node {node} mass"), n.mass)?;
        for (c, v) in n.inertia.iter().enumerate() {
            finite(|| format!("node {node} inertia[{c}]"), *v)?;
        }
    }
    for (j, k) in e.kinds.iter().enumerate() {
        if let ModeKind::Normal { omega } = k {
            finite(|| format!("omega of mode {}", j + 1), *omega)?;
        }
    }
    check_invariants(&to_runtime(&e.invariants), &e.labels, Formalism::Lumped)
        .map_err(|m| ffr::Error::Invalid(format!("invariants.{m}")))
}

/// `ffr export`: write the body reduced as [`ReducibleBody::reduce`] says in
/// `format` (`mbdyn-fem` or `sid`) to `out`, atomically.
#[allow(clippy::too_many_arguments)]
pub fn export(
    format: ExportFormat,
    body: &BodyArgs,
    params: &ParamArgs,
    from_scene: &SceneBodyArgs,
    count: Option<usize>,
    boundary: &[usize],
    out: &Path,
) -> Result<(), Box<dyn Error>> {
    output::check_outputs(&[("--out", out)])?;
    let (description, basis, e) = match (&from_scene.scene, &from_scene.body_name) {
        (Some(path), Some(name)) => {
            let scene = ffr::scene::load(path)?;
            output::check_not_scene_files(&[("--out", out)], &scene.input_files())?;
            match fe_from_scene(&scene, name)? {
                Some(fe) => {
                    let basis = fe_basis(&fe, count, boundary, "--modes")?;
                    let e = ExportBody::from_fe(&fe, &basis)?;
                    (ffr::fe::describe(&fe), basis, e)
                }
                None => {
                    let (whole, f) = scene.whole_body(name)?;
                    let b = ReducibleBody::of_scene_body(f, whole)?;
                    let basis = b.reduce(count, boundary, "--modes")?;
                    let e = ExportBody::new(&b.spec, &b.params, &b.invariants, &basis)?;
                    (b.description(), basis, e)
                }
            }
        }
        _ => {
            let b = reducible(body, params)?;
            let basis = b.reduce(count, boundary, "--modes")?;
            let e = ExportBody::new(&b.spec, &b.params, &b.invariants, &basis)?;
            (b.description(), basis, e)
        }
    };
    check_export(&e)?;
    let (text, name) = match format {
        ExportFormat::MbdynFem => (mbdyn_fem(&e), "mbdyn-fem"),
        ExportFormat::Sid => (sid(&e), "sid"),
    };
    output::write_atomic(out, text.as_bytes())?;
    crate::outln!("{description}")?;
    crate::outln!(
        "wrote {} ({name}, {} modes, {})",
        out.display(),
        basis.len(),
        basis.reduction_name()
    )?;
    Ok(())
}
