//! The generated modal body against the run-time equations: the KRB
//! spin-up beam on 16 elements reduced to 4 modes plus the static modes
//! (`attr::SpinUpBeam16`, 18 modes: 4 normal and 14 static, fourth-order
//! stiffening) as
//! `SpinUpBeam16Modal::body()` (its inertia equations through the
//! generated `SpinUpBeam16ModalKernels`) and as `ModalBody::new` of the
//! same constants (the run-time equations, `InertiaTerms`). Prints the
//! least wall time of `ROUNDS` alternating runs of a spin-up (ω_s = 4
//! rad/s, T = 15 s, 20 s simulated, dt = 0.01 s, generalized-α ρ∞ = 0.8: what
//! `ffr spin-up --elements 16 --modes 4` runs),
//! of one tangent and one mass evaluation (averaged over many calls), and
//! the largest difference of the two runs' tip deflections.
//!
//! `cargo run --release -p arm-crate --example modal_speed [ROUNDS]`

use arm_crate::attr::{SpinUpBeam16, SpinUpBeam16Kernels, SpinUpBeam16Modal};
use ffr::runtime::{
    Body, BodyForces, BodyMass, BodyState, BodyTangent, CompiledBody, Driver, GeneralizedAlpha,
    Integrator, KernelBody, ModalBody, Pose, System,
};
use std::hint::black_box;
use std::ops::ControlFlow;
use std::time::Instant;

/// The same reduced body with the run-time equations.
fn runtime_body() -> ModalBody {
    let full = KernelBody::new(
        SpinUpBeam16Kernels,
        SpinUpBeam16Modal::params(),
        <SpinUpBeam16 as CompiledBody>::ELEMENTS,
        <SpinUpBeam16 as CompiledBody>::REFERENCE,
    )
    .expect("the full body builds");
    let data = SpinUpBeam16Modal::CONSTS.data().expect("the constants");
    ModalBody::new(Box::new(full), data).expect("the modal body builds")
}

/// Wall time of the spin-up and the tip's transverse deflections.
fn spin_up(body: ModalBody) -> (f64, Vec<f64>) {
    let tip = body.point_shape(8.0).expect("the tip");
    let mut sys = System::planar();
    let b = sys
        .add_body("beam", body, Pose::identity(2))
        .expect("the body");
    sys.prescribe_rotation_about_z(b, Driver::spin_up(4.0, 15.0))
        .expect("the drive");
    let fo = sys.bodies()[0].f_offset();
    let mut y = Vec::with_capacity(2001);
    let integrator = Integrator::GeneralizedAlpha(GeneralizedAlpha::with_rho_inf(0.8));
    let start = Instant::now();
    sys.simulate(20.0, 0.01, &integrator, |v| {
        let q = &v.state.q;
        y.push(tip.entries.iter().map(|(d, s, _)| s[1] * q[fo + d]).sum());
        ControlFlow::Continue(())
    })
    .expect("the spin-up runs");
    (start.elapsed().as_secs_f64(), y)
}

/// Seconds per call of the tangent and of the mass blocks at a deformed,
/// moving state.
fn per_call(body: &ModalBody, calls: usize) -> (f64, f64) {
    let lay = body.layout();
    let (k, hb) = (lay.nf, lay.half_bandwidth);
    let wave = |a: f64, p: f64| -> Vec<f64> {
        (0..k)
            .map(|i| a * ((i as f64 + 1.0) * 0.7 + p).sin())
            .collect()
    };
    let (q, qd, qdd) = (wave(0.01, 0.0), wave(0.1, 1.0), wave(1.0, 2.0));
    let state = BodyState {
        q_f: &q,
        qd_f: &qd,
        qdd_f: &qdd,
        frame: [0.3, -0.2, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.9],
    };
    let mut w = body.work();
    let mut f = BodyForces::zeros(k);
    let mut t = BodyTangent::zeros(k, hb);
    let mut m = BodyMass::zeros(k, hb);
    let start = Instant::now();
    for _ in 0..calls {
        body.tangent(black_box(&state), 4e4, 2e2, true, &mut w, &mut f, &mut t);
        black_box(&t);
    }
    let tangent = start.elapsed().as_secs_f64() / calls as f64;
    let start = Instant::now();
    for _ in 0..calls {
        body.mass(black_box(&q), &mut w, &mut m);
        black_box(&m);
    }
    (tangent, start.elapsed().as_secs_f64() / calls as f64)
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5)
        .max(1);
    let generated = SpinUpBeam16Modal::body().expect("the generated modal body");
    assert!(generated.uses_generated_kernels());
    let runtime = runtime_body();
    assert!(!runtime.uses_generated_kernels());
    let least = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let (mut sim, mut tan, mut mass) = ([vec![], vec![]], [vec![], vec![]], [vec![], vec![]]);
    let mut tips = [Vec::new(), Vec::new()];
    for _ in 0..rounds {
        for (i, make) in [SpinUpBeam16Modal::body as fn() -> _, || Ok(runtime_body())]
            .iter()
            .enumerate()
        {
            let body = make().expect("the modal body");
            let (t, m) = per_call(&body, 20_000);
            tan[i].push(t);
            mass[i].push(m);
            let (s, y) = spin_up(body);
            sim[i].push(s);
            tips[i] = y;
        }
    }
    let diff = tips[0]
        .iter()
        .zip(&tips[1])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    let peak = tips[1].iter().fold(0.0f64, |m, y| m.max(y.abs()));
    println!(
        "SpinUpBeam16Modal: {} modes, least of {rounds} alternating rounds",
        SpinUpBeam16Modal::MODES
    );
    println!(
        "spin-up (20 s, 2000 steps): generated {:.4} s, run-time {:.4} s",
        least(&sim[0]),
        least(&sim[1])
    );
    println!(
        "tangent per call:        generated {:.2} µs, run-time {:.2} µs",
        least(&tan[0]) * 1e6,
        least(&tan[1]) * 1e6
    );
    println!(
        "mass per call:           generated {:.2} µs, run-time {:.2} µs",
        least(&mass[0]) * 1e6,
        least(&mass[1]) * 1e6
    );
    println!("tip deflections agree to {diff:.1e} m (peak {peak:.4} m)");
    // Not a valid comparison unless both runs moved and agree to round-off.
    if !(peak > 0.0 && peak.is_finite() && diff <= 1e-9 * peak) {
        eprintln!(
            "error: the generated and run-time modal bodies disagree ({diff:e} m, peak {peak:e} m)"
        );
        std::process::exit(1);
    }
}
