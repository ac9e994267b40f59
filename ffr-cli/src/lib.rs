//! The `ffr` command line and what only it needs, on top of the `ffr`
//! library (nothing below imports this crate):
//!
//! - [`cli`]: the commands (`spin-up`, `run`, `emit`, `invariants`, `modes`,
//!   `export`, `report`, `stability`, `sweep`);
//! - [`benchmarks`]: the benchmark scenes written against the library's API
//!   (spin-up beam, pendulum, free-floating body, slider crank);
//! - [`report`]: `ffr report`, work-precision diagrams of the benchmarks;
//! - [`stability`]: `ffr stability`, stiff and extreme cases;
//! - [`sweep`]: `ffr sweep`, a scene over parameter axes, locally or on Dask;
//! - [`output`]: files and standard output written whole or not at all;
//! - [`clock`] and [`progress`]: CPU time of a run, a progress bar.

pub mod benchmarks;
pub mod cli;
pub mod clock;
pub mod output;
pub mod plot;
pub mod progress;
pub mod reference;
pub mod report;
pub mod stability;
pub mod sweep;

pub use ffr::{codegen, runtime};
