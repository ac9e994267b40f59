pub mod free_floating;
pub mod pendulum;
pub mod slider_crank;
pub mod spin_up;
