pub mod spin_up;
