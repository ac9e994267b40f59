//! Generates the benchmark bodies into OUT_DIR (see `src/lib.rs`).

use ffr_codegen::{emit_file, BodySpec, EmitOptions, Options, Reference, Shape};

/// (type name, shape, elements, stiffening)
pub const BODIES: [(&str, &str, usize, bool); 4] = [
    ("Beam3N1", "beam3", 1, false),
    ("Beam3N8", "beam3", 8, false),
    ("Beam3N32", "beam3", 32, false),
    ("Beam2N4", "beam2", 4, true),
];

fn main() {
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").unwrap());
    for (name, shape, n, stiffening) in BODIES {
        let spec =
            BodySpec::new(Shape::resolve(shape, None).unwrap(), n, Reference::Clamped).unwrap();
        let g = ffr_codegen::generate(&spec, Options { stiffening }).unwrap();
        let opts = EmitOptions {
            type_name: name.to_string(),
            define_struct: true,
            runtime_path: "::ffr_runtime".to_string(),
        };
        std::fs::write(
            out.join(format!("{}.rs", name.to_lowercase())),
            emit_file(&g, &opts),
        )
        .unwrap();
    }
    println!("cargo:rerun-if-changed=build.rs");
}
