//! `ffr modes` and `ffr export`: a body's modal reduction from its exact
//! invariants (see docs/modal.md) and its export to MBDyn's modal `.fem` or
//! SID (see docs/export.md).
//!
//! Both start from [`BodySpec::exact_invariants`] evaluated at the parameters
//! and rounded once per entry ([`modal::Invariants::from_exact`]), not from
//! the generated element kernels that `ffr invariants` runs; the two agree to
//! round-off (tests/modes_export.rs compares them).

use crate::cli::{check_invariants, invariants_json, BodyArgs, ParamArgs};
use crate::codegen::body::ExactInvariants;
use crate::codegen::export::{mbdyn_fem, sid, ExportBody};
use crate::codegen::limits::check_params;
use crate::codegen::modal::{self, reduce, rigid_body_modes, ModalBasis, Reduction};
use crate::codegen::poly::{Param, Poly, Sym};
use crate::codegen::{BodySpec, Shape};
use crate::output;
use crate::runtime::spec::{Formalism, Params, Reference};
use serde_json::{json, Value};
use std::collections::BTreeSet;
use std::error::Error;
use std::path::Path;

/// A body ready for reduction: its description, its invariants at the
/// parameters, and how many elastic modes it has.
pub struct ModalBody {
    /// The body.
    pub spec: BodySpec,
    /// The parameter values.
    pub params: Params,
    /// The full body's invariants (n_f nodal coordinates), correctly rounded.
    pub invariants: modal::Invariants,
    /// The elastic coordinates' labels (`uy_1`, …), as `ffr invariants` names them.
    pub dofs: Vec<String>,
    /// Number of elastic modes: n_f, less the rigid-body motions of a free body.
    pub available: usize,
}

/// The runtime parameters a polynomial's terms contain.
fn collect_params(p: &Poly, out: &mut BTreeSet<Param>) {
    for (m, _) in p.terms() {
        for &(s, _) in m.factors() {
            if let Sym::Param(q) = s {
                if q.field_index().is_some() {
                    out.insert(q);
                }
            }
        }
    }
}

/// The parameters the body's invariants depend on.
fn params_used(e: &ExactInvariants) -> Vec<Param> {
    let mut out = BTreeSet::new();
    collect_params(&e.mass, &mut out);
    for i in 0..e.nf {
        for j in 0..e.nf {
            collect_params(e.m_ff.get(i, j), &mut out);
            collect_params(e.k_ff.get(i, j), &mut out);
        }
    }
    out.into_iter().collect()
}

/// The runtime's `Invariants` (what `ffr invariants` checks and prints) with
/// the same numbers.
fn to_runtime(inv: &modal::Invariants) -> crate::runtime::Invariants {
    let mut r = crate::runtime::Invariants::zeros(inv.dim, inv.nf());
    r.mass = inv.mass;
    r.s_t0 = inv.s_t0;
    r.s_bar.copy_from(&inv.s_bar);
    r.s_kl = inv.s_kl.clone();
    r.i_kl = inv.i_kl.clone();
    r.theta = inv.theta;
    r.m_ff = inv.m_ff.clone();
    r.k_ff = inv.k_ff.clone();
    r
}

impl ModalBody {
    /// The body the shared `--shape/--elements/--reference/--formalism` and
    /// parameter arguments describe, checked like `ffr invariants` checks
    /// its body (parameters valid and used ones positive, every invariant
    /// finite, `m_ff`'s diagonal positive in the consistent formalism).
    pub fn new(body: &BodyArgs, params: &ParamArgs) -> Result<Self, Box<dyn Error>> {
        if body.tape {
            return Err(
                "--tape does not apply here: modes and export use the exact invariants, not the element kernels"
                    .into(),
            );
        }
        let p = params.values();
        check_params(&p, &[])?;
        let shape = Shape::resolve(&body.shape, None)?;
        let formalism = body.formalism.parse::<Formalism>()?;
        let spec = BodySpec::new(
            shape,
            body.elements as usize,
            body.reference.parse::<Reference>()?,
        )?
        .with_formalism(formalism);
        let exact = spec.exact_invariants()?;
        check_params(&p, &params_used(&exact))?;
        let invariants = modal::Invariants::from_exact(&exact, &p)?;
        let dofs: Vec<String> = spec.dofs().iter().map(|d| d.to_string()).collect();
        check_invariants(&to_runtime(&invariants), &dofs, formalism)?;
        let rigid = if spec.reference == Reference::Free {
            rigid_body_modes(&spec, p.length).ncols()
        } else {
            0
        };
        let available = dofs.len().saturating_sub(rigid);
        Ok(Self {
            spec,
            params: p,
            invariants,
            dofs,
            available,
        })
    }

    /// The reduction the command line asks for: modal truncation to `count`
    /// modes (all elastic modes when `None`), or with `boundary` nodes
    /// Craig–Bampton with `count` fixed-interface normal modes (all interior
    /// modes when `None`) and a constraint mode per boundary coordinate.
    /// `flag` names the count option in errors.
    pub fn reduce(
        &self,
        count: Option<usize>,
        boundary: &[usize],
        flag: &str,
    ) -> Result<ModalBasis, Box<dyn Error>> {
        if !boundary.is_empty() {
            return self.craig_bampton(count, boundary, flag);
        }
        let k = count.unwrap_or(self.available);
        if k == 0 || k > self.available {
            return Err(format!(
                "{flag} must be between 1 and {} (the body's elastic modes: {} elastic coordinates{}), found {k}",
                self.available,
                self.dofs.len(),
                if self.available < self.dofs.len() {
                    format!(" less {} rigid-body motions", self.dofs.len() - self.available)
                } else {
                    String::new()
                }
            )
            .into());
        }
        Ok(reduce(
            &self.spec,
            &self.params,
            &self.invariants,
            &Reduction::Modal { modes: k },
        )?)
    }

    fn craig_bampton(
        &self,
        count: Option<usize>,
        boundary: &[usize],
        flag: &str,
    ) -> Result<ModalBasis, Box<dyn Error>> {
        let n = self.spec.elements;
        if let Some(bad) = boundary.iter().find(|&&b| b > n) {
            return Err(
                format!("--boundary node {bad} out of range: the body has nodes 0 to {n}").into(),
            );
        }
        let nodes: BTreeSet<usize> = boundary.iter().copied().collect();
        let fixed = self
            .spec
            .dofs()
            .iter()
            .filter(|d| nodes.contains(&d.node))
            .count();
        let interior = self.dofs.len() - fixed;
        let k = count.unwrap_or(interior);
        if k > interior {
            return Err(format!(
                "{flag} must be at most {interior} with --boundary (the coordinates not on the boundary nodes), found {k}"
            )
            .into());
        }
        Ok(reduce(
            &self.spec,
            &self.params,
            &self.invariants,
            &Reduction::CraigBampton {
                boundary_nodes: nodes.into_iter().collect(),
                modes: k,
            },
        )?)
    }

    /// One line naming the body.
    pub fn description(&self) -> String {
        format!(
            "{} ({}), {} elements, {}, {} formalism: {} elastic coordinates, {} elastic modes",
            self.spec.shape.name,
            self.spec.shape.origin,
            self.spec.elements,
            self.spec.reference,
            self.spec.formalism,
            self.dofs.len(),
            self.available
        )
    }
}

/// What the basis is: `modal truncation` or `Craig-Bampton`.
fn reduction_name(basis: &ModalBasis) -> &'static str {
    if basis.frequencies.len() < basis.len() {
        "Craig-Bampton"
    } else {
        "modal truncation"
    }
}

/// The reduction as the JSON object of `ffr modes --json`: `reduction`,
/// `omega` (rad/s) and `hz` of the normal modes, `labels` of every mode
/// (normal modes first, then Craig–Bampton's constraint modes
/// `constraint_<dof>`), `dofs`, `phi` (n_f rows of k), `modal_mass`,
/// `modal_stiffness` (k × k) and `invariants`, the projected invariants keyed
/// like `ffr invariants --json` (with `dofs` the mode labels).
pub fn modes_json(body: &ModalBody, basis: &ModalBasis) -> Value {
    let rows = |m: &crate::runtime::nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
            .collect()
    };
    let projected = body.invariants.project(&basis.phi);
    json!({
        "body": body.description(),
        "reduction": reduction_name(basis),
        "omega": basis.frequencies,
        "hz": basis.frequencies.iter().map(|w| w / std::f64::consts::TAU).collect::<Vec<_>>(),
        "labels": basis.labels,
        "dofs": body.dofs,
        "phi": rows(&basis.phi),
        "modal_mass": rows(&basis.modal_mass),
        "modal_stiffness": rows(&basis.modal_stiffness),
        "invariants": invariants_json(&to_runtime(&projected), &basis.labels),
    })
}

/// `ffr modes`: print the frequencies (or, with `json`, the whole reduction).
pub fn modes(
    body: &BodyArgs,
    params: &ParamArgs,
    count: Option<usize>,
    boundary: &[usize],
    json: bool,
) -> Result<(), Box<dyn Error>> {
    let b = ModalBody::new(body, params)?;
    let basis = b.reduce(count, boundary, "--count")?;
    if json {
        println!("{}", serde_json::to_string(&modes_json(&b, &basis))?);
        return Ok(());
    }
    println!("{}", b.description());
    if boundary.is_empty() {
        println!(
            "modal truncation: the {} lowest modes of K_ff φ = ω² m_ff φ, mass-normalized{}",
            basis.len(),
            if b.spec.reference == Reference::Free {
                " (rigid-body motions removed)"
            } else {
                ""
            }
        );
    } else {
        println!(
            "Craig-Bampton: {} fixed-interface normal modes (boundary nodes fixed), mass-normalized, and {} static constraint modes",
            basis.frequencies.len(),
            basis.len() - basis.frequencies.len()
        );
    }
    if !basis.frequencies.is_empty() {
        println!("{:>5} {:>24} {:>24}", "mode", "omega (rad/s)", "f (Hz)");
    }
    for (j, w) in basis.frequencies.iter().enumerate() {
        println!(
            "{:>5} {:>24} {:>24}",
            j + 1,
            output::number(*w),
            output::number(w / std::f64::consts::TAU)
        );
    }
    let constraint = &basis.labels[basis.frequencies.len()..];
    if !constraint.is_empty() {
        println!("constraint modes: {}", constraint.join(" "));
    }
    Ok(())
}

/// `ffr export`: write the body reduced as [`ModalBody::reduce`] says in
/// `format` (`mbdyn-fem` or `sid`) to `out`, atomically.
pub fn export(
    format: &str,
    body: &BodyArgs,
    params: &ParamArgs,
    count: Option<usize>,
    boundary: &[usize],
    out: &Path,
) -> Result<(), Box<dyn Error>> {
    output::check_file_path(out, "--out")?;
    let b = ModalBody::new(body, params)?;
    let basis = b.reduce(count, boundary, "--modes")?;
    let e = ExportBody::new(&b.spec, &b.params, &b.invariants, &basis)?;
    let text = match format {
        "mbdyn-fem" => mbdyn_fem(&e),
        "sid" => sid(&e),
        other => return Err(format!("unknown --format `{other}` (mbdyn-fem, sid)").into()),
    };
    output::write_atomic(out, text.as_bytes())?;
    println!("{}", b.description());
    println!(
        "wrote {} ({format}, {} modes, {})",
        out.display(),
        basis.len(),
        reduction_name(&basis)
    );
    Ok(())
}
