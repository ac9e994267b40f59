// The bodies this crate generates from build.rs. Shared (with `include!`) by
// build.rs and tests/generated_code.rs, so the snapshot test reviews exactly
// what the build writes.

/// Every body of the crate, generated into `OUT_DIR/<name>.rs`.
fn ffr_bodies() -> ffr_codegen::Builder {
    use ffr_codegen::{
        BodyConfig, Builder, Formalism, ModalSettings, Params, Reference, Stiffening,
    };
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
        // A body reduced to modes at build time: the KRB spin-up beam on 4
        // elements, its 2 lowest modes plus the static modes, fourth-order
        // stiffening. `SpinUpBeamModal::body()` is the modal body with the
        // basis and the projected invariants baked in.
        .body(
            BodyConfig::new("spin_up_beam", "beam2", 4, Reference::Clamped)
                .stiffening(Stiffening::FourthOrder)
                .modes(
                    Params {
                        length: 8.0,
                        rho: 2766.67,
                        area: 7.2968e-5,
                        iy: 0.0,
                        iz: 8.2189e-9,
                        e: 6.8952e10,
                        g: 0.0,
                        j: 0.0,
                    },
                    ModalSettings::truncation(2),
                ),
        )
        // A whole scene: the specialized kernels of its flexible bodies and
        // `TwoLinksScene::load()`, which simulates like `ffr run` on the file.
        .scene("scenes/two_links.toml")
        // A body run as segments (`segments = 4`): kernels for the root
        // segment's prescribed frame and for the free frames of `beam[2]` …
        // `beam[4]`; and modal segments, each reduced when compiled.
        .scene("scenes/spin_up_segments.toml")
        .scene("scenes/spin_up_modal_segments.toml")
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
        // Markers with their own axes and a point force with a profile table.
        .scene_named("builtin_l_frame", "../../scenes/l_frame.toml")
}
