//! A body's modal reduction from its exact invariants (see docs/modal.md),
//! and the runtime's modal body made from it.
//!
//! Reductions start from [`BodySpec::exact_invariants`] evaluated at the parameters
//! and rounded once per entry ([`modal::Invariants::from_exact`]), not from
//! the generated element kernels that `ffr invariants` runs; the two agree to
//! round-off (tests/modes_export.rs compares them).

use crate::codegen::body::ExactInvariants;
use crate::codegen::limits::check_params;
use crate::codegen::modal::{self, reduce, ModalBasis, Reduction};
use crate::codegen::poly::{Param, Poly, Sym};
use crate::codegen::{BodySpec, Shape};
use crate::invariants::check_invariants;
use crate::kernels::BeamSpec;
use crate::runtime::modal::{ModalBody, ModalData};
use crate::runtime::spec::Stiffening;
use crate::runtime::spec::{Formalism, Params, Reference};
use crate::runtime::Body;
use std::collections::BTreeSet;

/// A body ready for reduction: its description, its invariants at the
/// parameters, and how many elastic modes it has.
pub struct ReducibleBody {
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
    /// The nodes of a graded mesh (`None`: equal elements).
    pub nodes: Option<Vec<f64>>,
    /// Whether the section varies along the span (a section table).
    pub varying_sections: bool,
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

/// The parameters the body's invariants depend on (the length always: the
/// invariants in the element length `l = L/N` do not name it).
fn params_used(e: &ExactInvariants) -> Vec<Param> {
    let mut out = BTreeSet::from([Param::Length]);
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
pub fn to_runtime(inv: &modal::Invariants) -> crate::runtime::Invariants {
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

impl ReducibleBody {
    /// The body of `elements` `shape` elements (a built-in name or a shape
    /// file's path) at parameters `p`, checked: parameters valid and the used ones positive, every invariant
    /// finite, `m_ff`'s diagonal positive in the consistent formalism.
    pub fn from_parts(
        shape: &str,
        elements: usize,
        reference: Reference,
        formalism: Formalism,
        p: Params,
    ) -> crate::Result<Self> {
        check_params(&p, &[])?;
        let shape = Shape::resolve(shape, None)?;
        let spec = BodySpec::new(shape, elements, reference)?.with_formalism(formalism);
        // In the element length `l = L/N`: evaluated at it exactly, the same
        // bits as the invariants in `L`, without rescaling every entry.
        let exact = spec.exact_invariants_in_element_length()?;
        check_params(&p, &params_used(&exact))?;
        let invariants = modal::Invariants::from_exact_elements(&exact, &p, elements)?;
        let dofs: Vec<String> = spec.dofs().iter().map(|d| d.to_string()).collect();
        check_invariants(&to_runtime(&invariants), &dofs, formalism)?;
        let available = modal::elastic_modes(&spec, p.length);
        Ok(Self {
            spec,
            params: p,
            invariants,
            dofs,
            available,
            nodes: None,
            varying_sections: false,
        })
    }

    /// The flexible body `f` of a built scene (`body`: its runtime body):
    /// equal elements of one section through the exact invariants
    /// ([`ReducibleBody::from_parts`], the body the command-line flags
    /// describe), a graded mesh, a section table or attached masses through
    /// the runtime's assembly ([`ReducibleBody::from_runtime`]).
    pub fn of_scene_body(
        f: &crate::scene::FlexSpec,
        body: &dyn crate::runtime::Body,
    ) -> crate::Result<Self> {
        if f.nodes.is_none() && f.sections.is_none() && f.masses.is_empty() {
            Self::from_parts(
                &f.shape,
                f.elements,
                f.reference,
                f.options.formalism,
                f.params,
            )
        } else {
            Self::from_runtime(
                &f.shape,
                f.elements,
                f.nodes.as_deref(),
                f.sections.is_some(),
                f.reference,
                f.options.formalism,
                f.params,
                &body.invariants(),
            )
        }
    }

    /// A body on a graded mesh (`nodes`: `Some`, from
    /// [`crate::runtime::KernelBody::with_nodes`]) or with varying sections
    /// (`varying_sections`, equal elements when `nodes` is `None`): the
    /// invariants are the runtime's assembly `inv` of its elements (the
    /// exact invariants are those of equal elements of one section),
    /// checked like [`ReducibleBody::from_parts`]. Clamped and pinned bodies
    /// only: a free body's rigid-body motions are written for equal
    /// elements.
    #[allow(clippy::too_many_arguments)]
    pub fn from_runtime(
        shape: &str,
        elements: usize,
        nodes: Option<&[f64]>,
        varying_sections: bool,
        reference: Reference,
        formalism: Formalism,
        p: Params,
        inv: &crate::runtime::Invariants,
    ) -> crate::Result<Self> {
        if reference == Reference::Free {
            return Err(
                "a free body on a graded mesh, with a section table or with attached masses cannot be reduced yet (its rigid-body motions are written for equal elements of one section)"
                    .into(),
            );
        }
        let shape = Shape::resolve(shape, None)?;
        let spec = BodySpec::new(shape, elements, reference)?.with_formalism(formalism);
        let dofs: Vec<String> = spec.dofs().iter().map(|d| d.to_string()).collect();
        check_invariants(inv, &dofs, formalism)?;
        let invariants = modal::Invariants {
            dim: inv.dim,
            mass: inv.mass,
            s_t0: inv.s_t0,
            s_bar: crate::runtime::nalgebra::DMatrix::from_iterator(
                3,
                inv.nf(),
                inv.s_bar.iter().copied(),
            ),
            s_kl: inv.s_kl.clone(),
            i_kl: inv.i_kl.clone(),
            theta: inv.theta,
            m_ff: inv.m_ff.clone(),
            k_ff: inv.k_ff.clone(),
        };
        let available = dofs.len();
        Ok(Self {
            spec,
            params: p,
            invariants,
            dofs,
            available,
            nodes: nodes.map(<[f64]>::to_vec),
            varying_sections,
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
    ) -> crate::Result<ModalBasis> {
        let basis = self.reduce_unchecked(count, boundary, flag)?;
        self.check_basis(&basis)?;
        Ok(basis)
    }

    /// Every number of `basis` and of the invariants projected onto it
    /// finite, named as `ffr modes --json` keys it: at extreme parameters
    /// (`--rho 1e-300`) the eigenproblem overflows, and `inf`, `NaN` or JSON
    /// `null` must not be printed or written.
    fn check_basis(&self, basis: &ModalBasis) -> crate::Result<()> {
        let label = |j: usize| {
            basis
                .labels
                .get(j)
                .map_or(String::new(), |l| format!(" ({l})"))
        };
        let dof = |i: usize| {
            self.dofs
                .get(i)
                .map_or(String::new(), |l| format!(" ({l})"))
        };
        for (j, w) in basis.frequencies.iter().enumerate() {
            finite(|| format!("omega[{j}]{}", label(j)), *w)?;
        }
        for i in 0..basis.phi.nrows() {
            for j in 0..basis.phi.ncols() {
                finite(
                    || format!("phi[{i}][{j}]{}{}", dof(i), label(j)),
                    basis.phi[(i, j)],
                )?;
            }
        }
        for (name, m) in [
            ("modal_mass", &basis.modal_mass),
            ("modal_stiffness", &basis.modal_stiffness),
        ] {
            for i in 0..m.nrows() {
                for j in 0..m.ncols() {
                    finite(|| format!("{name}[{i}][{j}]{}", label(i)), m[(i, j)])?;
                }
            }
        }
        let projected = self.invariants.project(&basis.phi);
        check_invariants(&to_runtime(&projected), &basis.labels, Formalism::Lumped)
            .map_err(|e| crate::Error::Invalid(format!("invariants.{e}")))
    }

    fn reduce_unchecked(
        &self,
        count: Option<usize>,
        boundary: &[usize],
        flag: &str,
    ) -> crate::Result<ModalBasis> {
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
    ) -> crate::Result<ModalBasis> {
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
        modal::describe_body(
            &self.spec,
            self.nodes.is_some(),
            self.varying_sections,
            self.available,
        )
    }
}

/// How a flexible body is reduced to modes in a scene (keys `modes`,
/// `boundary`, `static_modes`, `modal_damping`) and by `ffr spin-up --modes`.
pub use crate::runtime::spec::scene::ModalSettings;

impl ReducibleBody {
    /// The runtime body reduced as `settings` say: the basis (with static
    /// modes if asked), the projected invariants, the modal damping; `full`
    /// is the same body with nodal coordinates, whose kernels must have the
    /// stiffening model `stiffening`: its point shapes place markers and,
    /// with stiffening, its elastic kernels give the elastic force at `Φ η`.
    pub fn runtime_body(
        &self,
        settings: &ModalSettings,
        stiffening: Stiffening,
        full: Box<dyn Body>,
    ) -> crate::Result<ModalBody> {
        let model = self.model(settings, stiffening, &*full)?;
        let data = modal_data(&model, self.description());
        Ok(ModalBody::new(full, data)?)
    }

    /// [`ReducibleBody::runtime_body`] whose inertia equations run through
    /// the generated modal kernels on tapes (the programs `ffr emit --modes`
    /// compiles, [`crate::runtime::modal_tape::TapeModalKernels`]); above
    /// [`modal::MAX_GENERATED_MODES`] modes the run-time equations, as
    /// generated code does ([`ModalBody::uses_generated_kernels`] tells).
    pub fn tape_body(
        &self,
        settings: &ModalSettings,
        stiffening: Stiffening,
        full: Box<dyn Body>,
    ) -> crate::Result<ModalBody> {
        let model = self.model(settings, stiffening, &*full)?;
        let dim = full.layout().scene_dim;
        let scene = crate::runtime::spec::SceneDim::from_dim(dim)
            .ok_or_else(|| format!("the full body's scene dimension is {dim}, not 2 or 3"))?;
        let kernels = modal::generate_modal_kernels(&model, scene)?;
        let data = modal_data(&model, self.description());
        Ok(match kernels {
            Some(set) => ModalBody::with_kernels(
                full,
                data,
                Box::new(crate::runtime::modal_tape::TapeModalKernels::from_set(&set)),
            )?,
            None => ModalBody::new(full, data)?,
        })
    }

    /// The reduced body's numbers (see [`ReducibleBody::runtime_body`]).
    fn model(
        &self,
        settings: &ModalSettings,
        stiffening: Stiffening,
        full: &dyn Body,
    ) -> crate::Result<modal::ModalModel> {
        if full.layout().nf != self.dofs.len() {
            return Err(format!(
                "the full body has {} elastic coordinates, the reduction {}",
                full.layout().nf,
                self.dofs.len()
            )
            .into());
        }
        let base = self.reduce(Some(settings.modes), &settings.boundary, "`modes`")?;
        Ok(modal::ModalModel::new(
            &self.spec,
            &self.params,
            &self.invariants,
            base,
            settings,
            stiffening,
        )?)
    }
}

/// The runtime's [`ModalData`] of `model`, `body` naming the full body.
pub fn modal_data(model: &modal::ModalModel, body: String) -> ModalData {
    let description = model.describe(&body);
    ModalData {
        invariants: to_runtime(&model.projected),
        phi: model.basis.phi.clone(),
        // The stiffening energy through the full body's kernels at Φ η.
        stiffening: model.stiffening.is_on(),
        damping: model.damping.clone(),
        labels: model.basis.labels.clone(),
        description,
    }
}

/// The modal body `settings` make of the beam `beam` describes (its full
/// body, built as usual, places the markers).
pub fn modal_body(beam: &BeamSpec, settings: &ModalSettings) -> crate::Result<ModalBody> {
    reducible(beam)?.runtime_body(settings, beam.options.stiffening, Box::new(beam.body()?))
}

/// The reduction of the beam `beam` describes.
fn reducible(beam: &BeamSpec) -> crate::Result<ReducibleBody> {
    ReducibleBody::from_parts(
        &beam.shape,
        beam.elements,
        beam.reference,
        beam.options.formalism,
        beam.params,
    )
}

/// [`modal_body`] with the generated inertia kernels on tapes
/// ([`ReducibleBody::tape_body`]).
pub fn modal_body_tape(beam: &BeamSpec, settings: &ModalSettings) -> crate::Result<ModalBody> {
    reducible(beam)?.tape_body(settings, beam.options.stiffening, Box::new(beam.body()?))
}

/// `quantity` is `v`: an error unless `v` is finite.
pub fn finite(quantity: impl Fn() -> String, v: f64) -> crate::Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!(
            "{} is {v} at these parameters, not a finite number: the parameters are too large or too small for f64 (nothing written)",
            quantity()
        )
        .into())
    }
}
