//! The same FFR bodies generated two ways: by the `#[ffr::flex_body]`
//! attribute ([`attr`]) and by a build script with `ffr_codegen::Builder`
//! ([`built`]). `tests/same_code.rs` checks that both give bit-identical
//! results. [`scenes`] holds a scene file compiled by the build script,
//! which simulates bit for bit like `ffr run` on the same file.

/// Bodies from `#[ffr::flex_body]`.
pub mod attr {
    /// A clamped spatial beam of 8 elements.
    #[ffr::flex_body(shape = "beam3", elements = 8, reference = "clamped")]
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Arm {
        pub length: f64,
        pub rho: f64,
        pub area: f64,
        pub iy: f64,
        pub iz: f64,
        pub e: f64,
        pub g: f64,
        pub j: f64,
    }

    /// A bar from the crate's own shape file: planar, so only the fields the
    /// shape uses are needed (no `iy`, `g`, `j`); other fields are left alone.
    #[ffr::flex_body(shape = "shapes/bar.toml", elements = 4)]
    #[derive(Clone, Debug)]
    pub struct Bar {
        pub label: &'static str,
        pub length: f64,
        pub rho: f64,
        pub area: f64,
        pub iz: f64,
        pub e: f64,
    }

    /// Lumped masses and geometric stiffening.
    #[ffr::flex_body(
        shape = "beam2",
        elements = 3,
        reference = "pinned",
        formalism = "lumped",
        stiffening = true
    )]
    pub struct SpinningBlade {
        pub length: f64,
        pub rho: f64,
        pub area: f64,
        pub iz: f64,
        pub e: f64,
    }

    /// A spatial beam run as 4 segments of 2 elements
    /// (`ThrownBeam::segments()` for `System::add_segments`): the type is
    /// the whole body as one, the constructor splits it as the scene file
    /// `scenes/thrown_segments.toml` does (tests/attribute_segments.rs).
    #[ffr::flex_body(
        shape = "beam3",
        elements = 8,
        segments = 4,
        reference = "clamped",
        stiffening = true
    )]
    #[derive(Clone, Copy, Debug)]
    pub struct ThrownBeam {
        pub length: f64,
        pub rho: f64,
        pub area: f64,
        pub iy: f64,
        pub iz: f64,
        pub e: f64,
        pub g: f64,
        pub j: f64,
    }

    /// The KRB spin-up beam on 16 elements reduced at build time to its 4
    /// lowest modes plus the static modes (8 modes in all), fourth-order
    /// stiffening: `SpinUpBeam16Modal::body()` runs the generated
    /// `SpinUpBeam16ModalKernels` (`examples/modal_speed.rs` times them
    /// against the run-time equations).
    #[ffr::flex_body(
        shape = "beam2",
        elements = 16,
        reference = "clamped",
        stiffening = true,
        modes = 4,
        params(
            length = 8.0,
            rho = 2766.67,
            area = 7.2968e-5,
            iz = 8.2189e-9,
            e = 6.8952e10
        )
    )]
    pub struct SpinUpBeam16 {
        pub length: f64,
        pub rho: f64,
        pub area: f64,
        pub iz: f64,
        pub e: f64,
    }
}

/// Scenes from `build.rs`: `scenes/two_links.toml` and the scenes shipped
/// with ffr compiled (their bodies' kernels specialized for the scene, the
/// resolved scene as data).
pub mod scenes {
    include!(concat!(env!("OUT_DIR"), "/two_links.rs"));
    include!(concat!(env!("OUT_DIR"), "/spin_up_segments.rs"));
    include!(concat!(env!("OUT_DIR"), "/spin_up_modal_segments.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_free_floating.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_pendulum.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_precone.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_slider_crank.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_spin_up.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_spin_up_modal.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_two_link_arm.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_blade_5mw.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_boom_payload.rs"));
    include!(concat!(env!("OUT_DIR"), "/builtin_l_frame.rs"));
}

/// Bodies from `build.rs` (see `ffr_bodies.rs`): each file defines a struct
/// with all parameter fields and implements the same traits.
pub mod built {
    include!(concat!(env!("OUT_DIR"), "/arm.rs"));
    include!(concat!(env!("OUT_DIR"), "/bar.rs"));
    include!(concat!(env!("OUT_DIR"), "/spinning_blade.rs"));
    include!(concat!(env!("OUT_DIR"), "/spin_up_beam.rs"));
}
