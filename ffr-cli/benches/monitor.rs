//! The divergence monitor's cost: whole scene runs (`ffr::scene::run`) of
//! the undriven built-in scenes, where every check is on (deformation,
//! restarts and the energy balance each step), against the same runs with
//! `Monitor::off()`, side by side.
//!
//! `cargo bench --bench monitor`

use criterion::{criterion_group, criterion_main, Criterion};
use ffr::runtime::Monitor;

fn runs(c: &mut Criterion) {
    let dir = ffr::scene::load::builtin_dir();
    for name in ["pendulum", "two_link_arm", "free_floating", "spin_up"] {
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        for (tag, monitor) in [
            ("monitor on", Monitor::default()),
            ("monitor off", Monitor::off()),
        ] {
            let mut scene =
                ffr::scene::load(&dir.join(format!("{name}.toml"))).expect("built-in scene");
            scene.system.set_monitor(monitor);
            group.bench_function(tag, |b| {
                b.iter(|| {
                    let r = ffr::scene::run(&scene).expect("runs");
                    assert!(r.failed.is_none());
                    r.steps
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, runs);
criterion_main!(benches);
