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
        // Every scene shipped with ffr, compiled the same way
        // (tests/compiled_scene.rs checks each against `ffr run`).
        .scene_named("builtin_free_floating", "../../scenes/free_floating.toml")
        .scene_named("builtin_pendulum", "../../scenes/pendulum.toml")
        .scene_named("builtin_precone", "../../scenes/precone.toml")
        .scene_named("builtin_slider_crank", "../../scenes/slider_crank.toml")
        .scene_named("builtin_spin_up", "../../scenes/spin_up.toml")
        .scene_named("builtin_spin_up_modal", "../../scenes/spin_up_modal.toml")
        .scene_named("builtin_two_link_arm", "../../scenes/two_link_arm.toml")
        .scene_named("builtin_blade_5mw", "../../scenes/blade_5mw.toml")
        .scene_named("builtin_boom_payload", "../../scenes/boom_payload.toml")
}
