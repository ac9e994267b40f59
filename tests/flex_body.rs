//! `#[ffr::flex_body]` in the root crate: option handling, the fields it
//! needs and the ones it leaves alone, generic structs, and agreement with
//! the generator run at test time (the same model taped, bit for bit).

use ffr::kernels::BeamSpec;
use ffr::runtime::spec::{Formalism, Params, Reference, Stiffening};
use ffr::runtime::{sample_bits, Body, CompiledBody, KernelBody};

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

/// A planar shape in a spatial scene with the second-order model.
#[ffr::flex_body(
    shape = "beam2",
    elements = 2,
    scene = "spatial",
    stiffening = "second-order"
)]
pub struct InSpace {
    pub length: f64,
    pub rho: f64,
    pub area: f64,
    pub iz: f64,
    pub e: f64,
}

const V: Params = Params {
    length: 2.0,
    rho: 2700.0,
    area: 3e-4,
    iy: 2e-9,
    iz: 4e-9,
    e: 7e10,
    g: 2.6e10,
    j: 5e-9,
};

/// The attribute's body computes bit for bit what the generator's program
/// for the same model computes on a tape (`spec` with `force_tape`), and
/// the body's mass is ρ A L.
fn check_against_generator<B: CompiledBody>(body: &B, spec: BeamSpec) {
    let compiled = KernelBody::compiled(body).unwrap();
    let tape = BeamSpec {
        force_tape: true,
        ..spec
    }
    .body()
    .unwrap();
    assert!(matches!(tape.kernels(), ffr::Kernels::Tape(_)));
    assert_eq!(compiled.layout().labels, tape.layout().labels);
    assert_eq!(B::DOFS.len(), B::NF);
    assert_eq!(sample_bits(&compiled, 1e-3), sample_bits(&tape, 1e-3));
    let m = V.rho * V.area * V.length;
    assert!((compiled.invariants().mass - m).abs() <= 1e-12 * m);
}

#[test]
fn planar_body_without_unused_fields() {
    let body = Planar {
        name: "blade".into(),
        length: V.length,
        rho: V.rho,
        area: V.area,
        iz: V.iz,
        e: V.e,
        j: 7,
    };
    assert_eq!(<Planar as CompiledBody>::DIM, 2);
    // Pinned: node 0 loses u, v; node 3 loses v.
    assert_eq!(<Planar as CompiledBody>::NF, 4 * 3 - 3);
    assert_eq!(<Planar as CompiledBody>::REFERENCE, Reference::Pinned);
    // Unused parameters are passed as 0.
    assert_eq!((body.params().iy, body.params().j), (0.0, 0.0));
    let spec = BeamSpec {
        reference: Reference::Pinned,
        ..BeamSpec::new("beam2", 3, V)
    };
    check_against_generator(&body, spec);
    // The struct is kept as written (derives, other fields).
    assert_eq!(body.clone(), body);
    assert_eq!((body.name.as_str(), body.j), ("blade", 7));
}

#[test]
fn generic_struct_with_options() {
    let tag = String::from("t");
    let body = Tagged {
        tag: &tag,
        length: V.length,
        rho: V.rho,
        area: V.area,
        iy: V.iy,
        iz: V.iz,
        e: V.e,
        g: V.g,
        j: V.j,
    };
    assert_eq!(<Tagged<'_, String> as CompiledBody>::NF, 12);
    let spec = BeamSpec::new("beam3", 2, V)
        .formalism(Formalism::Lumped)
        .stiffening(Stiffening::FourthOrder);
    check_against_generator(&body, spec.clone());
    // A different option would be a different body: the check can fail.
    let second = BeamSpec {
        force_tape: true,
        ..spec.stiffening(Stiffening::SecondOrder)
    }
    .body()
    .unwrap();
    let compiled = KernelBody::compiled(&body).unwrap();
    assert_ne!(sample_bits(&compiled, 1e-3), sample_bits(&second, 1e-3));
    assert_eq!(body.tag, "t");
}

#[test]
fn planar_shape_in_a_spatial_scene() {
    let body = InSpace {
        length: V.length,
        rho: V.rho,
        area: V.area,
        iz: V.iz,
        e: V.e,
    };
    let compiled = KernelBody::compiled(&body).unwrap();
    assert_eq!(compiled.layout().scene_dim, 3);
    assert_eq!(compiled.layout().dim, 2);
    let spec = BeamSpec::new("beam2", 2, V)
        .stiffening(Stiffening::SecondOrder)
        .scene_dim(3);
    check_against_generator(&body, spec);
}

/// Sections that vary along the span, from a CSV table relative to the
/// crate root (tapered and twisted, resultant form): the attribute generates
/// varying-section kernels and bakes the table into the type; the body is
/// the scene loader's body on the same table (the generator's programs on
/// tapes), bit for bit.
#[ffr::flex_body(
    shape = "beam3",
    elements = 5,
    sections = "tests/data/taper.csv",
    stiffening = true
)]
pub struct Taper {}

#[test]
fn sections_from_a_table_are_baked_into_the_type() {
    let stations = Taper::SECTIONS.expect("a section table");
    assert_eq!(stations.len(), 4);
    assert_eq!((stations[1].x, stations[1].twist), (0.7, 0.19));
    let compiled = KernelBody::compiled(&Taper {}).unwrap();
    assert_eq!(compiled.params().length, 2.0);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let text = "dimension = 3\nt_end = 1.0\ndt = 0.01\n\n[bodies.taper]\nshape = \"beam3\"\nelements = 5\nstiffening = true\nsections = \"taper.csv\"\n";
    let s = ffr::scene::from_str(text, "taper.toml", &dir, &ffr::scene::DefaultKernels).unwrap();
    let loaded = s.system.body(s.system.body_id("taper").unwrap());
    assert_eq!(
        sample_bits(&compiled, 1e-3),
        sample_bits(loaded.as_ref(), 1e-3)
    );
    // The table is in it: the mass is the table's, not a uniform beam's.
    let m: f64 = stations
        .windows(2)
        .map(|w| 0.5 * (w[0].mass + w[1].mass) * (w[1].x - w[0].x))
        .sum();
    assert!((compiled.invariants().mass - m).abs() < 1e-12 * m);
}

/// The KRB spin-up beam on 4 elements reduced at build time to its 2 lowest
/// modes plus the static modes (the default), fourth-order stiffening.
#[ffr::flex_body(
    shape = "beam2",
    elements = 4,
    stiffening = true,
    modes = 2,
    params(
        length = 8.0,
        rho = 2766.67,
        area = 7.2968e-5,
        iz = 8.2189e-9,
        e = 6.8952e10
    )
)]
pub struct SpinBeam {
    pub length: f64,
    pub rho: f64,
    pub area: f64,
    pub iz: f64,
    pub e: f64,
}

/// Craig–Bampton with the tip node as the boundary (the default), no
/// static modes.
#[ffr::flex_body(
    shape = "beam3",
    elements = 3,
    modes = 2,
    reduction = "craig-bampton",
    static_modes = false,
    params(
        length = 2.0,
        rho = 2700,
        area = 3e-4,
        iy = 2e-9,
        iz = 4e-9,
        e = 7e10,
        g = 2.6e10,
        j = 5e-9
    )
)]
pub struct TipBoundary {
    pub length: f64,
    pub rho: f64,
    pub area: f64,
    pub iy: f64,
    pub iz: f64,
    pub e: f64,
    pub g: f64,
    pub j: f64,
}

/// `#[flex_body(modes = …)]` bakes the modal body in at build time, its
/// inertia equations as generated kernels: the same bits as the runtime's
/// modal body of the same beam and reduction with the same generated
/// programs on tapes (`ffr::modal::modal_body_tape`; `modal_body`, what a
/// scene file with `modes` builds, has the same constants and damping),
/// for modal truncation with static modes and for Craig–Bampton.
#[test]
fn modal_bodies_from_the_attribute_are_the_runtime_ones() {
    use ffr::modal::{modal_body, modal_body_tape, ModalSettings};
    let mut beam = BeamSpec::new("beam2", 4, SpinBeamModal::params());
    beam.options.stiffening = Stiffening::FourthOrder;
    let runtime = modal_body_tape(&beam, &ModalSettings::truncation(2)).unwrap();
    let generated = SpinBeamModal::body().unwrap();
    assert!(generated.uses_generated_kernels() && runtime.uses_generated_kernels());
    let plain = modal_body(&beam, &ModalSettings::truncation(2)).unwrap();
    assert_eq!(generated.data().phi, plain.data().phi);
    assert_eq!(generated.invariants(), plain.invariants());
    assert_eq!(SpinBeamModal::MODES, 9);
    assert_eq!(generated.layout().labels, runtime.layout().labels);
    assert_eq!(generated.data().description, runtime.data().description);
    assert_eq!(sample_bits(&generated, 1e-3), sample_bits(&runtime, 1e-3));

    let beam = BeamSpec::new("beam3", 3, TipBoundaryModal::params());
    let settings = ModalSettings {
        modes: 2,
        boundary: vec![3],
        static_modes: false,
        damping: Vec::new(),
    };
    let runtime = modal_body_tape(&beam, &settings).unwrap();
    let generated = TipBoundaryModal::body().unwrap();
    assert_eq!(
        generated.layout().labels,
        [
            "mode_1",
            "mode_2",
            "constraint_ux_3",
            "constraint_uy_3",
            "constraint_uz_3",
            "constraint_rx_3",
            "constraint_ry_3",
            "constraint_rz_3"
        ]
    );
    assert_eq!(sample_bits(&generated, 1e-3), sample_bits(&runtime, 1e-3));
}
