//! Generated code pinned by `insta` snapshots (review changes with
//! `cargo insta review`), and its determinism.
//!
//! The element-kernel files of beam2 in a planar scene and beam3 in a
//! spatial scene, with and without (fourth-order) stiffening, one lumped;
//! and the items a fixed-mesh body adds to its kernels.

use ffr_codegen::builder::{BodyConfig, Builder, KernelConfig};
use ffr_codegen::{
    emit_kernels_file, generate_kernels, Formalism, FrameModel, KernelModel, KernelOptions,
    Reference, SceneDim, Shape, Stiffening,
};

fn kernels(shape: &str, scene_dim: usize, formalism: Formalism, stiffening: Stiffening) -> String {
    let options = KernelOptions::new()
        .formalism(formalism)
        .stiffening(stiffening)
        .scene(SceneDim::from_dim(scene_dim).unwrap());
    let set = generate_kernels(&KernelModel::new(
        Shape::resolve(shape, None).unwrap(),
        options,
    ))
    .unwrap();
    let name = format!(
        "{}{}",
        shape.replace("beam", "Beam"),
        if scene_dim == 2 { "Planar" } else { "Spatial" }
    );
    emit_kernels_file(&set, &name, "::ffr_runtime")
}

#[test]
fn beam2_planar() {
    insta::assert_snapshot!(kernels("beam2", 2, Formalism::Consistent, Stiffening::Off));
}

#[test]
fn beam2_planar_fourth_order() {
    insta::assert_snapshot!(kernels(
        "beam2",
        2,
        Formalism::Consistent,
        Stiffening::FourthOrder
    ));
}

#[test]
fn beam2_planar_lumped() {
    insta::assert_snapshot!(kernels("beam2", 2, Formalism::Lumped, Stiffening::Off));
}

#[test]
fn beam3_spatial() {
    insta::assert_snapshot!(kernels("beam3", 3, Formalism::Consistent, Stiffening::Off));
}

#[test]
fn beam3_spatial_fourth_order() {
    insta::assert_snapshot!(kernels(
        "beam3",
        3,
        Formalism::Consistent,
        Stiffening::FourthOrder
    ));
}

/// Kernels for a frame whose motion is prescribed with its origin at rest
/// and no gravity: no `residual`/`tangent` (reference rows), no `ā` terms
/// (the header says what was left out and why).
#[test]
fn beam2_planar_prescribed_at_rest() {
    let options = KernelOptions::new()
        .stiffening(Stiffening::FourthOrder)
        .scene(SceneDim::Planar)
        .frame(FrameModel::PrescribedAtRest);
    let set = generate_kernels(&KernelModel::new(
        Shape::resolve("beam2", None).unwrap(),
        options,
    ))
    .unwrap();
    insta::assert_snapshot!(emit_kernels_file(
        &set,
        "Beam2PlanarPrescribed",
        "::ffr_runtime"
    ));
}

/// What a fixed-mesh body file adds to its kernels: the header's coordinate
/// list, the parameter struct and the `CompiledBody` implementation (the
/// kernels themselves are pinned above).
#[test]
fn beam2_body_items() {
    let files = Builder::new()
        .runtime_path("::ffr_runtime")
        .body(
            BodyConfig::new("arm", "beam2", 3, Reference::Pinned)
                .stiffening(Stiffening::SecondOrder),
        )
        .render()
        .unwrap();
    let text = &files[0].contents;
    let header: String = text
        .lines()
        .take_while(|l| l.starts_with("//"))
        .map(|l| format!("{l}\n"))
        .collect();
    let start = text
        .find("/// Parameters of an FFR body")
        .expect("the parameter struct");
    insta::assert_snapshot!(format!("{header}\n[… ArmKernels …]\n\n{}", &text[start..]));
}

#[test]
fn output_is_byte_identical_for_the_same_input() {
    for (shape, scene) in [("beam2", 2), ("beam3", 3)] {
        for s in [
            Stiffening::Off,
            Stiffening::SecondOrder,
            Stiffening::FourthOrder,
        ] {
            let a = kernels(shape, scene, Formalism::Consistent, s);
            let b = kernels(shape, scene, Formalism::Consistent, s);
            assert_eq!(a, b, "{shape} {s}: two runs differ");
        }
    }
}

/// The builder writes exactly what `emit_kernels_file` gives.
#[test]
fn builder_kernels_are_the_emitted_file() {
    let files = Builder::new()
        .runtime_path("::ffr_runtime")
        .kernels(
            KernelConfig::new("beam3_spatial", "beam3")
                .stiffening(Stiffening::FourthOrder)
                .scene_dim(3),
        )
        .render()
        .unwrap();
    assert_eq!(files[0].type_name, "Beam3Spatial");
    assert_eq!(
        files[0].contents,
        kernels("beam3", 3, Formalism::Consistent, Stiffening::FourthOrder)
    );
}

#[test]
fn the_same_file_text_gives_the_same_code_through_a_user_path() {
    let dir = std::env::temp_dir().join(format!("ffr-snap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("beam2.toml");
    std::fs::write(&path, include_str!("../shapes/beam2.toml")).unwrap();
    let from_file = Shape::from_file(&path).unwrap();
    let builtin = Shape::resolve("beam2", None).unwrap();
    assert_eq!(from_file.rows, builtin.rows);
    assert_eq!(from_file.coordinates, builtin.coordinates);
    assert_eq!(from_file.source_hash, builtin.source_hash);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A modal body's file, its header and the modal items (the full body's
/// kernels are pinned above): `BeamModal` with its generated inertia
/// kernels `BeamModalKernels` (beam2, 2 elements, 2 modes, no static modes,
/// no stiffening: the linear elastic force is in the kernels).
#[cfg(feature = "modal")]
#[test]
fn beam2_modal_body() {
    use ffr_codegen::modal::ModalModel;
    use ffr_codegen::{BodySpec, EmitOptions, ModalSettings, Params};
    let shape = Shape::resolve("beam2", None).unwrap();
    let spec = BodySpec::new(shape.clone(), 2, Reference::Clamped).unwrap();
    let p = Params {
        length: 2.0,
        rho: 2700.0,
        area: 3e-4,
        iy: 0.0,
        iz: 4e-9,
        e: 7e10,
        g: 0.0,
        j: 0.0,
    };
    let settings = ModalSettings {
        static_modes: false,
        ..ModalSettings::truncation(2)
    };
    let model = ModalModel::of_body(&spec, &p, &settings, Stiffening::Off).unwrap();
    let set = generate_kernels(&KernelModel::new(shape, KernelOptions::new())).unwrap();
    let opts = EmitOptions {
        type_name: "Beam".into(),
        ..EmitOptions::default()
    };
    let file = ffr_codegen::emit::emit_modal_body_file(&set, &spec, &opts, &model, &p).unwrap();
    let header_end = file.find("\n\n").unwrap();
    let modal = file
        .find("/// The body `Beam` at fixed parameters")
        .unwrap();
    insta::assert_snapshot!(format!("{}\n[…]\n{}", &file[..header_end], &file[modal..]));
}
