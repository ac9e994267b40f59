//! Generated element kernels and fixed-mesh bodies compiled at build time
//! (`build.rs`, the generator's `Builder` with runtime path `::ffr_runtime`;
//! the list is in [`configs`]), the same programs on tapes
//! (`ffr_runtime::tape`), for
//! benchmarks (`benches/kernels.rs`) and for the check that the compiled code
//! computes bit for bit what the tapes compute (`tests/compiled.rs`).

#[allow(missing_docs, clippy::all)]
pub mod configs {
    include!("configs.rs");
}

#[allow(missing_docs, clippy::all)]
mod registry {
    include!(concat!(env!("OUT_DIR"), "/registry.rs"));
}
pub use registry::*;

pub use ffr_runtime::tape;

use ffr_codegen::builder::KernelConfig;
use ffr_codegen::{generate_kernels, Formalism, KernelSet, Stiffening};
use ffr_runtime::spec::Params;

/// The generator's programs of the `configs::KERNELS` entry `name` (the
/// programs the compiled kernels of that name were emitted from).
pub fn kernel_set(name: &str) -> KernelSet {
    let &(_, shape, scene, f, s, free) = configs::KERNELS
        .iter()
        .find(|k| k.0 == name)
        .unwrap_or_else(|| panic!("no kernel set `{name}`"));
    let model = KernelConfig::new(name, shape)
        .scene_dim(scene)
        .formalism(f.parse::<Formalism>().unwrap())
        .stiffening(s.parse::<Stiffening>().unwrap())
        .free_frame(free)
        .model(std::path::Path::new("."))
        .unwrap();
    generate_kernels(&model).unwrap()
}

/// An aluminium beam, 2.5 m, a 20 × 15 mm section.
pub fn params() -> Params {
    let (wy, wz): (f64, f64) = (0.02, 0.015);
    Params {
        length: 2.5,
        rho: 2700.0,
        area: wy * wz,
        iy: wy * wz.powi(3) / 12.0,
        iz: wz * wy.powi(3) / 12.0,
        e: 7e10,
        g: 2.6e10,
        j: 1.2e-8,
    }
}

/// SplitMix64 values in `[-s, s)`.
pub fn random(n: usize, seed: u64, s: f64) -> Vec<f64> {
    let mut state = seed;
    (0..n)
        .map(|_| {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            s * ((z >> 11) as f64 / (1u64 << 52) as f64 - 1.0)
        })
        .collect()
}
