// The bodies this crate generates from build.rs. Shared (with `include!`) by
// build.rs and tests/generated_code.rs, so the snapshot test reviews exactly
// what the build writes.

/// Every body of the crate, generated into `OUT_DIR/<name>.rs`.
fn ffr_bodies() -> ffr_codegen::Builder {
    use ffr_codegen::{BodyConfig, Builder, Formalism, Reference, Stiffening};
    Builder::new()
        // The same beam as `attr::Arm`.
        .body(BodyConfig::new("arm", "beam3", 8, Reference::Clamped))
        // A user shape file, relative to the crate root.
        .body(BodyConfig::new("bar", "shapes/bar.toml", 4, Reference::Clamped))
        // Options belong to their body: lumped masses and fourth-order
        // geometric stiffening for this one only.
        .body(
            BodyConfig::new("spinning_blade", "beam2", 3, Reference::Pinned)
                .formalism(Formalism::Lumped)
                .stiffening(Stiffening::FourthOrder),
        )
        // A whole scene: the specialized kernels of its flexible bodies and
        // `TwoLinksScene::load()`, which simulates like `ffr run` on the file.
        .scene("scenes/two_links.toml")
}
