//! Bodies generated at build time, for benchmarks and for checking that the
//! compiled code computes bit for bit what the generator's evaluator reports.
//! The generating call is in `build.rs`; every body is clamped, consistent.

/// beam3, 1 element.
pub mod beam3_n1 {
    include!(concat!(env!("OUT_DIR"), "/beam3n1.rs"));
}
/// beam3, 8 elements.
pub mod beam3_n8 {
    include!(concat!(env!("OUT_DIR"), "/beam3n8.rs"));
}
/// beam3, 32 elements.
pub mod beam3_n32 {
    include!(concat!(env!("OUT_DIR"), "/beam3n32.rs"));
}
/// beam2, 4 elements, with geometric stiffening.
pub mod beam2_n4 {
    include!(concat!(env!("OUT_DIR"), "/beam2n4.rs"));
}

pub use beam2_n4::Beam2N4;
pub use beam3_n1::Beam3N1;
pub use beam3_n32::Beam3N32;
pub use beam3_n8::Beam3N8;
