//! The lumped formalism with nodal rotary inertia (`docs/theory.md` §7):
//! each node is a small rigid body carrying half of each adjacent element's
//! mass, the sections' rotary inertia and the HRZ rotational inertia of
//! bending, so lumped beams integrate in every scene.
//!
//! - Frequencies of a clamped Euler–Bernoulli beam (no section rotary
//!   inertia, `rho_iz = 0`) converge to the exact `(β_n L)² √(EI/ρA)/L²`
//!   from below, as `h²`.
//! - The KRB spin-up with lumped masses converges to the geometrically
//!   exact reference (Exudyn, `bench/reference/`) as `h²`.
//! - Planar and spatial lumped pendulums run with the energy conserved.

use ffr::runtime::spec::{Formalism, KernelOptions, Params, Reference};
use ffr::runtime::Body;
use ffr::scene::{self, DefaultKernels};
use ffr::BeamSpec;
use ffr_cli::benchmarks::pendulum;
use ffr_cli::benchmarks::spin_up::{self, SpinUp};
use std::path::Path;

/// The clamped frequencies (rad/s) of a uniform Euler–Bernoulli beam
/// (`EI = 168 N m²`, `ρA = 0.785 kg/m`, 1 m) of `n` lumped beam2 elements.
fn lumped_frequencies(n: usize, count: usize) -> Vec<f64> {
    let row = |x: f64| {
        format!("{{ x = {x:?}, mass = 0.785, ea = 2.1e7, ei_y = 0.0, ei_z = 168.0, gj = 0.0, rho_iy = 0.0, rho_iz = 0.0 }}")
    };
    let text = format!(
        "dimension = 2\nt_end = 1.0\ndt = 0.01\n\n[bodies.bar]\nshape = \"beam2\"\nformalism = \"lumped\"\nelements = {n}\nsections = [{}, {}]\n",
        row(0.0),
        row(1.0)
    );
    let s = scene::from_str(&text, "bar.toml", Path::new("."), &DefaultKernels)
        .unwrap_or_else(|e| panic!("{e}"));
    let f = &s.flex[0];
    let body = s.system.body(s.system.body_id("bar").unwrap());
    ffr::modal::ReducibleBody::of_scene_body(f, body.as_ref())
        .unwrap()
        .reduce(Some(count), &[], "count")
        .unwrap()
        .frequencies
}

#[test]
fn lumped_frequencies_converge_to_euler_bernoulli_from_below() {
    let beta = [
        1.875_104_068_711_961f64,
        4.694_091_132_974_175,
        7.854_757_438_237_613,
    ];
    let scale = (168.0f64 / 0.785).sqrt();
    let mut last: Option<Vec<f64>> = None;
    for n in [8, 16, 32, 64] {
        // The bending modes are the lowest (the axial one is far above).
        let w = lumped_frequencies(n, 3);
        let err: Vec<f64> = (0..3)
            .map(|i| {
                let exact = beta[i] * beta[i] * scale;
                (exact - w[i]) / exact
            })
            .collect();
        println!("{n} elements: relative errors (exact − lumped)/exact {err:?}");
        // From below: the lumped masses sit at the nodes, where the mode
        // shapes are largest on average.
        assert!(err.iter().all(|e| *e > 0.0), "{n}: {err:?}");
        if let Some(prev) = &last {
            for i in 0..3 {
                let rate = prev[i] / err[i];
                // h²: each halving divides the error by 4 (measured 3.9–4.0
                // for the first mode, 3.6–4.0 for the third).
                assert!(
                    (3.4..4.3).contains(&rate),
                    "{n}: mode {}: ratio {rate}",
                    i + 1
                );
            }
        }
        last = Some(err);
    }
    // At 64 elements: measured 1.27e-4, 4.9e-4, 8.8e-4.
    let fine = last.unwrap();
    assert!(fine[0] < 2e-4 && fine[2] < 1.5e-3, "{fine:?}");
}

#[test]
fn lumped_spin_up_converges_to_the_reference() {
    let reference = ffr_cli::reference::spin_up(4.0).expect("the 4 rad/s reference");
    let mut errors = Vec::new();
    for n in [4, 8, 16] {
        let mut cfg = SpinUp::new(4.0);
        cfg.elements = n;
        cfg.formalism = Formalism::Lumped;
        let r = spin_up::run(&cfg).unwrap();
        assert!(r.diverged.is_none());
        let (rel, _) = reference
            .error("tip_transverse", &r.t, &r.tip_transverse, 20.0)
            .unwrap();
        println!("{n} lumped elements: history error {rel:.3e}");
        errors.push(rel);
    }
    // h² (measured 6.1e-2, 1.5e-2, 3.8e-3; 9.9e-4 and 2.8e-4 at 32 and 64
    // with `ffr spin-up --formalism lumped`).
    for w in errors.windows(2) {
        let rate = w[0] / w[1];
        assert!((3.5..4.5).contains(&rate), "{errors:?}");
    }
    assert!(errors[2] < 5e-3, "{errors:?}");
}

fn lumped_bar(shape: &str) -> BeamSpec {
    BeamSpec {
        shape: shape.into(),
        elements: 4,
        reference: Reference::Clamped,
        options: KernelOptions::new().formalism(Formalism::Lumped),
        params: Params {
            length: 1.0,
            rho: 7850.0,
            area: 1e-4,
            iy: 8e-10,
            iz: 8e-10,
            e: 2.1e11,
            g: 8.1e10,
            j: 1.4e-8,
        },
        force_tape: false,
    }
}

/// The nodes' rotations have inertia (`J = D_yy + D_xx` about z: the
/// section's `ρ I_z l` and the HRZ `ρ A l³/39` of an inner node), and a
/// lumped pendulum swings with its energy kept, in the plane and in space.
#[test]
fn lumped_pendulums_run_with_their_energy() {
    for shape in ["beam2", "beam3"] {
        let spec = lumped_bar(shape);
        let body = spec.body().unwrap();
        let m_ff = body.invariants().m_ff;
        let rz = body
            .layout()
            .labels
            .iter()
            .position(|d| d == "rz_1")
            .unwrap();
        let p = spec.params;
        let l = 0.25;
        let want = p.rho * p.iz * l + p.rho * p.area * l.powi(3) / 39.0;
        assert!(
            (m_ff[(rz, rz)] - want).abs() < 1e-12 * want,
            "{shape}: {} vs {want}",
            m_ff[(rz, rz)]
        );
        let beam = if shape == "beam2" {
            pendulum::Beam::Beam2
        } else {
            pendulum::Beam::Beam3
        };
        let args = pendulum::PendulumArgs {
            beam,
            t_end: 0.5,
            formalism: Formalism::Lumped,
            ..pendulum::PendulumArgs::default()
        };
        let r = pendulum::run_with(&args, p, |_| std::ops::ControlFlow::Continue(())).unwrap();
        println!(
            "{shape}: {} steps, energy drift {:.3e} E_ref, max ‖Φ‖∞ {:.1e} m, lowest tip y {:.3} m",
            r.steps, r.energy_drift, r.max_phi, r.min_tip_y
        );
        assert_eq!(r.steps, 500);
        // Generalized-α with ρ∞ = 1 keeps the energy to its O(dt²) error.
        assert!(r.energy_drift < 1e-3, "{shape}: {}", r.energy_drift);
        assert!(r.min_tip_y < -0.5, "{shape}: the bar swung down");
    }
}
