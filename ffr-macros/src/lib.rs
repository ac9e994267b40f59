//! The `#[flex_body]` attribute (see the `ffr` crate).
