pub mod free_floating;
pub mod pendulum;
pub mod spin_up;
