// The bodies this crate generates from build.rs. Shared (with `include!`) by
// build.rs and tests/generated_code.rs, so the snapshot test reviews exactly
// what the build writes.

/// Every body of the crate, generated into `OUT_DIR/<name>.rs`.
fn ffr_bodies() -> ffr_codegen::Builder {
    use ffr_codegen::{Builder, Formalism, Reference};
    Builder::new()
        // The same beam as `attr::Arm`.
        .body("arm", "beam3", 8, Reference::Clamped)
        // A user shape file, relative to the crate root.
        .body("bar", "shapes/bar.toml", 4, Reference::Clamped)
        // Non-default options: lumped masses and geometric stiffening.
        .body("spinning_blade", "beam2", 3, Reference::Pinned)
        .formalism(Formalism::Lumped)
        .stiffening(true)
}
