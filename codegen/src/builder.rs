//! `build.rs` integration in the style of `prost-build` (to be written).
