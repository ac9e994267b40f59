//! FFR dynamics of flexible multibody systems (floating frame of reference,
//! Shabana's notation; see the project's theory sheet).

pub mod body;

pub use body::{CompiledBody, FlexBody, InertiaTerms, InvariantBody, Invariants, Params};
pub use nalgebra;
