//! The scene files shipped in `scenes/`: each runs, and each reproduces a
//! physical property or a published solution by an independent route.

mod common;
use common::outputs::{col, last, rel, run};
use ffr::scene::{self, Scene, SceneRun};
use ffr_cli::benchmarks::slider_crank::{
    beam_init, beam_rod, simulate_beam, BeamField, RodElastic, PUBLISHED, SIMEON_INIT, T_END,
};

fn load(name: &str) -> Scene {
    scene::load(&scene::load::builtin_dir().join(name)).unwrap()
}

/// `scenes/slider_crank.toml` is the library's slider-crank (8 beam2
/// elements, dt = 2.5e-5 s, ρ∞ = 0.9): its initial elastic state is the
/// benchmark's INIT projected onto the nodes (the same bits as
/// `beam_init(&SIMEON_INIT)`), and at t = 0.1 s it reproduces the published
/// solution as `tests/slider_crank.rs` does — φ₂ and x₃ within 2e-7, the
/// midpoint deflection 0.4 % + 0.13 % below the published q₁ (measured
/// −0.547 %) — and the library's numbers bit for bit (the same bodies,
/// joints and prescribed crank in the same order; the crank's inertia, 7.02e-4
/// in the file and `0.002727 − 0.36·0.075²` one ulp below in the library,
/// does not enter: the crank is fully prescribed).
#[test]
fn slider_crank_file_reproduces_the_published_solution() {
    let s = load("slider_crank.toml");
    // Initial elastic state: the INIT fields at the nodes, bit for bit.
    let rod = s.system.body_id("rod").unwrap();
    let e = s.system.body_entry(rod);
    let labels = beam_rod(8).body().unwrap();
    let labels = ffr::runtime::Body::layout(&labels).labels.clone();
    let RodElastic::Fields { q, qd } = beam_init(&SIMEON_INIT).elastic else {
        unreachable!()
    };
    let nodal = |f: &BeamField| f.nodal_coordinates(&labels, 0.3).unwrap();
    let (q0, v0) = s.system.initial_coords();
    let fo = e.f_offset();
    assert_eq!(&q0[fo..fo + e.nf], nodal(&q).as_slice());
    assert_eq!(&v0[fo..fo + e.nf], nodal(&qd).as_slice());

    let r = run(&s);
    assert!((r.t.last().unwrap() - T_END).abs() < 1e-9);
    let (mid, phi2, x3) = (
        last(&r, "mid_deflection"),
        last(&r, "rod_angle"),
        last(&r, "slider_x"),
    );
    println!(
        "file: mid {mid:.6e} ({:+.3} %), φ2 {phi2:.9} (Δ {:+.1e}), x3 {x3:.9} (Δ {:+.1e}), {} steps, {} Newton, {:.2} s",
        100.0 * rel(mid, PUBLISHED.q[0]),
        phi2 - PUBLISHED.phi2,
        x3 - PUBLISHED.x3,
        r.steps,
        r.newton_iterations,
        r.wall
    );
    assert!((phi2 - PUBLISHED.phi2).abs() < 2e-7, "φ2 {phi2}");
    assert!((x3 - PUBLISHED.x3).abs() < 2e-7, "x3 {x3}");
    assert!(
        (-1e-2..0.0).contains(&rel(mid, PUBLISHED.q[0])),
        "mid {mid:e}"
    );
    // The slider's velocity at the end against the published ẋ₃.
    let v3 = last(&r, "slider_v");
    assert!(rel(v3, PUBLISHED.x3_dot).abs() < 1e-4, "ẋ3 {v3}");

    // The library's run of the same model.
    let lib = simulate_beam(8, T_END, 2.5e-5).unwrap();
    let k = lib.t.len() - 1;
    let (lmid, lphi, lx) = (lib.mid_deflection[k], lib.rod_angle[k], lib.slider_x[k]);
    println!(
        "library: mid {lmid:.6e}, φ2 {lphi:.9}, x3 {lx:.9}; file − library: {:.1e}, {:.1e}, {:.1e}",
        mid - lmid,
        phi2 - lphi,
        x3 - lx
    );
    assert_eq!((mid, phi2, x3), (lmid, lphi, lx));
    assert_eq!(col(&r, "mid_deflection"), lib.mid_deflection.as_slice());
    // The file's joints: the prismatic slider keeps y = 0 and its angle.
    let last_q = &r.last.as_ref().unwrap().q;
    let o = s.system.offset(s.system.body_id("slider").unwrap());
    assert!(last_q[o + 1].abs() < 1e-14 && last_q[o + 2].abs() < 1e-14);
}

/// Load a built-in scene file's text with `edits` (`(from, to)` textual
/// replacements, each of which must apply).
fn load_edited(name: &str, edits: &[(&str, &str)]) -> Scene {
    let dir = scene::load::builtin_dir();
    let mut text = std::fs::read_to_string(dir.join(name)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{name}: no `{from}`");
        text = text.replace(from, to);
    }
    scene::from_str(&text, name, &dir, &scene::DefaultKernels).unwrap()
}

/// `K(k)`, the complete elliptic integral of the first kind, by the
/// arithmetic–geometric mean: `K = π / (2 AGM(1, √(1 − k²)))`.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The first time `x` crosses `level` going down (linear interpolation).
fn crossing(t: &[f64], x: &[f64], level: f64) -> f64 {
    let i = x
        .windows(2)
        .position(|w| w[0] > level && w[1] <= level)
        .unwrap();
    t[i] + (t[i + 1] - t[i]) * (x[i] - level) / (x[i] - x[i + 1])
}

/// `scenes/pendulum.toml`: the bar starts at rest on the x axis, so its
/// energy is 0; with ρ∞ = 1 and no damping the energy stays within the
/// integrator's O(dt²) error of 0 (measured max |E| / (m g L/2) = 1.228e-6,
/// the library pendulum's figure), and the bar reaches the vertical after a
/// quarter period of the rigid compound pendulum released from the
/// horizontal, `T/4 = K(sin 45°) / ω₀`, `ω₀² = (m g L/2)/(m L²/3) = 3g/(2L)`
/// (0.48333 s; measured crossing at 0.48330 s), where the potential energy
/// m g L/2 has become kinetic (measured to 8e-6 relative: the bending energy).
/// The bar's 1 mm bending and its section inertia are the difference.
#[test]
fn pendulum_file_conserves_energy_and_swings_with_the_compound_pendulum_period() {
    let s = load("pendulum.toml");
    let r = run(&s);
    assert_eq!(r.steps, 1000);
    let (m, g, l) = (2700.0 * 1e-4 * 1.0, 9.81, 1.0);
    let e_ref = m * g * l / 2.0;
    let e = col(&r, "energy");
    assert_eq!(e[0], 0.0);
    let drift = e.iter().fold(0.0f64, |a, x| a.max(x.abs())) / e_ref;
    // Potential energy at the start of the swing and kinetic at the bottom.
    let (kin, grav) = (col(&r, "kinetic"), col(&r, "gravity"));
    let bottom = grav
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap()
        .0;
    let t_quarter = elliptic_k(std::f64::consts::FRAC_1_SQRT_2) / (1.5 * g / l).sqrt();
    let t_cross = crossing(&r.t, col(&r, "angle"), -std::f64::consts::FRAC_PI_2);
    println!(
        "pendulum: max |E|/(mgL/2) {drift:.3e}; at the bottom (t = {:.4} s) V_g {:.6} J, T {:.6} J (m g L/2 = {e_ref:.6} J); vertical at {t_cross:.5} s, rigid T/4 = {t_quarter:.5} s",
        r.t[bottom], grav[bottom], kin[bottom]
    );
    assert!(drift < 5e-6, "{drift:e}");
    assert!(rel(-grav[bottom], e_ref).abs() < 1e-4, "{}", grav[bottom]);
    assert!(rel(kin[bottom], e_ref).abs() < 1e-4, "{}", kin[bottom]);
    assert!((t_cross - t_quarter).abs() < 2e-4, "{t_cross} {t_quarter}");
    // The tip swings through the bottom, the bar bends by about a millimetre.
    assert!(col(&r, "tip_y").iter().any(|&y| y < -0.99));
    let bend = col(&r, "tip_deflection")
        .iter()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    assert!((5e-4..5e-3).contains(&bend), "{bend:e}");
}

/// `scenes/free_floating.toml`: the bar's kinetic energy at the start is that
/// of the rigid bar, `½ m v_c² + ½ (m L²/12 + ρ I_z L) ω²` (the consistent
/// beam2 mass represents rigid motion exactly: measured −6.2e-16 relative);
/// the energy then stays within the O(dt²) error (measured 2.26e-6
/// relative); the midpoint, the centre of mass of the symmetrically
/// stretched bar, moves uniformly at 0.5 m/s along x (measured within
/// 1.1e-6 m and 1.3e-6 m/s), the bar turns at 2 rad/s (within 1.4e-6 rad).
#[test]
fn free_floating_file_keeps_its_energy_and_centre_of_mass_motion() {
    let s = load("free_floating.toml");
    let r = run(&s);
    let (rho, a, iz, l, w) = (1150.0, 1e-4, 1e-8 / 12.0, 1.0, 2.0);
    let m = rho * a * l;
    let (vx, vy) = (0.5, -1.0 + w * l / 2.0);
    let t0 = 0.5 * m * (vx * vx + vy * vy) + 0.5 * (m * l * l / 12.0 + rho * iz * l) * w * w;
    let e = col(&r, "energy");
    let k0 = col(&r, "kinetic")[0];
    let drift = e.iter().fold(0.0f64, |d, x| d.max((x - e[0]).abs())) / e[0];
    let mut worst = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (i, &t) in r.t.iter().enumerate() {
        worst.0 = worst.0.max((col(&r, "mid_x")[i] - (0.5 + 0.5 * t)).abs());
        worst.1 = worst.1.max(col(&r, "mid_y")[i].abs());
        worst.2 = worst.2.max((col(&r, "mid_vx")[i] - 0.5).abs());
        worst.3 = worst.3.max((col(&r, "angle")[i] - w * t).abs());
    }
    println!(
        "free floating: T(0) {k0:.15e} J vs rigid {t0:.15e} J ({:.1e}); energy drift {drift:.2e}; midpoint off uniform motion by {:.1e} m (x), {:.1e} m (y), {:.1e} m/s; angle off 2t by {:.1e} rad",
        rel(k0, t0), worst.0, worst.1, worst.2, worst.3
    );
    assert!(rel(k0, t0).abs() < 1e-14, "{k0} {t0}");
    assert_eq!(e[0], k0);
    assert!(drift < 1e-5, "{drift:e}");
    assert!(
        worst.0 < 1e-5 && worst.1 < 1e-5 && worst.2 < 1e-5 && worst.3 < 1e-5,
        "{worst:?}"
    );
    assert!((r.t.last().unwrap() - 2.0).abs() < 1e-12);
}

/// The largest `|E(t) − E(0) − W(t) + D(t)|` over a run, and `max |W|`.
fn energy_balance(r: &SceneRun) -> (f64, f64) {
    let (e, w, d) = (col(r, "energy"), col(r, "motor_work"), col(r, "dissipated"));
    let mut worst = 0.0f64;
    for i in 0..e.len() {
        worst = worst.max((e[i] - e[0] - w[i] + d[i]).abs());
    }
    (worst, w.iter().fold(0.0f64, |a, x| a.max(x.abs())))
}

/// `scenes/two_link_arm.toml`: the motor's work and what the dampers (the
/// elbow's rotational damper, the links' Rayleigh damping) take out account
/// for the change of the mechanical energy, `E(t) − E(0) = W(t) − D(t)`, to
/// the integrator's O(dt²) error (ρ∞ = 1: no numerical dissipation): measured
/// max |E − E(0) − W + D| = 3.36e-5 J at dt = 1e-3 s for max |W| = 0.553 J,
/// and 4.00 times less at dt = 5e-4 s. Without the dissipated part the
/// balance would miss by D (0.0258 J at the end). The elbow spring's energy is
/// `½ k φ²` of the elbow's angle output.
#[test]
fn two_link_arm_file_balances_motor_work_dissipation_and_energy() {
    let coarse = run(&load("two_link_arm.toml"));
    let fine = run(&load_edited(
        "two_link_arm.toml",
        &[("dt = 1e-3", "dt = 5e-4")],
    ));
    let (b1, w1) = energy_balance(&coarse);
    let (b2, _) = energy_balance(&fine);
    let d_end = *col(&coarse, "dissipated").last().unwrap();
    println!(
        "two-link arm: max |E − E0 − W + D| {b1:.3e} J (dt 1e-3), {b2:.3e} J (dt 5e-4), ratio {:.2}; max |W| {w1:.3} J, D(end) {d_end:.4} J; {} steps, {} Newton, {:.2} s",
        b1 / b2,
        coarse.steps,
        coarse.newton_iterations,
        coarse.wall
    );
    assert!(b1 < 2e-4 * w1, "{b1:e}");
    assert!((3.0..5.5).contains(&(b1 / b2)), "second order: {}", b1 / b2);
    assert!(d_end > 100.0 * b1, "the dampers matter: D = {d_end:e}");
    let d = col(&coarse, "dissipated");
    assert!(
        d.windows(2).all(|p| p[1] >= p[0]),
        "dissipation never negative"
    );
    // The elbow spring's energy is ½ k φ² of the elbow angle (k = 2 N m/rad).
    for (v, phi) in col(&coarse, "elbow_spring")
        .iter()
        .zip(col(&coarse, "elbow"))
    {
        assert!(
            (v - phi * phi).abs() <= 1e-12 * (phi * phi) + 1e-300,
            "{v:e} {phi:e}"
        );
    }
    // The arm moves: the motor swings it by about ±0.5 rad.
    let sh = col(&coarse, "shoulder");
    assert!(sh.iter().any(|&x| x > 0.4) && sh.iter().any(|&x| x < -0.4));
}

/// `ffr spin-up` (the library's spin-up job) and `ffr run scenes/spin_up.toml`
/// write the same CSV columns, bit for bit (the CSV numbers are the shortest
/// decimal forms that read back to the same doubles, so equal text is equal
/// bits): 2001 rows of `t, tip_axial, tip_transverse`.
#[test]
fn spin_up_file_and_spin_up_job_write_identical_columns() {
    let dir = std::env::temp_dir().join(format!("ffr-scene-files-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let ffr = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let path = |f: &str| dir.join(f).display().to_string();
    ffr(&[
        "spin-up",
        "--csv",
        &path("job.csv"),
        "--svg",
        &path("job.svg"),
    ]);
    let file = scene::load::builtin_dir().join("spin_up.toml");
    ffr(&[
        "run",
        &file.display().to_string(),
        "--csv",
        &path("file.csv"),
        "--svg",
        &path("file.svg"),
    ]);
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    let (job, file) = (read("job.csv"), read("file.csv"));
    assert_eq!(job.lines().next(), Some("t,tip_axial,tip_transverse"));
    assert_eq!(job.lines().count(), 2002);
    // The tip moves (no trivially equal zero columns): measured peak
    // transverse deflection −0.53294 m.
    let peak = job
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().parse::<f64>().unwrap())
        .fold(0.0f64, f64::min);
    println!(
        "spin-up: {} rows, peak tip transverse {peak:.5} m",
        job.lines().count() - 1
    );
    assert!(peak < -0.1, "{peak}");
    assert_eq!(job, file);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `ffr spin-up --modes 4` and `ffr run scenes/spin_up_modal.toml` (the same
/// modal body: 4 clamped modes plus static modes) write the same CSV text.
#[test]
fn modal_spin_up_file_and_job_write_identical_columns() {
    let dir = std::env::temp_dir().join(format!("ffr-scene-modal-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = |f: &str| dir.join(f).display().to_string();
    let ffr = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    let job = ffr(&[
        "spin-up",
        "--modes",
        "4",
        "--csv",
        &path("job.csv"),
        "--svg",
        &path("job.svg"),
    ]);
    assert!(job.contains("reduced to 14 modes"), "{job}");
    let file = scene::load::builtin_dir().join("spin_up_modal.toml");
    let run = ffr(&[
        "run",
        &file.display().to_string(),
        "--csv",
        &path("file.csv"),
        "--svg",
        &path("file.svg"),
    ]);
    assert!(run.contains("modal, 14 modes"), "{run}");
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    let (job, file) = (read("job.csv"), read("file.csv"));
    assert_eq!(job.lines().count(), 2002);
    let peak = job
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().parse::<f64>().unwrap())
        .fold(0.0f64, f64::min);
    assert!(peak < -0.5, "{peak}");
    assert_eq!(job, file);
    let _ = std::fs::remove_dir_all(&dir);
}
