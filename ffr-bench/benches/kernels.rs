//! Time of one call of each element kernel, compiled (the generated Rust)
//! against a tape of the same program (`program::Tape`, the interpreter a
//! shape chosen at run time uses), for beam2 in a planar scene and beam3 in a
//! spatial scene, without and with (fourth-order) stiffening; and of the
//! assembled evaluation of a body of 8 and 32 elements
//! (`KernelBody::forces` and `KernelBody::tangent` with the reference rows:
//! gather, kernel, scatter over the elements).
//!
//! `cargo bench -p ffr-bench --bench kernels` (criterion), or
//! `FFR_KERNELS_MIN=200 cargo bench -p ffr-bench --bench kernels` for the
//! minimum and median time per call over 200 timed batches of calls (robust
//! on a loaded machine; a batch lasts about 0.2 ms).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, Criterion};
use ffr_bench::tape::TapeKernels;
use ffr_bench::{compiled, kernel_set, params, random};
use ffr_runtime::spec::Reference;
use ffr_runtime::{
    Body, BodyForces, BodyState, BodyTangent, ElementKernels, KernelBody, KernelInput, MassOut,
    ResidualOut, TangentOut,
};

const SETS: [&str; 4] = [
    "beam2_planar_off",
    "beam2_planar_fourth_order",
    "beam3_spatial_off",
    "beam3_spatial_fourth_order",
];
const BODY_SETS: [&str; 2] = ["beam2_planar_fourth_order", "beam3_spatial_fourth_order"];
const FUNCTIONS: [&str; 6] = [
    "mass",
    "residual",
    "tangent",
    "residual_elastic",
    "tangent_elastic",
    "energy",
];

/// Inputs and output buffers of one element.
struct Element {
    c: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    frame: [f64; 9],
    out: Vec<Vec<f64>>,
    small: [[f64; 3]; 3],
    scratch: Vec<f64>,
}

impl Element {
    fn new(k: &dyn ElementKernels, scratch: usize) -> Self {
        let n = k.info().n_local;
        let p = params();
        let l = p.length / 8.0;
        let mut c = vec![0.0; k.info().n_coefficients];
        k.coefficients(&p, l, &mut c);
        let r = random(9, 5, 1.0);
        Element {
            c,
            q: random(n, 1, 0.02 * l),
            qd: random(n, 2, 0.2 * l),
            qdd: random(n, 3, 2.0 * l),
            frame: std::array::from_fn(|i| r[i]),
            out: vec![
                vec![0.0; n * n],
                vec![0.0; 9 * n],
                vec![0.0; 6 * n],
                vec![0.0; 54],
                vec![0.0; n],
            ],
            small: [[0.0; 3]; 3],
            scratch: vec![0.0; scratch],
        }
    }

    fn call(&mut self, k: &dyn ElementKernels, f: &str) {
        let x = KernelInput {
            x0: 0.3,
            q: &self.q,
            qd: &self.qd,
            qdd: &self.qdd,
            frame: &self.frame,
        };
        let [a, b, c, d, e] = &mut self.out[..] else {
            unreachable!()
        };
        let [s0, s1, _] = &mut self.small;
        match f {
            "mass" => k.mass(
                &self.c,
                0.3,
                &self.q,
                &mut MassOut {
                    s_t: s0,
                    m_ee: a,
                    m_e_frame: &mut b[..6 * self.q.len()],
                    m_ref_e: c,
                    m_ref_frame: &mut d[..36],
                },
                &mut self.scratch,
            ),
            "residual" => k.residual(
                &self.c,
                &x,
                &mut ResidualOut {
                    f_r: s0,
                    f_th: s1,
                    f_e: e,
                },
                &mut self.scratch,
            ),
            "tangent" => k.tangent(
                &self.c,
                &x,
                4e6,
                2e3,
                &mut TangentOut {
                    f_r: s0,
                    f_th: s1,
                    f_e: e,
                    k_ee: a,
                    d_e_frame: b,
                    k_ref_e: c,
                    d_ref_frame: d,
                },
                &mut self.scratch,
            ),
            "residual_elastic" => k.residual_elastic(&self.c, &x, e, &mut self.scratch),
            "tangent_elastic" => k.tangent_elastic(&self.c, &x, 4e6, 2e3, e, a, &mut self.scratch),
            "energy" => {
                black_box(k.energy(&self.c, &self.q, &mut self.scratch));
            }
            other => unreachable!("{other}"),
        }
        black_box(&mut self.out);
    }
}

/// One body evaluation.
struct BodyCase<K> {
    body: KernelBody<K>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    frame: [f64; 9],
    work: ffr_runtime::BodyWork,
    forces: BodyForces,
    tangent: BodyTangent,
}

impl<K: ElementKernels> BodyCase<K> {
    fn new(kernels: K, elements: usize) -> Self {
        let body = KernelBody::new(kernels, params(), elements, Reference::Clamped).unwrap();
        let nf = body.layout().nf;
        let hb = body.layout().half_bandwidth;
        let l = params().length / elements as f64;
        let r = random(9, 5, 1.0);
        BodyCase {
            q: random(nf, 1, 0.02 * l),
            qd: random(nf, 2, 0.2 * l),
            qdd: random(nf, 3, 2.0 * l),
            frame: std::array::from_fn(|i| r[i]),
            work: body.work(),
            forces: BodyForces::zeros(nf),
            tangent: BodyTangent::zeros(nf, hb),
            body,
        }
    }

    fn call(&mut self, what: &str) {
        let s = BodyState {
            q_f: &self.q,
            qd_f: &self.qd,
            qdd_f: &self.qdd,
            frame: self.frame,
        };
        match what {
            "forces" => self.body.forces(&s, true, &mut self.work, &mut self.forces),
            "tangent" => self.body.tangent(
                &s,
                4e6,
                2e3,
                true,
                &mut self.work,
                &mut self.forces,
                &mut self.tangent,
            ),
            other => unreachable!("{other}"),
        }
        black_box(&mut self.forces);
        black_box(&mut self.tangent);
    }
}

/// Every case: a name and a closure making one call.
fn cases() -> Vec<(String, Box<dyn FnMut()>)> {
    let mut v: Vec<(String, Box<dyn FnMut()>)> = Vec::new();
    for set in SETS {
        let s = kernel_set(set);
        let tape = TapeKernels::from_set(&s);
        let scratch = tape.info().scratch;
        let comp: &'static dyn ElementKernels = Box::leak(compiled(set).unwrap());
        let tape: &'static TapeKernels = Box::leak(Box::new(tape));
        for f in FUNCTIONS {
            let mut e = Element::new(comp, 0);
            v.push((
                format!("kernel/{set}/{f}/compiled"),
                Box::new(move || e.call(comp, f)),
            ));
            let mut e = Element::new(tape, scratch);
            v.push((
                format!("kernel/{set}/{f}/tape"),
                Box::new(move || e.call(tape, f)),
            ));
        }
    }
    for set in BODY_SETS {
        let s = kernel_set(set);
        for n in [8, 32] {
            for what in ["forces", "tangent"] {
                let mut b = BodyCase::new(compiled(set).unwrap(), n);
                v.push((
                    format!("body/{set}/{n}/{what}/compiled"),
                    Box::new(move || b.call(what)),
                ));
                let mut b = BodyCase::new(TapeKernels::from_set(&s), n);
                v.push((
                    format!("body/{set}/{n}/{what}/tape"),
                    Box::new(move || b.call(what)),
                ));
            }
        }
    }
    v
}

fn bench(c: &mut Criterion) {
    for (name, mut f) in cases() {
        c.bench_function(&name, |b| b.iter(&mut f));
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = bench
}

/// Minimum and median time per call over `reps` batches of about 0.2 ms.
fn min_median(reps: usize) {
    println!("| case | calls/batch | min (ns/call) | median (ns/call) |");
    println!("|---|---|---|---|");
    for (name, mut f) in cases() {
        // Warm up (about 10 ms), then calibrate the batch.
        let t = Instant::now();
        while t.elapsed() < Duration::from_millis(10) {
            f();
        }
        let mut calls = 1usize;
        loop {
            let t = Instant::now();
            for _ in 0..calls {
                f();
            }
            if t.elapsed() > Duration::from_micros(200) || calls > 1 << 24 {
                break;
            }
            calls *= 2;
        }
        let mut times: Vec<f64> = (0..reps)
            .map(|_| {
                let t = Instant::now();
                for _ in 0..calls {
                    f();
                }
                t.elapsed().as_secs_f64() * 1e9 / calls as f64
            })
            .collect();
        times.sort_by(|a, b| a.partial_cmp(b).unwrap());
        println!(
            "| {name} | {calls} | {:.1} | {:.1} |",
            times[0],
            times[reps / 2]
        );
    }
}

fn main() {
    if let Some(reps) = std::env::var("FFR_KERNELS_MIN")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        min_median(reps.max(1));
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
