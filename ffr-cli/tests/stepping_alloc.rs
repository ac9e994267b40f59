//! No heap allocation in `Simulation::step` (and reading the outputs,
//! setting inputs by index) after a warm-up: a counting global allocator
//! over 100 steps of the spin-up and of the flexible two-link arm, also
//! with inputs (a drive-acceleration input set at every step, a torque
//! input from a profile table, a force input, a drive-acceleration input on
//! a constraint drive).

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
    let spin = std::fs::read_to_string(dir.join("spin_up.toml")).unwrap()
        + "\n[[inputs]]\nname = \"hub_acc\"\nkind = \"drive-acceleration\"\njoint = 1\n";
    let arm = std::fs::read_to_string(dir.join("two_link_arm.toml")).unwrap()
        + "\n[[inputs]]\nname = \"tau\"\nkind = \"torque\"\njoint = 3\nprofile = { table = [[0.0, 0.0], [0.2, 0.1]] }\n\n[[inputs]]\nname = \"push\"\nkind = \"force\"\nat = \"forearm@x=0.4\"\ndirection = [0.0, 1.0]\naxes = \"body\"\n";
    // A drive that stays a constraint row (the elbow's), perturbed by an
    // input: its driver reads the perturbation from the assembly.
    let elbow = std::fs::read_to_string(dir.join("two_link_arm.toml"))
        .unwrap()
        .replace(
            "a = \"upper@x=0.5\"\nb = \"forearm\"\n\n#",
            "a = \"upper@x=0.5\"\nb = \"forearm\"\ndrive = { angle = \"constant\", value = 0.0 }\n\n#",
        )
        + "\n[[inputs]]\nname = \"elbow_acc\"\nkind = \"drive-acceleration\"\njoint = 3\n";
    let texts = [
        ("spin_up.toml", None),
        ("two_link_arm.toml", None),
        ("spin_up + input", Some(spin)),
        ("two_link_arm + inputs", Some(arm)),
        ("two_link_arm + elbow drive input", Some(elbow)),
    ];
    for (name, text) in texts {
        let scene = match text {
            None => ffr::scene::load(&dir.join(name)).unwrap(),
            Some(t) => ffr::scene::from_str(&t, name, &dir, &ffr::scene::DefaultKernels).unwrap(),
        };
        let mut sim = Simulation::new(Arc::new(scene)).unwrap();
        let n_inputs = sim.input_names().len();
        for _ in 0..20 {
            sim.step().unwrap();
        }
        let mut sum = 0.0;
        let before = count();
        for k in 0..100 {
            if n_inputs > 0 {
                let last = n_inputs - 1;
                sim.set_input_at(last, 0.01 * (k % 5) as f64).unwrap();
            }
            sim.step().unwrap();
            sum += sim.outputs().iter().sum::<f64>();
        }
        let n = count() - before;
        assert!(sum.is_finite());
        assert_eq!(n, 0, "{name}: {n} allocations in 100 steps");
    }
}
