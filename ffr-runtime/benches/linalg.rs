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
//! `cargo bench -p ffr-runtime --bench linalg` (criterion), or
//! `FFR_LINALG_MIN=300 cargo bench -p ffr-runtime --bench linalg` for the
//! minimum and median time per call (robust on a loaded machine).

use std::time::{Duration, Instant};

use criterion::{black_box, criterion_group, BenchmarkId, Criterion, Throughput};
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

const SIZES: [usize; 4] = [24, 96, 384, 1536];

/// `(kind, bw, pivoting)` of the benchmarked cases.
fn cases() -> impl Iterator<Item = (&'static str, usize, bool)> {
    [false, true].into_iter().flat_map(|pivoting| {
        let kind = if pivoting { "pivoting" } else { "dominant" };
        [5, 11].into_iter().map(move |bw| (kind, bw, pivoting))
    })
}

/// Time of one `factor` on a fresh copy of `sys` (the copy, from the
/// assembled original so that the matrix is in cache as after assembly, is
/// not timed).
fn time_factor(sys: &BorderedSystem, work: &mut BorderedSystem) -> Duration {
    work.clone_from(sys);
    let t = Instant::now();
    black_box(&mut *work).factor().unwrap();
    t.elapsed()
}

/// Time of one `solve` of a fresh copy of `rhs` (the copy is not timed).
fn time_solve(sys: &BorderedSystem, rhs: &[f64], xb: &mut [f64], xk: &mut [f64]) -> Duration {
    let n = xb.len();
    xb.copy_from_slice(&rhs[..n]);
    xk.copy_from_slice(&rhs[n..]);
    let t = Instant::now();
    sys.solve(black_box(xb), black_box(xk));
    t.elapsed()
}

fn bench(c: &mut Criterion) {
    for (kind, bw, pivoting) in cases() {
        let mut group = c.benchmark_group(format!("linalg/{kind}/bw{bw}"));
        for n in SIZES {
            let sys = system(n, bw, pivoting);
            group.throughput(Throughput::Elements(n as u64));
            group.bench_with_input(BenchmarkId::new("factor", n), &sys, |b, sys| {
                let mut work = sys.clone();
                b.iter_custom(|iters| (0..iters).map(|_| time_factor(sys, &mut work)).sum())
            });
            let mut factored = sys.clone();
            factored.factor().unwrap();
            let rhs: Vec<f64> = (0..n + K).map(|i| (i as f64).sin()).collect();
            group.bench_with_input(BenchmarkId::new("solve", n), &factored, |b, sys| {
                let (mut xb, mut xk) = (vec![0.0; n], vec![0.0; K]);
                b.iter_custom(|iters| {
                    (0..iters)
                        .map(|_| time_solve(sys, &rhs, &mut xb, &mut xk))
                        .sum()
                })
            });
        }
        group.finish();
    }
}

/// `FFR_LINALG_MIN=reps`: instead of criterion, time every call alone and
/// print the minimum and median per call (`reps · 1536 / n` calls per size),
/// the ratios of the minima between successive sizes and the time per band
/// row. The per-call minimum is robust to a loaded machine, where
/// criterion's per-sample means are not.
fn per_call(reps: usize) {
    let us = |d: Duration| d.as_secs_f64() * 1e6;
    for (kind, bw, pivoting) in cases() {
        let mut rows = [(Vec::new(), Vec::new()), (Vec::new(), Vec::new())];
        for n in SIZES {
            let sys = system(n, bw, pivoting);
            let mut work = sys.clone();
            let calls = reps * 1536 / n;
            let mut tf: Vec<f64> = (0..calls)
                .map(|_| us(time_factor(&sys, &mut work)))
                .collect();
            let rhs: Vec<f64> = (0..n + K).map(|i| (i as f64).sin()).collect();
            let (mut xb, mut xk) = (vec![0.0; n], vec![0.0; K]);
            let mut ts: Vec<f64> = (0..calls)
                .map(|_| us(time_solve(&work, &rhs, &mut xb, &mut xk)))
                .collect();
            for (t, row) in [&mut tf, &mut ts].into_iter().zip(rows.iter_mut()) {
                t.sort_by(f64::total_cmp);
                row.0.push(t[0]);
                row.1.push(t[t.len() / 2]);
            }
        }
        for (op, (min, med)) in ["factor", "solve"].iter().zip(&rows) {
            let fmt = |v: &[f64]| v.iter().map(|x| format!("{x:8.2}")).collect::<String>();
            let ratios: String = min
                .windows(2)
                .map(|w| format!(" {:.2}", w[1] / w[0]))
                .collect();
            let per_row: String = min
                .iter()
                .zip(SIZES)
                .map(|(t, n)| format!(" {:.0}", t * 1e3 / n as f64))
                .collect();
            println!(
                "{kind} bw{bw:<2} {op:6} min µs{} | median µs{} | ratios{ratios} | ns/row{per_row}",
                fmt(min),
                fmt(med)
            );
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

fn main() {
    match std::env::var("FFR_LINALG_MIN") {
        Ok(reps) => per_call(reps.parse().expect("FFR_LINALG_MIN=number of repetitions")),
        Err(_) => {
            benches();
            Criterion::default().configure_from_args().final_summary();
        }
    }
}
