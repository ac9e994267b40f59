//! The attribute and the build script call the same generator: the bodies
//! they produce must agree to the last bit.

use arm_crate::{attr, built};
use ffr::runtime::{CompiledBody, FlexBody, InertiaTerms, Invariants};

/// Bit patterns of everything in the invariants.
fn invariant_bits(inv: &Invariants) -> Vec<u64> {
    let mut v = vec![inv.dim as u64, inv.mass.to_bits()];
    let mut push = |xs: &[f64]| v.extend(xs.iter().map(|x| x.to_bits()));
    push(inv.s_t0.as_slice());
    push(inv.s_bar.as_slice());
    for k in 0..3 {
        for l in 0..3 {
            push(inv.s_kl[k][l].as_slice());
            push(inv.i_kl[k][l].as_slice());
        }
    }
    push(inv.theta.as_slice());
    push(inv.m_ff.as_slice());
    push(inv.k_ff.as_slice());
    v
}

fn inertia_bits(body: &dyn FlexBody, q_f: &[f64]) -> Vec<u64> {
    let mut out = InertiaTerms::zeros(body.nf());
    body.inertia_terms(q_f, &mut out);
    [
        out.s_t.as_slice(),
        out.i_theta_theta.as_slice(),
        out.i_theta_f.as_slice(),
    ]
    .concat()
    .iter()
    .map(|x| x.to_bits())
    .collect()
}

fn stiffening_bits(body: &dyn FlexBody, q_f: &[f64]) -> Vec<u64> {
    let nf = body.nf();
    let mut force = vec![0.0; nf];
    let mut tangent = ffr::nalgebra::DMatrix::zeros(nf, nf);
    body.stiffening(q_f, &mut force, Some(&mut tangent));
    force
        .iter()
        .chain(tangent.as_slice())
        .map(|x| x.to_bits())
        .collect()
}

/// A deformed state that touches every coordinate.
fn q_f(nf: usize) -> Vec<f64> {
    (0..nf)
        .map(|i| 1e-3 * ((i as f64 + 1.0) * 0.7).sin())
        .collect()
}

/// Both bodies give the same bits for invariants, inertia terms and stiffening.
fn assert_same(a: &dyn FlexBody, b: &dyn FlexBody) {
    assert_eq!(a.nf(), b.nf());
    assert_eq!(a.dim(), b.dim());
    assert_eq!(a.dof_labels(), b.dof_labels());
    let inv = a.invariants();
    assert!(inv.mass > 0.0 && inv.mass.is_finite());
    assert_eq!(invariant_bits(&inv), invariant_bits(&b.invariants()));
    for q in [vec![0.0; a.nf()], q_f(a.nf())] {
        assert_eq!(inertia_bits(a, &q), inertia_bits(b, &q));
        assert_eq!(a.has_stiffening(), b.has_stiffening());
        assert_eq!(stiffening_bits(a, &q), stiffening_bits(b, &q));
    }
}

/// 1 m steel bar, 10 mm × 10 mm.
fn steel() -> ffr::runtime::Params {
    ffr::runtime::Params {
        length: 1.0,
        rho: 7850.0,
        area: 1e-4,
        iy: 1e-8 / 12.0,
        iz: 1e-8 / 12.0,
        e: 2.1e11,
        g: 8.1e10,
        j: 1.406e-8,
    }
}

#[test]
fn arm_is_the_same_both_ways() {
    let p = steel();
    let a = attr::Arm {
        length: p.length,
        rho: p.rho,
        area: p.area,
        iy: p.iy,
        iz: p.iz,
        e: p.e,
        g: p.g,
        j: p.j,
    };
    let b = built::Arm::from(p);
    assert_same(&a, &b);
    assert_eq!(
        <attr::Arm as CompiledBody>::NF,
        <built::Arm as CompiledBody>::NF
    );
    assert_eq!(<attr::Arm as CompiledBody>::NF, 8 * 6);
    assert_eq!(<attr::Arm as CompiledBody>::DIM, 3);
    assert_eq!(
        <attr::Arm as CompiledBody>::DOFS,
        <built::Arm as CompiledBody>::DOFS
    );
    assert!(!a.has_stiffening());
    // Cross-check against the generator's own numeric evaluation.
    let mass = a.invariants().mass;
    assert!((mass - p.rho * p.area * p.length).abs() <= 1e-12 * mass);
}

#[test]
fn user_shape_file_works_both_ways() {
    let p = steel();
    let a = attr::Bar {
        label: "bar",
        length: p.length,
        rho: p.rho,
        area: p.area,
        iz: p.iz,
        e: p.e,
    };
    let b = built::Bar::from(p);
    assert_same(&a, &b);
    // Clamped at node 0: u, v at nodes 1..=4.
    assert_eq!(<attr::Bar as CompiledBody>::NF, 8);
    assert_eq!(<attr::Bar as CompiledBody>::DIM, 2);
    assert_eq!(
        a.dof_labels(),
        ["ux_1", "uy_1", "ux_2", "uy_2", "ux_3", "uy_3", "ux_4", "uy_4"]
    );
    let inv = a.invariants();
    let m = p.rho * p.area * p.length;
    assert!((inv.mass - m).abs() <= 1e-12 * m);
    // Linear shapes: the first moment along x is m L / 2.
    assert!((inv.s_t0[0] - m * p.length / 2.0).abs() <= 1e-12 * m);
    // Axial stiffness of the last element: EA / l on the end node's u.
    let l = p.length / 4.0;
    let k = p.e * p.area / l;
    assert!((inv.k_ff[(6, 6)] - k).abs() <= 1e-9 * k);
    assert_eq!(a.label, "bar");
}

#[test]
fn options_are_the_same_both_ways() {
    let p = steel();
    let a = attr::SpinningBlade {
        length: p.length,
        rho: p.rho,
        area: p.area,
        iz: p.iz,
        e: p.e,
    };
    let b = built::SpinningBlade::from(p);
    assert!(a.has_stiffening());
    assert_same(&a, &b);
}
