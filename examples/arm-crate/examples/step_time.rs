//! Time per step of the compiled 5-MW blade scene (49 section stations, 16
//! beam3 elements with varying sections, fourth-order stiffening, a rigid
//! hub and a fixed joint) beside the compiled KRB spin-up beam (8 beam2
//! elements, uniform, the hub's motion prescribed), measured side by side:
//! the two runs alternate `ROUNDS` times and the medians are printed (wall
//! time of `ffr::scene::run`, steps of each scene's own `dt`).
//!
//! `cargo run --release -p arm-crate --example step_time [ROUNDS]`

use arm_crate::scenes::{BuiltinBlade5mwScene, BuiltinSpinUpScene};
use std::time::Instant;

fn per_step(scene: &ffr::scene::Scene) -> f64 {
    let start = Instant::now();
    let run = ffr::scene::run(scene).expect("the scene runs");
    let wall = start.elapsed().as_secs_f64();
    if let Some(f) = &run.failed {
        eprintln!("{}: {f:?}", scene.origin);
        std::process::exit(1);
    }
    wall / (run.t.len() - 1) as f64
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let blade = BuiltinBlade5mwScene::load().expect("the blade scene builds");
    let beam = BuiltinSpinUpScene::load().expect("the spin-up scene builds");
    let (mut b, mut k) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        b.push(per_step(&blade));
        k.push(per_step(&beam));
    }
    let (b, k) = (median(b), median(k));
    println!("5-MW blade (compiled scene): {:.1} µs per step", b * 1e6);
    println!("KRB beam (compiled scene):   {:.1} µs per step", k * 1e6);
    println!("ratio: {:.1}", b / k);
}
