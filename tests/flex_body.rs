//! `#[ffr::flex_body]` in the root crate: option handling, the fields it
//! needs and the ones it leaves alone, generic structs, and agreement with
//! the generator's own numeric evaluation.

use ffr::codegen::{BodySpec, Formalism, Options, ParamValues, Reference, Shape};
use ffr::runtime::{CompiledBody, FlexBody, InertiaTerms};

/// A planar beam needs only `length, rho, area, iz, e`; other fields (of any
/// type, also raw identifiers and spelled-out `f64`) are left alone.
#[ffr::flex_body(shape = "beam2", elements = 3, reference = "pinned")]
#[derive(Clone, Debug, PartialEq)]
pub struct Planar {
    /// Not a parameter.
    pub name: String,
    pub length: f64,
    pub r#rho: f64,
    pub area: core::primitive::f64,
    pub iz: f64,
    pub e: f64,
    /// Not used by a planar beam, so any type is fine.
    pub j: u8,
}

/// Lumped masses with geometric stiffening, on a generic struct.
#[ffr::flex_body(shape = "beam3", elements = 2, formalism = "lumped", stiffening = true)]
pub struct Tagged<'a, T: Clone> {
    pub tag: &'a T,
    pub length: f64,
    pub rho: f64,
    pub area: f64,
    pub iy: f64,
    pub iz: f64,
    pub e: f64,
    pub g: f64,
    pub j: f64,
}

fn values() -> ParamValues {
    ParamValues {
        length: 2.0,
        rho: 2700.0,
        area: 3e-4,
        iy: 2e-9,
        iz: 4e-9,
        e: 7e10,
        g: 2.6e10,
        j: 5e-9,
    }
}

fn close(a: f64, b: f64, scale: f64) {
    assert!((a - b).abs() <= 1e-12 * scale, "{a} vs {b}");
}

/// The expansion's invariants agree with `Generated::eval_invariants`.
fn check_against_generator(body: &dyn FlexBody, spec: BodySpec, options: Options) {
    let g = ffr::codegen::generate(&spec, options).unwrap();
    let want = g.eval_invariants(&values());
    let got = body.invariants();
    assert_eq!(body.nf(), want.dofs.len());
    assert_eq!(body.dof_labels(), want.dofs);
    assert_eq!(body.dim(), want.dim);
    close(got.mass, want.mass, want.mass);
    let nf = body.nf();
    let big = |m: &Vec<Vec<f64>>| m.iter().flatten().fold(0f64, |a, x| a.max(x.abs()));
    let (sm, sk) = (big(&want.m_ff), big(&want.k_ff));
    for a in 0..nf {
        for b in 0..nf {
            close(got.m_ff[(a, b)], want.m_ff[a][b], sm);
            close(got.k_ff[(a, b)], want.k_ff[a][b], sk);
        }
    }
    for k in 0..3 {
        close(got.s_t0[k], want.s_t0[k], want.mass * 2.0);
    }
}

#[test]
fn planar_body_without_unused_fields() {
    let v = values();
    let body = Planar {
        name: "blade".into(),
        length: v.length,
        rho: v.rho,
        area: v.area,
        iz: v.iz,
        e: v.e,
        j: 7,
    };
    assert_eq!(<Planar as CompiledBody>::DIM, 2);
    // Pinned: node 0 loses u, v; node 3 loses v.
    assert_eq!(<Planar as CompiledBody>::NF, 4 * 3 - 3);
    assert!(!body.has_stiffening());
    let spec = BodySpec::new(Shape::resolve("beam2", None).unwrap(), 3, Reference::Pinned).unwrap();
    check_against_generator(&body, spec, Options::default());
    // The struct is kept as written (derives, other fields).
    assert_eq!(body.clone(), body);
    assert_eq!((body.name.as_str(), body.j), ("blade", 7));
}

#[test]
fn generic_struct_with_options() {
    let v = values();
    let tag = String::from("t");
    let body = Tagged {
        tag: &tag,
        length: v.length,
        rho: v.rho,
        area: v.area,
        iy: v.iy,
        iz: v.iz,
        e: v.e,
        g: v.g,
        j: v.j,
    };
    assert_eq!(<Tagged<'_, String> as CompiledBody>::NF, 12);
    assert!(body.has_stiffening());
    let spec = BodySpec::new(
        Shape::resolve("beam3", None).unwrap(),
        2,
        Reference::Clamped,
    )
    .unwrap()
    .with_formalism(Formalism::Lumped);
    check_against_generator(&body, spec, Options { stiffening: true });
    // Stiffening is active: a stretched and bent state gives a force.
    let q: Vec<f64> = (0..12).map(|i| 1e-3 * (i as f64 + 1.0)).collect();
    let mut force = vec![0.0; 12];
    body.stiffening(&q, &mut force, None);
    assert!(force.iter().any(|f| *f != 0.0));
    let mut out = InertiaTerms::zeros(12);
    body.inertia_terms(&q, &mut out);
    assert!(out.i_theta_theta[(0, 0)] > 0.0);
    assert_eq!(body.tag, "t");
}
