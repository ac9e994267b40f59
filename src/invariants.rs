//! Checks on a body's invariants evaluated at its parameters.

use crate::runtime::spec::Formalism;
use crate::runtime::Invariants;

const AXES: [&str; 3] = ["x", "y", "z"];

/// Every number finite, and (consistent formalism) every diagonal entry of
/// `m_ff` positive; the error names the quantity as `invariants --json` keys it.
pub fn check_invariants(
    inv: &Invariants,
    dofs: &[String],
    formalism: Formalism,
) -> crate::Result<()> {
    let dof = |a: usize| dofs.get(a).map_or(String::new(), |l| format!(" ({l})"));
    let bad = |q: String, v: f64| {
        crate::Error::Invalid(format!("{q} is {v} at these parameters, not a finite number: the parameters or the shape's coefficients are too large or too small for f64"))
    };
    if !inv.mass.is_finite() {
        return Err(bad("mass".into(), inv.mass));
    }
    let d = inv.dim;
    for k in 0..d {
        if !inv.s_t0[k].is_finite() {
            return Err(bad(format!("St0[{k}]"), inv.s_t0[k]));
        }
        for a in 0..inv.nf() {
            if !inv.s_bar[(k, a)].is_finite() {
                return Err(bad(format!("Sbar[{k}][{a}]{}", dof(a)), inv.s_bar[(k, a)]));
            }
        }
        for l in 0..d {
            let key = format!("{}{}", AXES[k], AXES[l]);
            if !inv.theta[(k, l)].is_finite() {
                return Err(bad(format!("theta.{key}"), inv.theta[(k, l)]));
            }
            if let Some((a, v)) = inv.i_kl[k][l]
                .iter()
                .enumerate()
                .find(|(_, v)| !v.is_finite())
            {
                return Err(bad(format!("Ikl.{key}[{a}]{}", dof(a)), *v));
            }
            for (i, v) in inv.s_kl[k][l].iter().enumerate() {
                if !v.is_finite() {
                    let n = inv.nf();
                    return Err(bad(format!("Skl.{key}[{}][{}]", i % n, i / n), *v));
                }
            }
        }
    }
    for (name, m) in [("mff", &inv.m_ff), ("Kff", &inv.k_ff)] {
        for (i, v) in m.iter().enumerate() {
            if !v.is_finite() {
                let n = inv.nf();
                return Err(bad(
                    format!("{name}[{}][{}]{}", i % n, i / n, dof(i % n)),
                    *v,
                ));
            }
        }
    }
    if formalism == Formalism::Consistent {
        for a in 0..inv.nf() {
            let v = inv.m_ff[(a, a)];
            if !(v > 0.0) {
                return Err(format!("mff[{a}][{a}]{} is {v} at these parameters: a diagonal entry of the mass matrix must be positive (the shape's coefficients are too small for f64, or the coordinate carries no mass)", dof(a)).into());
            }
        }
    }
    Ok(())
}

/// A body's invariants at its parameters, checked ([`check_invariants`]):
/// what `ffr invariants` prints.
pub struct BodyInvariants {
    /// The body, as its layout describes it.
    pub description: String,
    /// The invariants.
    pub invariants: Invariants,
    /// The elastic coordinates' labels (`uy_1`, …).
    pub dofs: Vec<String>,
}

/// The invariants of the body `beam` describes, from its element kernels
/// (compiled or on tapes): the parameters checked (valid, and the ones the
/// kernels use positive), every invariant checked.
pub fn of_beam(beam: &crate::kernels::BeamSpec) -> crate::Result<BodyInvariants> {
    use crate::codegen::limits::check_params;
    use crate::runtime::Body;
    check_params(&beam.params, &[])?;
    let kernels = beam.kernels()?;
    let used = crate::runtime::ElementKernels::info(&kernels)
        .params_used
        .to_vec();
    check_params(&beam.params, &used)?;
    let b = beam.body()?;
    let invariants = b.invariants();
    let dofs = b.layout().labels.clone();
    check_invariants(&invariants, &dofs, beam.options.formalism)?;
    Ok(BodyInvariants {
        description: b.layout().description.clone(),
        invariants,
        dofs,
    })
}

/// The invariants of the flexible body `name` of a built scene, as it runs
/// there (its shape, mesh, sections and parameters), checked; of an FE body,
/// the full body's on its nodal coordinates (the scene runs it reduced).
pub fn of_scene_body(scene: &crate::scene::Scene, name: &str) -> crate::Result<BodyInvariants> {
    if let Some(f) = scene.fe.iter().find(|f| f.name == name) {
        // The full FE body's invariants on its nodal coordinates (the scene
        // runs it reduced).
        let body = crate::fe::body(f).map_err(|e| format!("FE body `{name}`: {e}"))?;
        let invariants = crate::modal::to_runtime(&body.invariants);
        check_invariants(&invariants, &body.dof_names, Formalism::Consistent)?;
        return Ok(BodyInvariants {
            description: crate::fe::describe(&body),
            invariants,
            dofs: body.dof_names,
        });
    }
    let (b, f) = scene.whole_body(name)?;
    let invariants = b.invariants();
    let dofs = b.layout().labels.clone();
    check_invariants(&invariants, &dofs, f.options.formalism)?;
    Ok(BodyInvariants {
        description: b.layout().description.clone(),
        invariants,
        dofs,
    })
}
