//! The element kernels of the built-in shapes (`beam2`, `beam3`), compiled
//! by `build.rs` for every formalism and stiffening model, planar and
//! spatial scenes, a free frame and a prescribed frame at rest. The `ffr`
//! library uses them behind its feature `builtin-kernels`; shapes chosen at
//! run time run on tapes of the same programs instead.

use ffr_runtime::spec::{Formalism, Stiffening};

include!(concat!(env!("OUT_DIR"), "/builtin.rs"));

ffr_runtime::forward_element_kernels!([] BuiltinKernels, dispatch);

/// The compiled kernels of a built-in shape for these options, if there
/// are any: `free_frame` selects the general set, else the set specialized
/// for a prescribed frame with `ā ≡ 0`.
pub fn builtin(
    shape: &str,
    scene_dim: usize,
    free_frame: bool,
    formalism: Formalism,
    stiffening: Stiffening,
) -> Option<BuiltinKernels> {
    BUILTIN
        .iter()
        .find(|(s, d, free, f, st, _)| {
            *s == shape
                && *d == scene_dim
                && *free == free_frame
                && *f == formalism
                && *st == stiffening
        })
        .map(|e| e.5)
}
