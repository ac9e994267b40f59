//! Cost of the bordered block-banded solver against the block size: one band
//! block of order n = 24, 96, 384, 1536 with half-bandwidths kl = ku = 5 or
//! 11, coupled to a border of k = 6 unknowns (m = 6), both for a diagonally
//! dominant block (no row interchanges) and for one whose diagonal is small
//! (interchanges at most steps, fill-in up to kl + ku superdiagonals).
//! `factor` is timed on a fresh copy of the assembled system, `solve` on a
//! fresh copy of the right-hand side (the copies are not timed: each call is
//! timed alone with `Instant`, about 25 ns of overhead). Both should grow
//! linearly in n (see the per-element throughput).
//!
//! `cargo bench -p ffr-runtime --bench linalg`

use std::time::{Duration, Instant};

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ffr_runtime::linalg::{BlockShape, BorderedSystem};

const K: usize = 6;

/// SplitMix64 in [-1, 1).
fn rand(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

fn system(n: usize, bw: usize, pivoting: bool) -> BorderedSystem {
    let shape = BlockShape {
        n,
        kl: bw,
        ku: bw,
        border: (0..K).collect(),
    };
    let mut sys = BorderedSystem::new(&[shape], K);
    let mut s = 42u64;
    let band = sys.band_mut(0);
    for j in 0..n {
        for i in j.saturating_sub(bw)..(j + bw + 1).min(n) {
            let v = if i != j {
                rand(&mut s)
            } else if pivoting {
                0.1 * rand(&mut s)
            } else {
                2.0 * bw as f64 + 1.0
            };
            band.add(i, j, v);
        }
    }
    for l in 0..K {
        for r in 0..n {
            sys.c_mut(0).add(r, l, rand(&mut s));
            sys.e_mut(0).add(l, r, rand(&mut s));
        }
    }
    for g in 0..K {
        sys.d_mut().add(g, g, 10.0 * n as f64);
    }
    sys
}

fn bench(c: &mut Criterion) {
    for pivoting in [false, true] {
        for bw in [5, 11] {
            let kind = if pivoting { "pivoting" } else { "dominant" };
            let mut group = c.benchmark_group(format!("linalg/{kind}/bw{bw}"));
            for n in [24, 96, 384, 1536] {
                let sys = system(n, bw, pivoting);
                group.throughput(Throughput::Elements(n as u64));
                group.bench_with_input(BenchmarkId::new("factor", n), &sys, |b, sys| {
                    // Only `factor` is timed; the copy before it (from the
                    // assembled original, so the matrix is in cache as after
                    // assembly) is not.
                    let mut work = sys.clone();
                    b.iter_custom(|iters| {
                        let mut total = Duration::ZERO;
                        for _ in 0..iters {
                            work.clone_from(sys);
                            let t = Instant::now();
                            black_box(&mut work).factor().unwrap();
                            total += t.elapsed();
                        }
                        total
                    })
                });
                let mut factored = sys.clone();
                factored.factor().unwrap();
                let rhs: Vec<f64> = (0..n + K).map(|i| (i as f64).sin()).collect();
                group.bench_with_input(BenchmarkId::new("solve", n), &factored, |b, sys| {
                    let (mut xb, mut xk) = (vec![0.0; n], vec![0.0; K]);
                    b.iter_custom(|iters| {
                        let mut total = Duration::ZERO;
                        for _ in 0..iters {
                            xb.copy_from_slice(&rhs[..n]);
                            xk.copy_from_slice(&rhs[n..]);
                            let t = Instant::now();
                            sys.solve(black_box(&mut xb), black_box(&mut xk));
                            total += t.elapsed();
                        }
                        total
                    })
                });
            }
            group.finish();
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
