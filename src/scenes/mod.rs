pub mod pendulum;
pub mod spin_up;
