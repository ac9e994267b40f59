// Shared by `build.rs` (which generates them) and the crate (which names
// them): the kernel sets and fixed-mesh bodies compiled into `ffr-bench`.
// Plain data so that both can `include!` it.

/// Element kernels: `(name, shape, scene dimension, formalism, stiffening,
/// free frame)`; the type is the CamelCase of the name.
pub const KERNELS: &[(&str, &str, usize, &str, &str, bool)] = &[
    ("beam2_planar_off", "beam2", 2, "consistent", "off", true),
    ("beam2_planar_second_order", "beam2", 2, "consistent", "second-order", true),
    ("beam2_planar_fourth_order", "beam2", 2, "consistent", "fourth-order", true),
    ("beam2_planar_lumped_fourth_order", "beam2", 2, "lumped", "fourth-order", true),
    ("beam2_spatial_fourth_order", "beam2", 3, "consistent", "fourth-order", true),
    ("beam3_spatial_off", "beam3", 3, "consistent", "off", true),
    ("beam3_spatial_second_order", "beam3", 3, "consistent", "second-order", true),
    ("beam3_spatial_fourth_order", "beam3", 3, "consistent", "fourth-order", true),
    ("beam3_prescribed_fourth_order", "beam3", 3, "consistent", "fourth-order", false),
];

/// Fixed-mesh bodies: `(name, shape, elements, reference, formalism,
/// stiffening)`, all free-frame kernels in the shape's own scene.
pub const BODIES: &[(&str, &str, usize, &str, &str, &str)] = &[
    ("arm8", "beam3", 8, "clamped", "consistent", "fourth-order"),
    ("arm32", "beam3", 32, "clamped", "consistent", "off"),
    ("bar4", "beam2", 4, "pinned", "lumped", "second-order"),
];
