//! `ffr_runtime::linalg` allocates only in `new`: a counting global
//! allocator shows that `clear`, filling, `mul_vec`, `factor` (also a failing
//! one) and `solve` make no heap allocation.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use ffr_runtime::linalg::{BandMatrix, BlockShape, BorderedSystem, DenseLu};

/// Counts the allocations of the current thread while `COUNTING` is set
/// (per thread, so the test harness's own threads do not interfere).
struct Counting;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn note() {
    // `try_with`: the thread-locals may be gone while a thread shuts down.
    let _ = COUNTING.try_with(|c| {
        if c.get() {
            let _ = ALLOCATIONS.try_with(|a| a.set(a.get() + 1));
        }
    });
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        System.alloc(layout)
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        System.alloc_zeroed(layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        System.realloc(ptr, layout, new_size)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Number of allocations made by `f` on this thread.
fn allocations<R>(f: impl FnOnce() -> R) -> (usize, R) {
    ALLOCATIONS.with(|a| a.set(0));
    COUNTING.with(|c| c.set(true));
    let r = f();
    COUNTING.with(|c| c.set(false));
    (ALLOCATIONS.with(|a| a.get()), r)
}

fn fill(sys: &mut BorderedSystem, t: f64) {
    for i in 0..sys.n_blocks() {
        let n = sys.block_range(i).len();
        let (kl, ku) = (sys.band(i).kl(), sys.band(i).ku());
        let m = sys.border(i).len();
        let band = sys.band_mut(i);
        for j in 0..n {
            for r in j.saturating_sub(ku)..(j + kl + 1).min(n) {
                let v = if r == j {
                    40.0 + t
                } else {
                    ((r * 7 + j * 3) % 5) as f64 - 2.0
                };
                band.add(r, j, v);
            }
        }
        for l in 0..m {
            let mut c = sys.c_mut(i);
            for r in 0..n {
                c.add(r, l, 0.1 * ((r + l) % 3) as f64);
            }
            for (r, e) in sys.e_row_mut(i, l).iter_mut().enumerate() {
                *e = 0.1 * ((r * l) % 4) as f64 - 0.15;
            }
            sys.c_col_mut(i, l)[0] += 1.0;
            sys.e_mut(i).add(l, n - 1, 1.0);
        }
    }
    let k = sys.k();
    let mut d = sys.d_mut();
    for g in 0..k {
        d.add(g, g, 10.0 + t);
        d.add(g, (g + 1) % k, 1.0);
    }
}

#[test]
fn the_counter_counts() {
    let (count, v) = allocations(|| vec![1.0f64; 10]);
    assert!(count >= 1, "the counting allocator does not count");
    drop(v);
}

#[test]
fn bordered_system_allocates_only_in_new() {
    let shapes = [
        BlockShape {
            n: 96,
            kl: 11,
            ku: 11,
            border: vec![0, 1, 2, 3, 4, 5],
        },
        BlockShape {
            n: 24,
            kl: 5,
            ku: 3,
            border: vec![2, 7],
        },
        BlockShape {
            n: 1,
            kl: 0,
            ku: 0,
            border: vec![],
        },
    ];
    let mut sys = BorderedSystem::new(&shapes, 9);
    let (nb, k) = (sys.n_band(), sys.k());
    let mut xb = vec![0.0; nb];
    let mut xk = vec![0.0; k];
    let mut yb = vec![0.0; nb];
    let mut yk = vec![0.0; k];

    let (count, residual) = allocations(|| {
        let mut residual = 0.0f64;
        for step in 0..3 {
            let t = step as f64;
            sys.clear();
            fill(&mut sys, t);
            for (i, x) in xb.iter_mut().enumerate() {
                *x = (i as f64 * 0.1).sin();
            }
            for (i, x) in xk.iter_mut().enumerate() {
                *x = (i as f64).cos();
            }
            // b = A x, then solve A x' = b and compare.
            sys.mul_vec(&xb, &xk, &mut yb, &mut yk);
            assert_eq!(sys.border_local(1, 7), Some(1));
            sys.factor().unwrap();
            let report = sys.pivot_report();
            assert!(report.min_ratio > 0.0);
            sys.solve(&mut yb, &mut yk);
            for (i, y) in yb.iter().enumerate() {
                residual = residual.max((y - (i as f64 * 0.1).sin()).abs());
            }
            for (i, y) in yk.iter().enumerate() {
                residual = residual.max((y - (i as f64).cos()).abs());
            }
        }
        // A failing factorization allocates nothing either.
        sys.clear();
        let err = sys.factor().unwrap_err();
        assert_eq!(err.column, 0);
        residual
    });
    assert_eq!(count, 0, "allocations after new");
    assert!(residual < 1e-12, "solve error {residual:e}");
}

#[test]
fn band_and_dense_allocate_only_in_new() {
    let mut band = BandMatrix::new(200, 11, 11);
    let mut dense = DenseLu::new(50);
    let mut b = vec![1.0; 200 * 3];
    let mut y = vec![0.0; 200];
    let mut c = vec![1.0; 50 * 2];
    let (count, ()) = allocations(|| {
        for _ in 0..2 {
            band.clear();
            for j in 0..200usize {
                for i in j.saturating_sub(11)..(j + 12).min(200) {
                    band.add(i, j, if i == j { 0.0 } else { 1.0 + (i % 3) as f64 });
                }
            }
            band.mul_vec_add(&b[..200], &mut y);
            band.factor().unwrap();
            band.solve(&mut y);
            band.solve_many(&mut b, 3);
            dense.clear();
            for j in 0..50 {
                for i in 0..50 {
                    dense.set(i, j, if i == j { 100.0 } else { (i * j % 7) as f64 });
                }
            }
            dense.mul_vec_add(&c[..50], &mut y[..50]);
            dense.factor().unwrap();
            dense.solve_many(&mut c, 2);
            let _ = (band.pivot_info().growth(), dense.pivot_info().pivot_ratio());
        }
    });
    assert_eq!(count, 0, "allocations after new");
}
