//! Generated code pinned by `insta` snapshots (review changes with
//! `cargo insta review`), and its determinism.

use ffr_codegen::{emit_file, BodySpec, EmitOptions, Options, Reference, Shape};

fn emit(shape: &str, n: usize, stiffening: bool) -> String {
    let spec = BodySpec::new(Shape::resolve(shape, None).unwrap(), n, Reference::Clamped).unwrap();
    let g = ffr_codegen::generate(&spec, Options { stiffening }).unwrap();
    let opts = EmitOptions {
        type_name: format!("{}N{n}", shape.replace("beam", "Beam")),
        ..EmitOptions::default()
    };
    emit_file(&g, &opts)
}

#[test]
fn beam2_one_element() {
    insta::assert_snapshot!(emit("beam2", 1, false));
}

#[test]
fn beam2_two_elements() {
    insta::assert_snapshot!(emit("beam2", 2, false));
}

#[test]
fn beam2_one_element_with_stiffening() {
    insta::assert_snapshot!(emit("beam2", 1, true));
}

#[test]
fn beam3_one_element() {
    insta::assert_snapshot!(emit("beam3", 1, false));
}

#[test]
fn beam3_two_elements() {
    insta::assert_snapshot!(emit("beam3", 2, false));
}

#[test]
fn output_is_byte_identical_for_the_same_input() {
    for (shape, n) in [("beam2", 3), ("beam3", 2)] {
        let a = emit(shape, n, true);
        let b = emit(shape, n, true);
        assert_eq!(a, b, "{shape} {n}: two runs differ");
    }
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
