//! The attribute and the build script call the same generator: the bodies
//! they produce must agree to the last bit.

use arm_crate::{attr, built};
use ffr::runtime::spec::Params;
use ffr::runtime::{sample_bits, Body, CompiledBody, KernelBody};

/// Both types give the same bits for everything the body computes
/// (invariants, mass blocks, forces, tangent, energy) at rest and deformed.
fn assert_same<A, B>(a: &A, b: &B)
where
    A: CompiledBody,
    B: CompiledBody,
{
    assert_eq!(A::NF, B::NF);
    assert_eq!(A::DIM, B::DIM);
    assert_eq!(A::DOFS, B::DOFS);
    assert_eq!(A::ELEMENTS, B::ELEMENTS);
    assert_eq!(A::REFERENCE, B::REFERENCE);
    let ba = KernelBody::compiled(a).unwrap();
    let bb = KernelBody::compiled(b).unwrap();
    let inv = ba.invariants();
    assert!(inv.mass > 0.0 && inv.mass.is_finite());
    assert_eq!(sample_bits(&ba, 1e-3), sample_bits(&bb, 1e-3));
}

/// 1 m steel bar, 10 mm × 10 mm.
fn steel() -> Params {
    Params {
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
    assert_eq!(<attr::Arm as CompiledBody>::NF, 8 * 6);
    assert_eq!(<attr::Arm as CompiledBody>::DIM, 3);
    // The mass of the beam is ρ A L.
    let mass = KernelBody::compiled(&a).unwrap().invariants().mass;
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
        <attr::Bar as CompiledBody>::DOFS,
        ["ux_1", "uy_1", "ux_2", "uy_2", "ux_3", "uy_3", "ux_4", "uy_4"]
    );
    let inv = KernelBody::compiled(&a).unwrap().invariants();
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
    assert_same(&a, &b);
    // Stiffening is on: a stretched, bent blade has an elastic energy above
    // the linear ½ qᵀ K_ff q.
    let body = KernelBody::compiled(&a).unwrap();
    let nf = <attr::SpinningBlade as CompiledBody>::NF;
    let q: Vec<f64> = (0..nf).map(|i| 2e-2 * (i as f64 + 1.0).sin()).collect();
    let k = body.invariants().k_ff;
    let linear = 0.5
        * (k.clone() * ffr::runtime::nalgebra::DVector::from_column_slice(&q))
            .dot(&ffr::runtime::nalgebra::DVector::from_column_slice(&q));
    let energy = body.elastic_energy(&q, &mut body.work());
    assert!(
        (energy - linear).abs() > 1e-9 * linear,
        "stiffening energy missing: {energy} vs linear {linear}"
    );
}

/// The modal body generated at build time (`BodyConfig::modes`: the basis
/// and the projected invariants baked in as constants, the inertia
/// equations as generated kernels) is the runtime's modal body of the same
/// beam and reduction with the same generated programs on tapes
/// (`ffr::modal::modal_body_tape`): the same bits for everything it
/// computes, at rest and deformed, and the same modes; the constants are
/// those of the runtime's modal body with the run-time equations
/// (`ffr::modal::modal_body`, what a scene file with `modes = 2` builds;
/// ffr-cli/tests/modal_body.rs compares the two sets of equations).
#[test]
fn generated_modal_body_is_the_runtime_one() {
    use arm_crate::built::{SpinUpBeam, SpinUpBeamModal};
    use ffr::kernels::BeamSpec;
    use ffr::runtime::spec::{Reference, Stiffening};
    let generated = SpinUpBeamModal::body().unwrap();
    let mut beam = BeamSpec::new("beam2", 4, SpinUpBeamModal::params());
    beam.reference = Reference::Clamped;
    beam.options.stiffening = Stiffening::FourthOrder;
    let settings = ffr::modal::ModalSettings::truncation(2);
    let runtime = ffr::modal::modal_body_tape(&beam, &settings).unwrap();
    assert!(generated.uses_generated_kernels() && runtime.uses_generated_kernels());
    assert_eq!(generated.layout().labels, runtime.layout().labels);
    assert_eq!(generated.data().description, runtime.data().description);
    assert_eq!(generated.layout().nf, SpinUpBeamModal::MODES);
    assert_eq!(
        generated.data().phi.nrows(),
        <SpinUpBeam as CompiledBody>::NF
    );
    assert_eq!(sample_bits(&generated, 1e-3), sample_bits(&runtime, 1e-3));
    let plain = ffr::modal::modal_body(&beam, &settings).unwrap();
    assert!(!plain.uses_generated_kernels());
    assert_eq!(generated.data().phi, plain.data().phi);
    assert_eq!(generated.invariants(), plain.invariants());
}

/// The attribute's `SpinUpBeam16Modal` (16 beam2, 4 modes plus 14 static
/// modes, fourth-order stiffening; its inertia equations as generated
/// kernels) is the run-time reduction of the same beam with the same
/// programs on tapes, bit for bit.
#[test]
fn attribute_modal_body_with_generated_kernels_is_the_tape_one() {
    use arm_crate::attr::SpinUpBeam16Modal;
    use ffr::kernels::BeamSpec;
    use ffr::runtime::spec::{Reference, Stiffening};
    let generated = SpinUpBeam16Modal::body().unwrap();
    let mut beam = BeamSpec::new("beam2", 16, SpinUpBeam16Modal::params());
    beam.reference = Reference::Clamped;
    beam.options.stiffening = Stiffening::FourthOrder;
    let settings = ffr::modal::ModalSettings::truncation(4);
    let tape = ffr::modal::modal_body_tape(&beam, &settings).unwrap();
    assert_eq!(SpinUpBeam16Modal::MODES, 18);
    assert!(generated.uses_generated_kernels() && tape.uses_generated_kernels());
    assert_eq!(generated.layout().labels, tape.layout().labels);
    assert_eq!(sample_bits(&generated, 1e-3), sample_bits(&tape, 1e-3));
}
