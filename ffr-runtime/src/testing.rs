//! Test bodies from the independent `ffr-reference` crate: its invariants
//! through [`InvariantBody`] plus its stiffening.

use crate::body::{FlexBody, InertiaTerms, InvariantBody, Invariants};
use ffr_reference::{RefBody, RefParams, Reference, Shape};
use nalgebra::DMatrix;

/// A reference beam as a [`FlexBody`].
pub struct RefFlex {
    pub reference: RefBody,
    pub inner: InvariantBody,
    pub stiffening: bool,
}

impl RefFlex {
    pub fn new(
        shape: Shape,
        elements: usize,
        reference: Reference,
        params: RefParams,
        stiffening: bool,
    ) -> Self {
        let reference = RefBody {
            shape,
            elements,
            reference,
            params,
        };
        let r = reference.invariants();
        let inv = Invariants {
            dim: if shape == Shape::Beam2 { 2 } else { 3 },
            mass: r.mass,
            s_t0: r.s_t0,
            s_bar: r.s_bar,
            s_kl: r.s_kl,
            i_kl: r.i_kl,
            theta: r.theta,
            m_ff: r.m_ff,
            k_ff: r.k_ff,
        };
        Self {
            reference,
            inner: InvariantBody::new(inv),
            stiffening,
        }
    }
    pub fn boxed(self) -> Box<dyn FlexBody> {
        Box::new(self)
    }
}

impl FlexBody for RefFlex {
    fn nf(&self) -> usize {
        self.inner.nf()
    }
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn dof_labels(&self) -> Vec<String> {
        self.reference.dof_labels()
    }
    fn invariants(&self) -> Invariants {
        self.inner.invariants()
    }
    fn inertia_terms(&self, q_f: &[f64], out: &mut InertiaTerms) {
        self.inner.inertia_terms(q_f, out)
    }
    fn has_stiffening(&self) -> bool {
        self.stiffening
    }
    fn stiffening(&self, q_f: &[f64], force: &mut [f64], tangent: Option<&mut DMatrix<f64>>) {
        let f = self.reference.stiffening_force(q_f);
        force.iter_mut().zip(f.iter()).for_each(|(a, b)| *a += b);
        if let Some(t) = tangent {
            *t += self.reference.stiffening_tangent(q_f);
        }
    }
}

/// Kane–Ryan–Banerjee beam: L = 8 m, A = 7.2968e-5 m², I = 8.2189e-9 m⁴,
/// E = 6.8952e10 Pa, ρ = 2766.67 kg/m³ (square-ish section giving that A and I_z).
pub fn krb_params() -> RefParams {
    // wy, wz with wy·wz = A and wz·wy³/12 = I  ⇒ wy² = 12 I / A.
    let (a, i): (f64, f64) = (7.2968e-5, 8.2189e-9);
    let wy = (12.0 * i / a).sqrt();
    RefParams {
        length: 8.0,
        rho: 2766.67,
        wy,
        wz: a / wy,
        e: 6.8952e10,
        g: 2.6e10,
        j: 1e-8,
    }
}

/// A short steel-ish beam for quick dynamics tests.
pub fn small_params() -> RefParams {
    RefParams {
        length: 1.0,
        rho: 7800.0,
        wy: 0.02,
        wz: 0.03,
        e: 2e9,
        g: 0.8e9,
        j: 2e-8,
    }
}

pub fn krb_beam(elements: usize, stiffening: bool) -> Box<dyn FlexBody> {
    RefFlex::new(
        Shape::Beam2,
        elements,
        Reference::Clamped,
        krb_params(),
        stiffening,
    )
    .boxed()
}
