//! No heap allocation in `Simulation::step` (and reading the outputs)
//! after a warm-up: a counting global allocator over 100 steps of the
//! spin-up and of the flexible two-link arm.

use ffr::scene::Simulation;
use std::alloc::{GlobalAlloc, Layout, System as Sys};
use std::cell::Cell;
use std::path::Path;
use std::sync::Arc;

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

#[test]
fn simulation_steps_allocate_nothing() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for name in ["spin_up.toml", "two_link_arm.toml"] {
        let scene = Arc::new(ffr::scene::load(&dir.join(name)).unwrap());
        let mut sim = Simulation::new(scene).unwrap();
        for _ in 0..20 {
            sim.step().unwrap();
        }
        let mut sum = 0.0;
        let before = count();
        for _ in 0..100 {
            sim.step().unwrap();
            sum += sim.outputs().iter().sum::<f64>();
        }
        let n = count() - before;
        assert!(sum.is_finite());
        assert_eq!(n, 0, "{name}: {n} allocations in 100 steps");
    }
}
