//! Linear models (issue 20): the matrices from the generated tangents
//! against finite differences of the residual, eigenvalues against the
//! modal analysis, the Euler–Bernoulli values and a free response, the
//! constraint manifold (no spurious eigenvalues), the JSON shape, errors.

mod common;

use common::cli::ffr;
use ffr::runtime::linear::{
    eigenvalues, linearize, null_space_basis, InputLoad, LinearInput, LinearModel,
};
use ffr::runtime::nalgebra::{DMatrix, Vector3};
use ffr::runtime::{Assembly, Body, ForceAxes, ForceElement, Marker, State, System, TorqueLaw};
use ffr::scene::{from_str, DefaultKernels};
use std::ops::ControlFlow;
use std::path::Path;
use std::sync::Arc;

/// `M`, `C`, `K` over the free coordinates and `Φ_q` by central
/// differences of [`Assembly::residual`] (λ fixed): the oracle.
fn fd_parts<B: Body>(
    sys: &System<B>,
    s: &State,
    free: &[usize],
) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let mut asm = Assembly::new(sys).unwrap();
    let (n, m) = (asm.n, asm.m);
    let nu = free.len();
    let (mut mm, mut cc, mut kk) = (
        DMatrix::zeros(nu, nu),
        DMatrix::zeros(nu, nu),
        DMatrix::zeros(nu, nu),
    );
    let mut phi = DMatrix::zeros(m, nu);
    let (mut rp, mut rm) = (vec![0.0; n + m], vec![0.0; n + m]);
    for (j, &c) in free.iter().enumerate() {
        for which in 0..3 {
            let x = [&s.q, &s.v, &s.a][which][c];
            // The residual is quadratic in q̇ and linear in q̈: a central
            // difference is exact there for any step, and a large one keeps
            // the round-off of the stiff terms small.
            let h = if which == 0 { 1e-6 } else { 1e-2 } * (1.0 + x.abs());
            let mut st = [s.q.clone(), s.v.clone(), s.a.clone()];
            st[which][c] = x + h;
            asm.residual(s.t, &st[0], &st[1], &st[2], &s.lambda, &mut rp);
            st[which][c] = x - h;
            asm.residual(s.t, &st[0], &st[1], &st[2], &s.lambda, &mut rm);
            let target = [&mut kk, &mut cc, &mut mm];
            for (i, &r) in free.iter().enumerate() {
                target[which][(i, j)] = (rp[r] - rm[r]) / (2.0 * h);
            }
            if which == 0 {
                for k in 0..m {
                    phi[(k, j)] = (rp[n + k] - rm[n + k]) / (2.0 * h);
                }
            }
        }
    }
    (mm, cc, kk, phi)
}

/// The largest entry difference of `a` and `b`, relative to the largest
/// entry of its column (of either).
fn col_rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let mut worst = 0.0f64;
    for j in 0..a.ncols() {
        let scale = a.column(j).amax().max(b.column(j).amax());
        if scale == 0.0 {
            continue;
        }
        worst = worst.max((a.column(j) - b.column(j)).amax() / scale);
    }
    worst
}

/// `A` and `B` of the oracle: the finite-difference parts projected with
/// the model's basis `N`, and the inputs' generalized forces `q_in`.
fn fd_model(
    model: &LinearModel,
    mm: &DMatrix<f64>,
    cc: &DMatrix<f64>,
    kk: &DMatrix<f64>,
    q_in: &DMatrix<f64>,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = &model.basis;
    let nt = n.transpose();
    let mh = &nt * mm * n;
    let lu = mh.lu();
    let mk = lu.solve(&(&nt * kk * n)).unwrap();
    let mc = lu.solve(&(&nt * cc * n)).unwrap();
    let nz = n.ncols();
    let mut a = DMatrix::zeros(2 * nz, 2 * nz);
    for i in 0..nz {
        a[(i, nz + i)] = 1.0;
        for j in 0..nz {
            a[(nz + i, j)] = -mk[(i, j)];
            a[(nz + i, nz + j)] = -mc[(i, j)];
        }
    }
    let mb = lu.solve(&(&nt * q_in)).unwrap();
    let mut b = DMatrix::zeros(2 * nz, q_in.ncols());
    b.view_mut((nz, 0), (nz, q_in.ncols())).copy_from(&mb);
    (a, b)
}

/// The state of `sys` after `steps` steps of `dt` (velocities, drives and
/// reactions all non-zero).
fn state_after<B: Body>(sys: &System<B>, steps: usize, dt: f64) -> State {
    let integ = ffr::runtime::Integrator::GeneralizedAlpha(Default::default());
    sys.simulate(steps as f64 * dt, dt, &integ, |_| ControlFlow::Continue(()))
        .unwrap()
        .last
}

/// `A` and `B` of the mechanism (a flexible arm on a driven, PD-motored hub,
/// a rigid link in a revolute joint at its tip with a rotational
/// spring–damper, a spring–damper to the ground, point and follower
/// forces, gravity), planar and spatial, in motion: from the generated
/// tangents they equal the finite differences of the residual projected
/// the same way, to 1e-6 of each column's largest entry. The inputs are a
/// unit global force on the link and a unit torque in the tip joint; the
/// oracle's generalized forces are `F · ∂p/∂q` and `∂φ/∂q` by differences
/// of the marker kinematics.
#[test]
fn a_and_b_from_the_tangents_equal_finite_differences() {
    for dim in [2, 3] {
        let sys = common::mechanism(dim);
        let s = state_after(&sys, 20, 1e-3);
        let link = sys.body_id("link").unwrap();
        let arm = sys.body_id("arm").unwrap();
        let at = Marker::at(link, Vector3::new(0.2, 0.0, 0.0));
        let tip = sys.point(arm, 1.0).unwrap();
        let dir = Vector3::new(0.3, -0.8, if dim == 3 { 0.5 } else { 0.0 }).normalize();
        let inputs = [
            LinearInput {
                name: "f".into(),
                load: InputLoad::Force(Box::new(ForceElement::Point {
                    marker: at.clone(),
                    force: Arc::new(move |_| dir),
                    axes: ForceAxes::Global,
                })),
            },
            LinearInput {
                name: "tau".into(),
                load: InputLoad::Force(Box::new(ForceElement::Torque {
                    a: tip.clone(),
                    b: Marker::origin(link),
                    law: TorqueLaw::Torque(Arc::new(|_| 1.0)),
                })),
            },
        ];
        let model = linearize(&sys, &s, &inputs, &[]).unwrap();
        let free = model.parts.free.clone();
        let (mm, cc, kk, phi) = fd_parts(&sys, &s, &free);
        let em = col_rel(&model.parts.m, &mm);
        let ec = col_rel(&model.parts.c, &cc);
        let ek = col_rel(&model.parts.k, &kk);
        let ep = col_rel(&model.parts.phi_q, &phi);
        // The oracle's generalized forces.
        let mut q_in = DMatrix::zeros(free.len(), 2);
        let (mut kp, mut kt, mut ka) = (
            sys.marker_kin(&at),
            sys.marker_kin(&Marker::origin(link)),
            sys.marker_kin(&tip),
        );
        let angle = |q: &[f64],
                     ka: &mut ffr::runtime::marker::MarkerKin,
                     kt: &mut ffr::runtime::marker::MarkerKin| {
            ka.eval(&tip, q);
            kt.eval(&Marker::origin(link), q);
            let x = kt.axes[0];
            x.dot(&ka.axes[1]).atan2(x.dot(&ka.axes[0]))
        };
        for (j, &c) in free.iter().enumerate() {
            let h = 1e-6 * (1.0 + s.q[c].abs());
            let (mut qp, mut qm) = (s.q.clone(), s.q.clone());
            qp[c] += h;
            qm[c] -= h;
            kp.eval(&at, &qp);
            let pp = kp.pos;
            kp.eval(&at, &qm);
            q_in[(j, 0)] = dir.dot(&(pp - kp.pos)) / (2.0 * h);
            q_in[(j, 1)] =
                (angle(&qp, &mut ka, &mut kt) - angle(&qm, &mut ka, &mut kt)) / (2.0 * h);
        }
        let (a_fd, b_fd) = fd_model(&model, &mm, &cc, &kk, &q_in);
        let ea = col_rel(&model.a, &a_fd);
        let eb = col_rel(&model.b, &b_fd);
        let null = (&phi * &model.basis).amax();
        println!(
            "dim {dim}: {} states; M {em:.1e}, C {ec:.1e}, K {ek:.1e}, Φ_q {ep:.1e}, A {ea:.1e}, B {eb:.1e}, |Φ_q N| {null:.1e}",
            model.states.len()
        );
        assert!(
            model.parts.c.amax() > 0.0,
            "damping and gyroscopic terms present"
        );
        for (what, e) in [
            ("M", em),
            ("C", ec),
            ("K", ek),
            ("Φ_q", ep),
            ("A", ea),
            ("B", eb),
        ] {
            assert!(
                e < 1e-6,
                "dim {dim}: {what} differs from the differences by {e:e}"
            );
        }
        assert!(
            null < 1e-7,
            "the basis is not in the null space of Φ_q: {null:e}"
        );
    }
}

/// The spin-up beam (prescribed hub, fourth-order stiffening) while it
/// spins: the gyroscopic `C` and the stiffening, spin-softening `K` also
/// equal the differences.
#[test]
fn rotating_beam_tangents_equal_finite_differences() {
    let text = include_str!("../../scenes/spin_up.toml");
    let scene = from_str(text, "spin_up.toml", Path::new("scenes"), &DefaultKernels).unwrap();
    let s = state_after(&scene.system, 400, 0.02);
    let model = linearize(&scene.system, &s, &[], &[]).unwrap();
    let (mm, cc, kk, _) = fd_parts(&scene.system, &s, &model.parts.free);
    let (ek, ec, em) = (
        col_rel(&model.parts.k, &kk),
        col_rel(&model.parts.c, &cc),
        col_rel(&model.parts.m, &mm),
    );
    let (a_fd, _) = fd_model(
        &model,
        &mm,
        &cc,
        &kk,
        &DMatrix::zeros(model.parts.free.len(), 0),
    );
    let ea = col_rel(&model.a, &a_fd);
    println!(
        "spin-up at t = {}: M {em:.1e}, C {ec:.1e}, K {ek:.1e}, A {ea:.1e}",
        s.t
    );
    assert!(model.parts.c.amax() > 0.0, "gyroscopic coupling present");
    assert!(em < 1e-6 && ec < 1e-6 && ek < 1e-6 && ea < 1e-6);
}

/// A clamped uniform beam3 fixed to the ground, slender (radius of
/// gyration 1.4e-4 of its length: the rotary inertia of the elements' mass
/// changes the first frequency by about 1e-8).
fn cantilever(elements: usize) -> String {
    format!(
        r#"dimension = 3
t_end = 1.0
dt = 1e-3
[bodies.beam]
shape = "beam3"
elements = {elements}
reference = "clamped"
params = {{ length = 2.0, rho = 7800.0, area = 1e-4, iy = 8.0e-12, iz = 2.0e-11, e = 2.1e11, g = 8.0e10, j = 1.5e-11 }}
position = [0.0, 0.0, 0.0]
[[joints]]
kind = "ground"
b = "beam"
[[outputs]]
name = "tip_z"
kind = "deflection"
at = "beam@x=2.0"
component = "z"
"#
    )
}

/// The eigenvalues of a grounded cantilever at rest are `±i ω` with `ω`
/// the body's frequencies from `ffr modes` (the same exact `m_ff`, `K_ff`)
/// to 1e-9, and the Euler–Bernoulli values `(β_n L)² √(EI/(ρA L⁴))`
/// (`β₁L = 1.8751041`, `β₂L = 4.6940911`) in both bending planes at 16
/// elements to 1e-6 (mode 1, measured 8e-8) and 1e-5 (mode 2, 4.8e-6: the
/// mesh); no real part beyond round-off (1e-9 |λ|).
#[test]
fn cantilever_eigenvalues_equal_its_modes_and_euler_bernoulli() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cantilever.toml");
    std::fs::write(&path, cantilever(16)).unwrap();
    let p = path.to_str().unwrap();
    let (ok, out, err) = ffr(&["linearize", p, "--json"]);
    assert!(ok, "{err}");
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    let ev: Vec<(f64, f64)> = js["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| (e[0].as_f64().unwrap(), e[1].as_f64().unwrap()))
        .collect();
    let wmax = ev.iter().map(|e| e.1.abs()).fold(0.0, f64::max);
    assert!(ev.iter().all(|e| e.0.abs() < 1e-9 * wmax), "real parts");
    let omegas: Vec<f64> = ev.iter().filter(|e| e.1 > 0.0).map(|e| e.1).collect();
    let (ok, out, err) = ffr(&["modes", "--scene", p, "--body", "beam", "--json"]);
    assert!(ok, "{err}");
    let mj: serde_json::Value = serde_json::from_str(&out).unwrap();
    let modes: Vec<f64> = mj["omega"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(omegas.len(), modes.len());
    let worst = omegas
        .iter()
        .zip(&modes)
        .map(|(a, b)| (a - b).abs() / b)
        .fold(0.0, f64::max);
    println!("linearize vs modes: {worst:.2e} over {} modes", modes.len());
    assert!(worst < 1e-9, "{worst:e}");
    let (rho_a, l) = (7800.0 * 1e-4, 2.0f64);
    for (i_sec, first) in [(8.0e-12f64, 0), (2.0e-11, 2)] {
        let s = (2.1e11 * i_sec / (rho_a * l * l * l * l)).sqrt();
        for (k, bl) in [1.875_104_068_711_961_f64, 4.694_091_132_974_175]
            .iter()
            .enumerate()
        {
            let exact = bl * bl * s;
            // The k-th mode of this bending plane: the nearest frequency.
            let near = omegas
                .iter()
                .map(|w| (w - exact).abs() / exact)
                .fold(f64::INFINITY, f64::min);
            println!("I = {i_sec:e}, mode {}: {near:.2e}", k + 1);
            // The second mode carries the mesh's error (cubic elements: (βh)⁴/720).
            let tol = [1e-6, 1e-5][k];
            assert!(near < tol, "I = {i_sec}, mode {}: {near:e}", k + 1 + first);
        }
    }
}

/// The flexible pendulum hanging at rest (`--at static`): its states are
/// the independent coordinates on the revolute joint (13 = 16 − 3
/// coordinates; `x`, `y` are dependent), no eigenvalue is spuriously zero
/// or infinite, none has a positive real part beyond round-off, and the
/// lowest is the compound pendulum `√(3g/2L)` (to 1e-3: the bar bends a
/// little). A free swing of 0.002 rad about the same state (a time run)
/// has the same period, by zero crossings, to 1e-5.
#[test]
fn hanging_pendulum_has_the_physical_eigenvalues_and_its_free_period() {
    let (ok, out, err) = ffr(&[
        "linearize",
        "../scenes/pendulum.toml",
        "--at",
        "static",
        "--json",
    ]);
    assert!(ok, "{err}");
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    let states: Vec<&str> = js["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert_eq!(states.len(), 26);
    assert!(
        states.contains(&"bar.theta") && !states.contains(&"bar.x"),
        "{states:?}"
    );
    let ev: Vec<(f64, f64)> = js["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| (e[0].as_f64().unwrap(), e[1].as_f64().unwrap()))
        .collect();
    assert_eq!(ev.len(), 26);
    let mags: Vec<f64> = ev.iter().map(|e| e.0.hypot(e.1)).collect();
    let wmax = mags.iter().copied().fold(0.0, f64::max);
    assert!(mags.iter().all(|m| m.is_finite()));
    assert!(
        ev.iter().all(|e| e.0 < 1e-9 * wmax),
        "an unstable eigenvalue: {ev:?}"
    );
    let w0 = (1.5 * 9.81f64 / 1.0).sqrt();
    let w1 = mags[0];
    println!("lowest |λ| {w1} against the rigid compound pendulum {w0}");
    assert!((w1 - w0).abs() / w0 < 1e-3, "{w1} vs {w0}");
    assert!(
        mags.iter().all(|&m| m > 0.5 * w0),
        "a spurious small eigenvalue"
    );
    // The free swing about the hanging state: released at 0.002 rad with
    // the static deflection (so that the bending modes stay quiet); the
    // amplitude lengthens the period by θ₀²/16 = 2.5e-7 and the integrator
    // (ρ∞ = 1, dt = 1 ms) by (ω dt)²/12 = 1.2e-6.
    let text = include_str!("../../scenes/pendulum.toml");
    let sag = {
        let scene = from_str(text, "pendulum.toml", Path::new("scenes"), &DefaultKernels).unwrap();
        let st =
            ffr::scene::linear::operating_state(&scene, ffr::scene::linear::At::Static).unwrap();
        let e = &scene.system.bodies()[0];
        st.q[e.f_offset()..e.f_offset() + e.nf].to_vec()
    };
    let start = -std::f64::consts::FRAC_PI_2 + 0.002;
    let text = text
        .replace("angle = 0.0", &format!("angle = {start}"))
        .replace("t_end = 1.0", "t_end = 10.0");
    let mut scene = from_str(&text, "pendulum.toml", Path::new("scenes"), &DefaultKernels).unwrap();
    let bar = scene.system.body_id("bar").unwrap();
    scene
        .system
        .set_elastic(bar, &sag, &vec![0.0; sag.len()])
        .unwrap();
    let r = ffr::scene::run(&scene).unwrap();
    let i = r.names.iter().position(|n| n == "angle").unwrap();
    let y: Vec<f64> = r.columns[i]
        .iter()
        .map(|a| a + std::f64::consts::FRAC_PI_2)
        .collect();
    let mut ups = Vec::new();
    for k in 1..y.len() {
        if y[k - 1] < 0.0 && y[k] >= 0.0 {
            ups.push(r.t[k - 1] + (r.t[k] - r.t[k - 1]) * (-y[k - 1]) / (y[k] - y[k - 1]));
        }
    }
    assert!(ups.len() >= 3, "{ups:?}");
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    let w_run = std::f64::consts::TAU / period;
    println!("free swing: {w_run} rad/s against the eigenvalue {w1}");
    assert!((w_run - w1).abs() / w1 < 1e-5, "{w_run} vs {w1}");
}

/// `--json` has exactly the keys `states, inputs, outputs, A, B, C, D,
/// eigenvalues` with consistent dimensions; `--out` writes the four
/// Matrix Market files and the JSON.
#[test]
fn json_shape_and_matrix_market_files() {
    let scene = "../scenes/two_link_arm.toml";
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("lin");
    let (ok, out, err) = ffr(&[
        "linearize",
        scene,
        "--at",
        "0.01",
        "--json",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    let mut keys: Vec<&str> = js.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "A",
            "B",
            "C",
            "D",
            "eigenvalues",
            "inputs",
            "outputs",
            "states"
        ]
    );
    let len = |k: &str| js[k].as_array().unwrap().len();
    let (n, ni, no) = (len("states"), len("inputs"), len("outputs"));
    assert_eq!(js["inputs"][0], "joint1");
    assert_eq!(no, 5, "the energies are left out");
    let dims = |k: &str| {
        let rows = js[k].as_array().unwrap();
        (
            rows.len(),
            rows.first().map_or(0, |r| r.as_array().unwrap().len()),
        )
    };
    assert_eq!(dims("A"), (n, n));
    assert_eq!(dims("B"), (n, ni));
    assert_eq!(dims("C"), (no, n));
    assert_eq!(dims("D"), (no, ni));
    assert_eq!(len("eigenvalues"), n);
    assert!(js["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .all(|e| e.as_array().unwrap().len() == 2));
    for (f, (r, c)) in [
        ("A.mtx", (n, n)),
        ("B.mtx", (n, ni)),
        ("C.mtx", (no, n)),
        ("D.mtx", (no, ni)),
    ] {
        let text = std::fs::read_to_string(out_dir.join(f)).unwrap();
        assert!(text.starts_with("%%MatrixMarket matrix coordinate real general\n"));
        let size = text.lines().find(|l| !l.starts_with('%')).unwrap();
        let v: Vec<usize> = size.split(' ').map(|x| x.parse().unwrap()).collect();
        assert_eq!((v[0], v[1]), (r, c), "{f}");
        assert_eq!(
            text.lines().filter(|l| !l.starts_with('%')).count(),
            v[2] + 1,
            "{f}"
        );
        // The entries read back equal the JSON's.
        let key = &f[..1];
        for l in text.lines().filter(|l| !l.starts_with('%')).skip(1) {
            let p: Vec<&str> = l.split(' ').collect();
            let (i, j): (usize, usize) = (p[0].parse().unwrap(), p[1].parse().unwrap());
            let x: f64 = p[2].parse().unwrap();
            // serde_json's parser may miss the nearest f64 by an ulp.
            let y = js[key][i - 1][j - 1].as_f64().unwrap();
            assert!((x - y).abs() <= 4.0 * f64::EPSILON * x.abs(), "{x} {y}");
        }
    }
    let mut back: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("linear.json")).unwrap())
            .unwrap();
    // The file is the JSON object with ffr's mark as its first key.
    assert_eq!(
        back.as_object_mut().unwrap().remove("written_by"),
        Some(serde_json::Value::from("ffr linearize"))
    );
    assert_eq!(back, js);
    // The text summary ends with the stiffest mode and the RK4 step it allows.
    let (ok, out, err) = ffr(&["linearize", scene]);
    assert!(ok, "{err}");
    let wmax = js["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e[0].as_f64().unwrap().hypot(e[1].as_f64().unwrap()))
        .fold(0.0, f64::max);
    let dt = 2.0 * std::f64::consts::SQRT_2 / wmax;
    assert!(out.contains(&format!("2√2/|λ| = {dt:.3e} s")), "{out}");
    // `--inputs ''` and `--outputs ''`: none.
    let (ok, out, err) = ffr(&[
        "linearize",
        scene,
        "--inputs",
        "",
        "--outputs",
        "",
        "--json",
    ]);
    assert!(ok, "{err}");
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(js["inputs"], serde_json::json!([]));
    assert_eq!(js["outputs"], serde_json::json!([]));
    assert_eq!(js["states"].as_array().unwrap().len(), n);
}

/// Bad requests: a clear message naming the problem, a non-zero exit, no
/// panic.
#[test]
fn bad_requests_are_refused_with_a_message() {
    let scene = "../scenes/two_link_arm.toml";
    for (args, says) in [
        (vec!["--at", "soon"], "--at `soon`"),
        (vec!["--at=-1"], "--at `-1`"),
        (vec!["--inputs", "joint9"], "input `joint9`"),
        (vec!["--inputs", "joint2"], "input `joint2`"),
        (vec!["--inputs", "motor"], "unknown input `motor`"),
        (vec!["--inputs", "drive2"], "input `drive2`: joint 2"),
        (vec!["--outputs", "energy"], "output `energy` is an energy"),
        (vec!["--outputs", "nothing"], "unknown output `nothing`"),
    ] {
        let mut a = vec!["linearize", scene];
        a.extend(args.iter());
        let (ok, _, err) = ffr(&a);
        assert!(!ok, "{a:?}");
        assert!(err.contains(says), "{a:?}: {err}");
    }
    let (ok, _, err) = ffr(&["campbell", scene, "--speeds", "0,1"]);
    assert!(!ok && err.contains("drive"), "{err}");
    let (ok, _, err) = ffr(&[
        "campbell",
        "../scenes/spin_up.toml",
        "--speeds",
        "0",
        "--joint",
        "0",
    ]);
    assert!(!ok && err.contains("--joint 0"), "{err}");
}

/// The null-space basis of a constraint Jacobian: `Φ_q N = 0`, identity on
/// the independent coordinates, and redundant rows do not reduce it.
#[test]
fn null_space_basis_by_coordinate_partitioning() {
    let phi = DMatrix::from_row_slice(
        3,
        5,
        &[
            1.0, 0.0, 2.0, 0.0, 1.0, //
            0.0, 1.0, -1.0, 0.0, 0.5, //
            1.0, 1.0, 1.0, 0.0, 1.5, // the sum of the first two
        ],
    );
    let (n, ind) = null_space_basis(&phi);
    assert_eq!(n.shape(), (5, 3));
    assert!((&phi * &n).amax() < 1e-14);
    for (j, &c) in ind.iter().enumerate() {
        for (k, &d) in ind.iter().enumerate() {
            assert_eq!(n[(c, k)], if j == k { 1.0 } else { 0.0 }, "{d}");
        }
    }
    assert!(
        ind.contains(&3),
        "a coordinate no row touches is independent"
    );
    let ev = eigenvalues(&DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -4.0, 0.0])).unwrap();
    assert_eq!(ev.len(), 2);
    assert!(ev[0].im < 0.0 && ev[1].im > 0.0 && (ev[1].im - 2.0).abs() < 1e-14);
}

/// A drive input (`drive1`: the acceleration of the spin-up beam's hub
/// drive, which the linear model unfolds into a driving constraint): the
/// linear model's response to the spin-up profile's acceleration
/// `f̈ = (ω_s/T)(1 − cos 2πt/T)` (exact discretization, `exp` of the
/// augmented matrix, the input at mid-step) equals the nonlinear run of the
/// scene (prescribed hub, ω_s = 0.01 rad/s so that the centrifugal terms
/// are 1e-5 of the inertial ones) in the transverse tip deflection over
/// 0–10 s, to 1e-5 of its peak (measured 1.4e-6).
#[test]
fn drive_input_response_equals_the_time_run() {
    let text = include_str!("../../scenes/spin_up.toml")
        .replace("omega = 4.0", "omega = 0.01")
        .replace("t_end = 20.0", "t_end = 10.0")
        .replace("dt = 0.01", "dt = 1e-3");
    let spec = ffr::codegen::scene::resolve_str(&text, "spin_up.toml", Path::new(".")).unwrap();
    let model = ffr::scene::linear::linearize_scene(
        &spec,
        &DefaultKernels,
        ffr::scene::linear::At::Time(0.0),
        Some(&["drive1".to_string()]),
        Some(&["tip_transverse".to_string()]),
    )
    .unwrap();
    let n = model.a.nrows();
    assert_eq!(model.states[n / 2 - 1], "drive1");
    // Exact discretization: exp([[A, B], [0, 0]] h) = [[Φ, Γ], [0, I]].
    let h = 1e-3;
    let mut aug = DMatrix::zeros(n + 1, n + 1);
    aug.view_mut((0, 0), (n, n)).copy_from(&(&model.a * h));
    aug.view_mut((0, n), (n, 1)).copy_from(&(&model.b * h));
    let e = aug.exp();
    let phi = e.view((0, 0), (n, n)).into_owned();
    let gamma = e.view((0, n), (n, 1)).into_owned();
    let (ws, tr) = (0.01, 15.0);
    let u = |t: f64| ws / tr * (1.0 - (std::f64::consts::TAU * t / tr).cos());
    let scene = from_str(&text, "spin_up.toml", Path::new("."), &DefaultKernels).unwrap();
    let r = ffr::scene::run(&scene).unwrap();
    let col = &r.columns[r.names.iter().position(|c| c == "tip_transverse").unwrap()];
    let mut x = ffr::runtime::nalgebra::DVector::zeros(n);
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    for (k, &t) in r.t.iter().enumerate() {
        if k > 0 {
            let tm = 0.5 * (t + r.t[k - 1]);
            x = &phi * &x + &gamma * u(tm);
        }
        let y = (&model.c * &x)[0];
        worst = worst.max((y - col[k]).abs());
        peak = peak.max(col[k].abs());
    }
    println!("drive input: worst {worst:.3e} m against the run's peak {peak:.3e} m");
    assert!(peak > 0.0 && worst < 1e-5 * peak, "{worst:e} vs {peak:e}");
}

/// The pendulum with a constant torque `τ` at its pin, released
/// horizontal: below `m g L/2` the static solver (`ffr static`'s, which
/// keeps to stable equilibria) finds the equilibrium below the horizontal,
/// `cos θ = τ/(m g L/2)`, whose lowest pair is `±i ω` with the compound
/// pendulum's `ω² = (3g/2L) sin|θ|` (the bar's flexibility lowers it by
/// 3.9e-5 relative; 2e-4 asserted); above it there is none, and `--at
/// static` says so and exits non-zero.
#[test]
fn static_equilibrium_stable_or_missing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pt.toml");
    let base = include_str!("../../scenes/pendulum.toml");
    let with = |tau: f64| {
        format!("{base}\n[[forces]]\nkind = \"torque\"\na = \"ground@[0.0, 0.0]\"\nb = \"bar\"\ntorque = {tau:?}\n")
    };
    std::fs::write(&path, with(0.5)).unwrap();
    let p = path.to_str().unwrap();
    let (ok, out, err) = ffr(&["linearize", p, "--at", "static", "--json"]);
    assert!(ok, "{err}");
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(js["inputs"], serde_json::json!(["force1"]));
    let ev = js["eigenvalues"].as_array().unwrap();
    let (re, im) = (ev[0][0].as_f64().unwrap(), ev[0][1].as_f64().unwrap());
    let (re1, im1) = (ev[1][0].as_f64().unwrap(), ev[1][1].as_f64().unwrap());
    // m g L/2 = 2700 · 1e-4 · 9.81 · 0.5 = 1.32 N m > 0.5 N m.
    let c = 0.5 / (2700.0 * 1e-4 * 9.81 * 0.5);
    let w = (1.5 * 9.81 * (1.0f64 - c * c).sqrt()).sqrt();
    println!("lowest pair: {re} ± {im} i, {re1} ± {im1} i; rigid pendulum {w}");
    assert!(re.abs() < 1e-9 * w && re1.abs() < 1e-9 * w, "{re} {re1}");
    assert!(im == -im1 && (im.abs() - w).abs() < 2e-4 * w, "{im} vs {w}");
    std::fs::write(&path, with(100.0)).unwrap();
    let (ok, _, err) = ffr(&["linearize", p, "--at", "static"]);
    assert!(!ok && err.contains("no static equilibrium found"), "{err}");
}

/// `C` of every kind of output (position, velocity, elastic deflection,
/// absolute and relative angle) equals central differences of the output
/// computed from the marker kinematics, projected with the same basis, to
/// 1e-6 of each column (the mechanism in motion, planar and spatial).
#[test]
fn output_matrix_equals_finite_differences() {
    use ffr::runtime::linear::LinearOutput;
    use ffr::runtime::spec::scene::OutputKind;
    for dim in [2, 3] {
        let sys = common::mechanism(dim);
        let s = state_after(&sys, 20, 1e-3);
        let link = sys.body_id("link").unwrap();
        let arm = sys.body_id("arm").unwrap();
        let p = Marker::at(link, Vector3::new(0.2, 0.0, 0.0));
        let tip = sys.point(arm, 1.0).unwrap();
        let mid = sys.point(arm, 0.5).unwrap();
        let out = |name: &str, kind, marker: &Marker, rel: Option<&Marker>| LinearOutput {
            name: name.into(),
            kind,
            marker: marker.clone(),
            relative_to: rel.cloned(),
        };
        let outputs = [
            out("py", OutputKind::Position(1), &p, None),
            out("vx", OutputKind::Velocity(0), &tip, None),
            out("dy", OutputKind::Deflection(1), &mid, None),
            out("angle", OutputKind::Angle, &Marker::origin(link), None),
            out("rel", OutputKind::Angle, &Marker::origin(link), Some(&tip)),
        ];
        let model = linearize(&sys, &s, &[], &outputs).unwrap();
        // The outputs from the marker kinematics at (q, q̇).
        let value = |q: &[f64], v: &[f64]| -> Vec<f64> {
            let eval = |m: &Marker| {
                let mut k = sys.marker_kin(m);
                k.eval(m, q);
                k
            };
            let kp = eval(&p);
            let kt = eval(&tip);
            let km = eval(&mid);
            let kl = eval(&Marker::origin(link));
            let dy: f64 = mid
                .shape
                .entries
                .iter()
                .enumerate()
                .map(|(j, (_, sh, _))| sh[1] * q[km.idx[km.n_frame + j]])
                .sum();
            let x = kl.axes[0];
            vec![
                kp.pos.y,
                kt.velocity(v).x,
                dy,
                x.y.atan2(x.x),
                x.dot(&kt.axes[1]).atan2(x.dot(&kt.axes[0])),
            ]
        };
        let free = &model.parts.free;
        let (mut gq, mut gv) = (
            DMatrix::zeros(outputs.len(), free.len()),
            DMatrix::zeros(outputs.len(), free.len()),
        );
        for (j, &c) in free.iter().enumerate() {
            for which in 0..2 {
                let x = [&s.q, &s.v][which][c];
                let h = 1e-6 * (1.0 + x.abs());
                let (mut qp, mut vp) = (s.q.clone(), s.v.clone());
                let (mut qm, mut vm) = (s.q.clone(), s.v.clone());
                if which == 0 {
                    qp[c] += h;
                    qm[c] -= h;
                } else {
                    vp[c] += h;
                    vm[c] -= h;
                }
                let (yp, ym) = (value(&qp, &vp), value(&qm, &vm));
                for i in 0..outputs.len() {
                    let d = (yp[i] - ym[i]) / (2.0 * h);
                    if which == 0 {
                        gq[(i, j)] = d;
                    } else {
                        gv[(i, j)] = d;
                    }
                }
            }
        }
        let nz = model.basis.ncols();
        let mut c_fd = DMatrix::zeros(outputs.len(), 2 * nz);
        c_fd.view_mut((0, 0), (outputs.len(), nz))
            .copy_from(&(&gq * &model.basis));
        c_fd.view_mut((0, nz), (outputs.len(), nz))
            .copy_from(&(&gv * &model.basis));
        let err = col_rel(&model.c.transpose(), &c_fd.transpose());
        println!("dim {dim}: C against differences {err:.1e} (per output row)");
        assert!(err < 1e-6, "{err:e}");
        assert!(
            model.c.row(1).iter().skip(nz).any(|x| *x != 0.0),
            "velocity output"
        );
    }
}

/// Issue 36: a time so short that a step of it is no step of the scene is
/// refused with the way out (`--at 0`), not by halving the step to
/// 1e-303 s; a time just above the bound is linearized.
#[test]
fn an_operating_time_too_short_for_a_step_is_refused() {
    let p = common::cli::scene("pendulum.toml");
    let (ok, _, err) = ffr(&["linearize", &p, "--at", "1e-300"]);
    assert!(!ok);
    assert!(
        err.contains("--at 1e-300")
            && err.contains("use --at 0")
            && !err.contains("halved")
            && err.lines().count() == 1,
        "{err}"
    );
    let (ok, _, err) = ffr(&["linearize", &p, "--at", "1e-14"]);
    assert!(ok, "{err}");
}

/// Issue 36: the eigenvalues of a matrix that is not finite are an error,
/// not a Schur iteration without end (the hang of `campbell --speeds
/// 1e15` on the slider-crank).
#[test]
fn eigenvalues_of_a_non_finite_matrix_are_an_error() {
    for x in [f64::NAN, f64::INFINITY] {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, x, 0.0]);
        let e = eigenvalues(&a).unwrap_err().to_string();
        assert!(e.contains("at (2, 1)"), "{e}");
    }
}

/// Issue 36 (the linearize fuzzer, 100 000 cases, seed 1, case 21 934):
/// the precone rotor's model with its drive's perturbation as the input
/// (98 states, a drive angle state whose row is zero and a column with no
/// off-diagonal entry) never converged in nalgebra's Schur iteration (the
/// capped iteration refused it: "did not converge in 5880 Schur
/// iterations"). The eigenvalues those isolate are taken first (as
/// LAPACK's `dgebal` permutes them out). Checked against the matrix: the
/// eigenvalues sum to its trace, and `A − λI` is singular at each of them
/// (its smallest singular value ≤ 1e-9 ‖A‖, and over a thousand times
/// larger 0.1 rad/s away).
#[test]
fn the_eigenvalues_of_a_model_with_isolated_eigenvalues_converge() {
    use ffr::runtime::nalgebra::Complex;
    use ffr::scene::linear::{linearize_scene, At};
    let dir = ffr::scene::load::builtin_dir();
    let spec = ffr::scene::load::load_spec(&dir.join("precone.toml")).unwrap();
    let m = linearize_scene(
        &spec,
        &DefaultKernels,
        At::Time(0.0),
        Some(&["drive1".to_string()]),
        None,
    )
    .unwrap();
    let a = &m.a;
    let n = a.nrows();
    let ev = eigenvalues(a).expect("eigenvalues");
    assert_eq!(ev.len(), n);
    let norm = a.norm();
    let trace: f64 = (0..n).map(|i| a[(i, i)]).sum();
    let sum: Complex<f64> = ev.iter().sum();
    assert!(
        (sum.re - trace).abs() <= 1e-9 * norm && sum.im.abs() <= 1e-9 * norm,
        "Σλ = {sum}, trace {trace}"
    );
    let ac = a.map(|x| Complex::new(x, 0.0));
    let smallest = |l: Complex<f64>| {
        let s = (&ac - DMatrix::<Complex<f64>>::identity(n, n) * l).singular_values();
        s.min()
    };
    // The slowest modes (two double pairs at ±2.9108 rad/s, ±18.24 rad/s).
    for l in ev.iter().filter(|l| l.norm() > 1e-6).take(6) {
        let s = smallest(*l);
        assert!(s <= 1e-9 * norm, "σ_min(A − λI) = {s:e} at λ = {l}");
        let off = smallest(*l + Complex::new(0.0, 0.1));
        assert!(off > 1e3 * s, "0.1 rad/s away: σ_min = {off:e}");
    }
}
