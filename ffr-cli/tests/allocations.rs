//! No heap allocation inside a time step after set-up: a counting global
//! allocator records the allocations between consecutive observer calls
//! (the observer itself does not allocate).

mod common;
use ffr::runtime::{Body, GeneralizedAlpha, Integrator, Rk4Baumgarte, System};
use ffr_cli::benchmarks::spin_up::{self, SpinUp};
use std::alloc::{GlobalAlloc, Layout, System as Sys};
use std::cell::Cell;
use std::ops::ControlFlow;

struct Counting;

thread_local! {
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        Sys.alloc(l)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        Sys.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        COUNT.with(|c| c.set(c.get() + 1));
        Sys.realloc(p, l, n)
    }
}

#[global_allocator]
static A: Counting = Counting;

fn count() -> usize {
    COUNT.with(Cell::get)
}

/// Allocations per step after the first `warm` steps, for `steps` steps.
fn allocations<B: Body>(
    sys: &System<B>,
    dt: f64,
    steps: usize,
    integrator: Integrator,
) -> Vec<usize> {
    let mut last = 0;
    let mut per_step = Vec::with_capacity(steps + 1);
    sys.simulate(dt * steps as f64, dt, &integrator, |v| {
        let now = count();
        if v.step > 0 {
            per_step.push(now - last);
        }
        last = count();
        ControlFlow::Continue(())
    })
    .unwrap();
    per_step
}

#[test]
fn spin_up_steps_allocate_nothing() {
    for spatial in [false, true] {
        let mut cfg = SpinUp::new(4.0);
        cfg.spatial = spatial;
        let (sys, _) = spin_up::system(&cfg).unwrap();
        for integrator in [
            Integrator::GeneralizedAlpha(GeneralizedAlpha::default()),
            Integrator::Rk4(Rk4Baumgarte::default()),
        ] {
            let dt = if matches!(integrator, Integrator::Rk4(_)) {
                1e-4
            } else {
                0.01
            };
            let a = allocations(&sys, dt, 300, integrator);
            assert!(
                a.iter().all(|&n| n == 0),
                "spatial={spatial} {integrator:?}: {a:?}"
            );
        }
    }
}

#[test]
fn mechanism_steps_allocate_nothing() {
    let tip = ffr::runtime::spec::AttachedMass {
        x: 1.0,
        mass: 0.05,
        inertia: [[1e-5, 0.0, 0.0], [0.0, 1e-5, 0.0], [0.0, 0.0, 1e-5]],
    };
    for (dim, masses) in [(2, vec![]), (3, vec![]), (3, vec![tip])] {
        // The last: with a mass attached on the arm.
        let sys = common::mechanism_with_masses(dim, &masses);
        let a = allocations(
            &sys,
            1e-3,
            200,
            Integrator::GeneralizedAlpha(GeneralizedAlpha::default()),
        );
        assert!(
            a.iter().all(|&n| n == 0),
            "dim {dim}, {} masses: {a:?}",
            masses.len()
        );
    }
}

/// The 5-MW blade (`scenes/blade_5mw.toml`: 49 section stations, varying
/// kernels on tapes, a rigid hub with a fixed joint) steps without
/// allocating, during the spin-up.
#[test]
fn blade_with_sections_steps_allocate_nothing() {
    let path = ffr::scene::load::builtin_dir().join("blade_5mw.toml");
    let scene = ffr::scene::load(&path).unwrap();
    let a = allocations(&scene.system, scene.dt, 200, scene.integrator);
    assert!(a.iter().all(|&n| n == 0), "{a:?}");
}

/// Point forces scaled by a profile (a table looked up by binary search, a
/// harmonic drive profile, a follower force) and markers with their own
/// axes (`scenes/l_frame.toml` and forces added to it) step without
/// allocating, while the table's rows are passed.
#[test]
fn profiled_forces_and_turned_markers_step_allocate_nothing() {
    let dir = ffr::scene::load::builtin_dir();
    let rows: Vec<String> = (0..1000)
        .map(|i| format!("[{:?}, {:?}]", i as f64 * 2e-4, (i as f64 * 0.1).sin()))
        .collect();
    let text = format!(
        "{}\n[[forces]]\nkind = \"point\"\nat = {{ at = \"leg1@x=0.5\", axes = {{ angle = 0.4 }} }}\nforce = [0.0, 0.01]\naxes = \"body\"\nprofile = {{ table = [{}] }}\n\n[[forces]]\nkind = \"point\"\nat = \"leg2@x=0.3\"\nforce = [0.01, 0.0]\nprofile = {{ kind = \"harmonic\", amplitude = 1.0, frequency = 5.0 }}\n",
        std::fs::read_to_string(dir.join("l_frame.toml")).unwrap(),
        rows.join(", ")
    );
    let scene =
        ffr::scene::from_str(&text, "l_frame.toml", &dir, &ffr::scene::DefaultKernels).unwrap();
    let a = allocations(&scene.system, scene.dt, 300, scene.integrator);
    assert!(a.iter().all(|&n| n == 0), "{a:?}");
}
