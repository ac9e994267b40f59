//! Reading a scene run's outputs (shared by the scene-file tests).

use ffr::scene::{self, Scene, SceneRun};

/// Run `s` to its end; the run must not fail.
pub fn run(s: &Scene) -> SceneRun {
    let r = scene::run(s).unwrap();
    assert!(r.failed.is_none(), "{:?}", r.failed);
    r
}

/// The output column `name`.
pub fn col<'a>(r: &'a SceneRun, name: &str) -> &'a [f64] {
    let i = r.names.iter().position(|n| n == name).unwrap();
    &r.columns[i]
}

/// The last value of the output `name`.
pub fn last(r: &SceneRun, name: &str) -> f64 {
    *col(r, name).last().unwrap()
}

/// `(a − b) / |b|`.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b) / b.abs()
}
