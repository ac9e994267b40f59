//! Two scene-file features: point forces scaled by a time function
//! (`profile = { kind = "…", … }` or `{ table = [[t, f], …] }`) and
//! markers with their own axes (`{ at = "…", axes = { … } }`). Each is
//! checked against an independent route: the work of a profiled force
//! against `∫ F(t)·ṗ dt` from the recorded velocities and the energy
//! balance, a harmonic load against the exact response of the scene's
//! linear model, the L-frame joined by one turned `fixed` joint against the
//! unit-load method, angles read at turned markers against the body's.

use ffr::runtime::nalgebra::{DMatrix, DVector};
use ffr::scene::linear::{linearize_scene, operating_state, At};
use ffr::scene::{self, DefaultKernels, Scene, SceneRun};
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    scene::load::builtin_dir()
}

/// A built-in scene's text with `edits` (each must apply once).
fn edited(name: &str, edits: &[(&str, &str)]) -> String {
    let mut text = std::fs::read_to_string(scenes().join(name)).unwrap();
    for (from, to) in edits {
        assert_eq!(text.matches(from).count(), 1, "{name}: `{from}`");
        text = text.replace(from, to);
    }
    text
}

fn load(text: &str) -> Scene {
    scene::from_str(text, "test.toml", &scenes(), &DefaultKernels).unwrap_or_else(|e| panic!("{e}"))
}

fn run(text: &str) -> SceneRun {
    let r = scene::run(&load(text)).unwrap();
    assert!(r.failed.is_none(), "{:?}", r.failed);
    r
}

fn column<'a>(r: &'a SceneRun, name: &str) -> &'a [f64] {
    let i = r.names.iter().position(|n| n == name).unwrap();
    &r.columns[i]
}

fn bits(r: &SceneRun) -> Vec<u64> {
    r.t.iter()
        .chain(r.columns.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Outputs added to the pendulum: the tip's velocity, the work of the
/// point forces and what the dampers took.
const TIP_OUTPUTS: &str = r#"
[[outputs]]
name = "tip_vx"
kind = "velocity"
at = "bar@x=1.0"
component = "x"

[[outputs]]
name = "tip_vy"
kind = "velocity"
at = "bar@x=1.0"
component = "y"

[[outputs]]
name = "work"
kind = "energy"
component = "work"
"#;

/// The pendulum (`scenes/pendulum.toml`, ρ∞ = 1, no damping) with a point
/// force `force` at the tip, `extra` lines in its table.
fn pendulum_with_force(force: &str, extra: &str) -> String {
    format!(
        "{}\n[[forces]]\nkind = \"point\"\nat = \"bar@x=1.0\"\nforce = {force}\n{extra}\n{TIP_OUTPUTS}",
        edited("pendulum.toml", &[])
    )
}

/// The piecewise-linear function through `rows`, written again here (held
/// before the first and after the last row).
fn table_at(rows: &[[f64; 2]], t: f64) -> f64 {
    if t <= rows[0][0] {
        return rows[0][1];
    }
    for w in rows.windows(2) {
        let ([t0, f0], [t1, f1]) = (w[0], w[1]);
        if t <= t1 {
            return f0 + (f1 - f0) * (t - t0) / (t1 - t0);
        }
    }
    rows[rows.len() - 1][1]
}

/// A global force at the pendulum's tip scaled by a table, which starts
/// after t = 0 (held at its first value before), turns the force over and
/// ends before `t_end` (held after): the `work` output equals the
/// trapezoidal `∫ F(t)·v dt` from the recorded tip velocities with the
/// table evaluated here (to round-off: 1e-12 of the largest work), and the
/// energy balance `E(t) − E(0) = W(t)` holds to the integrator's O(dt²)
/// error: at most 5e-6 of the work's peak at dt = 1 ms (measured 2.9e-6),
/// and 3.5 to 4.5 times smaller at dt = 0.5 ms (measured 3.98).
#[test]
fn a_table_profile_does_the_work_of_its_force() {
    let rows = [[0.1, 0.2], [0.3, 1.0], [0.5, -1.0], [0.55, 0.0], [0.8, 0.5]];
    let table: Vec<String> = rows
        .iter()
        .map(|r| format!("[{:?}, {:?}]", r[0], r[1]))
        .collect();
    let force = [0.3, -2.0];
    let text = pendulum_with_force(
        &format!("[{:?}, {:?}]", force[0], force[1]),
        &format!("profile = {{ table = [{}] }}", table.join(", ")),
    );
    let mut balance = Vec::new();
    for dt in ["1e-3", "5e-4"] {
        let r = run(&text.replace("dt = 1e-3", &format!("dt = {dt}")));
        let (vx, vy, work, energy) = (
            column(&r, "tip_vx"),
            column(&r, "tip_vy"),
            column(&r, "work"),
            column(&r, "energy"),
        );
        let power: Vec<f64> =
            r.t.iter()
                .enumerate()
                .map(|(i, &t)| table_at(&rows, t) * (force[0] * vx[i] + force[1] * vy[i]))
                .collect();
        let mut w = 0.0;
        let mut worst = 0.0f64;
        for i in 1..r.t.len() {
            w += 0.5 * (r.t[i] - r.t[i - 1]) * (power[i - 1] + power[i]);
            worst = worst.max((w - work[i]).abs());
        }
        let wmax = peak(work);
        println!("dt {dt}: work peak {wmax:.6} J, |W − ∫F·v| ≤ {worst:.2e}");
        assert!(wmax > 0.05, "the force did little work: {wmax}");
        assert!(worst <= 1e-12 * wmax, "{worst:e}");
        let bal = (0..r.t.len())
            .map(|i| (energy[i] - energy[0] - work[i]).abs())
            .fold(0.0f64, f64::max);
        println!(
            "dt {dt}: max |E − E(0) − W| = {bal:.3e} ({:.2e} of the work)",
            bal / wmax
        );
        balance.push(bal / wmax);
    }
    assert!(balance[0] < 5e-6, "{balance:?}");
    let ratio = balance[0] / balance[1];
    assert!((3.5..=4.5).contains(&ratio), "not O(dt²): {balance:?}");
}

/// `profile = { kind = "constant", value = 1.0 }` and a one-row table of 1
/// run bit for bit like the force without a profile (global and follower
/// forces); a constant 2 like the force doubled (`2 F` is exact).
#[test]
fn a_constant_profile_of_one_is_the_force_itself() {
    for axes in ["\"global\"", "\"body\""] {
        let plain = run(&pendulum_with_force(
            "[0.3, -2.0]",
            &format!("axes = {axes}"),
        ));
        for p in [
            "{ kind = \"constant\", value = 1.0 }",
            "{ table = [[0.4, 1.0]] }",
        ] {
            let with = run(&pendulum_with_force(
                "[0.3, -2.0]",
                &format!("axes = {axes}\nprofile = {p}"),
            ));
            assert_eq!(bits(&plain), bits(&with), "{axes} {p}");
        }
        let doubled = run(&pendulum_with_force(
            "[0.6, -4.0]",
            &format!("axes = {axes}"),
        ));
        let two = run(&pendulum_with_force(
            "[0.3, -2.0]",
            &format!("axes = {axes}\nprofile = {{ kind = \"constant\", value = 2.0 }}"),
        ));
        assert_eq!(bits(&doubled), bits(&two), "{axes}");
        assert_ne!(bits(&plain), bits(&two), "{axes}");
    }
}

/// A clamped aluminium cantilever (1 m, 10 × 10 mm, 4 beam2 elements,
/// first bending mode 8.2 Hz) under a tip load `0.01 f(t)` N with the
/// harmonic profile `f = 1 + sin(2π 3 Hz t − π/2) = 1 − cos(2π 3 Hz t)`
/// (which starts from 0 at rate 0): its tip deflection equals the exact
/// response of the scene's linear model (`linearize_scene`, input `force1`
/// = the force's magnitude, so `u(t) = 0.01 f(t)`) from rest: `x(t) = x_c +
/// x_p(t) + e^{At}(−x_c − x_p(0))` with the constant part `A x_c = −B F₀`
/// and the harmonic part `x_p = P sin ωt + Q cos ωt`, `ωP = AQ − B F₀`,
/// `−ωQ = AP` (`u = F₀ − F₀ cos ωt`). What remains is the integrator's
/// error (ρ∞ = 1: a period error of (ω dt)²/12 per mode) and the geometric
/// nonlinearity (third order in the tip deflection, 1.2e-4 of the length,
/// for a transverse output): at most 1e-5 of the peak at dt = 1e-4 s
/// (measured 3.7e-6), and O(dt²): 3.5 to 4.5 times smaller at dt = 5e-5 s
/// (measured 3.96).
#[test]
fn a_harmonic_load_drives_the_cantilever_as_its_linear_model() {
    let text = r#"
dimension = 2
t_end = 0.4
dt = 1e-4
integrator = { kind = "generalized-alpha", rho_inf = 1.0 }

[bodies.beam]
shape = "beam2"
elements = 4
reference = "clamped"
params = { length = 1.0, rho = 2700.0, area = 1e-4, iz = 8.333333333333334e-10, e = 7.0e10 }

[[joints]]
kind = "ground"
b = "beam"

[[forces]]
kind = "point"
at = "beam@x=1.0"
force = [0.0, 0.01]
profile = { kind = "harmonic", start = 1.0, amplitude = 1.0, frequency = 3.0, phase = -1.5707963267948966 }

[[outputs]]
name = "tip"
kind = "deflection"
at = "beam@x=1.0"
component = "y"
"#;
    let spec = ffr::codegen::scene::resolve_str(text, "cantilever.toml", Path::new(".")).unwrap();
    let model = linearize_scene(
        &spec,
        &DefaultKernels,
        At::Time(0.0),
        Some(&["force1".to_string()]),
        Some(&["tip".to_string()]),
    )
    .unwrap();
    let (a, b, c) = (&model.a, &model.b, &model.c);
    let n = a.nrows();
    let w = 2.0 * std::f64::consts::PI * 3.0;
    let f0 = 0.01;
    let bu: DVector<f64> = b.column(0) * f0;
    // The constant part and the harmonic part of u = F₀ − F₀ cos ωt.
    let xc = a
        .clone()
        .lu()
        .solve(&(-&bu))
        .expect("A is regular (clamped)");
    let mut h = DMatrix::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(a);
    h.view_mut((n, n), (n, n)).copy_from(a);
    h.view_mut((0, n), (n, n))
        .copy_from(&(DMatrix::identity(n, n) * -w));
    h.view_mut((n, 0), (n, n))
        .copy_from(&(DMatrix::identity(n, n) * w));
    // Rows: A Q − ω P = B F₀ (cos), A P + ω Q = 0 (sin); unknowns [Q; P].
    let mut rhs = DVector::zeros(2 * n);
    rhs.rows_mut(0, n).copy_from(&bu);
    let qp = h.lu().solve(&rhs).expect("ω is not an eigenfrequency");
    let (q, p) = (qp.rows(0, n).into_owned(), qp.rows(n, n).into_owned());
    assert!((a * &q - &p * w - &bu).norm() <= 1e-9 * bu.norm());
    assert!((a * &p + &q * w).norm() <= 1e-9 * bu.norm());
    let mut errors = Vec::new();
    for dt in [1e-4, 5e-5] {
        let r = run(&text.replace("dt = 1e-4", &format!("dt = {dt:e}")));
        let y = column(&r, "tip");
        let e = (a * dt).exp();
        let mut z = -&xc - &q; // e^{A t} (−x_c − x_p(0))
        let mut worst = 0.0f64;
        let mut lin_peak = 0.0f64;
        for (k, &t) in r.t.iter().enumerate() {
            if k > 0 {
                z = &e * &z;
            }
            assert!((t - k as f64 * dt).abs() < 1e-9);
            let x = &xc + &p * (w * t).sin() + &q * (w * t).cos() + &z;
            let yl = (c * &x)[0];
            lin_peak = lin_peak.max(yl.abs());
            worst = worst.max((y[k] - yl).abs());
        }
        println!(
            "dt {dt:e}: linear peak {lin_peak:.4e} m, run peak {:.4e} m, max difference {worst:.3e} ({:.2e} of the peak)",
            peak(y),
            worst / lin_peak
        );
        // About twice the static deflection of the amplitude, F L³/(3EI).
        assert!(lin_peak > 1e-4, "{lin_peak}");
        errors.push(worst / lin_peak);
    }
    assert!(errors[0] < 1e-5, "{errors:?}");
    let ratio = errors[0] / errors[1];
    assert!((3.5..=4.5).contains(&ratio), "not O(dt²): {errors:?}");
}

/// Aluminium, 10 × 10 mm.
const E: f64 = 7.0e10;
const AREA: f64 = 1e-4;
const IZ: f64 = 8.333333333333334e-10;

/// The tip deflection of the L-frame (leg 1 of length `l1` clamped, leg 2
/// of length `l2` at a right angle on its tip, a load `p` at leg 2's free
/// end perpendicular to leg 2, in leg 1's direction) by the unit-load
/// method: along the load, leg 2 bends as a cantilever (`v₂ = P L2³/(3EI)`),
/// leg 1 carries the constant moment `P L2` (its tip turns by `θ = P L2
/// L1/(EI)`, which swings leg 2's tip by `L2 θ`) and the axial force `P`
/// (`P L1/(EA)`); across it, leg 1's tip drops by `P L2 L1²/(2EI)` (leg 2
/// carries no axial force). Returns (along the load, across it in leg 2's
/// direction, the same with the second-order terms of leg 2's turn: its
/// tip drops by `L2 θ²/2 + v₂ θ` more, about 1e-4 of the linear value
/// here; along the load the next terms are of third order).
fn l_frame_deflection(p: f64, l1: f64, l2: f64) -> (f64, f64, f64) {
    let ei = E * IZ;
    let (v2, theta) = (p * l2.powi(3) / (3.0 * ei), p * l2 * l1 / ei);
    let across = -p * l2 * l1 * l1 / (2.0 * ei);
    (
        v2 + l2 * theta + p * l1 / (E * AREA),
        across,
        across - l2 * theta * theta / 2.0 - v2 * theta,
    )
}

/// `scenes/l_frame.toml`: two beams joined at a right angle by one `fixed`
/// joint whose marker `a` is leg 1's end section turned by π/2. Beam2
/// (Hermite) elements are exact at the nodes for these end loads (linear
/// moment, constant axial force), so the linear deflection is the
/// unit-load method's.
/// - The static equilibrium under the full load (the profile taken out):
///   along the load within 1e-6 (measured 2e-8); across it within 1e-4 of
///   the linear value (the second-order drop of leg 2's turning tip is
///   8.6e-5 of it) and within 1e-6 with that drop.
/// - The damped run with the load ramped by the table profile: settled on
///   the static state (within 1e-5 at t = 2 s), the corner section's angle
///   with the marker's turn equal to leg 2's frame angle at every step
///   (the joint, to 1e-10 rad), and the elastic energy stored in the end
///   `P δx / 2` (Clapeyron's theorem for a linear structure, 1e-5), which
///   is less than the work the load did (the dampers and the integrator's
///   numerical dissipation took the rest).
#[test]
fn the_l_frame_bends_as_the_unit_load_method_says() {
    let (l1, l2, p) = (1.0, 0.6, 0.01);
    let (dx, dy, dy2) = l_frame_deflection(p, l1, l2);
    println!("unit-load method: δx = {dx:.6e} m, δy = {dy:.6e} m ({dy2:.6e} m to second order)");
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    // Static, under the full load.
    let text = edited(
        "l_frame.toml",
        &[("profile = { table = [[0.0, 0.0], [0.2, 1.0]] }\n", "")],
    );
    let scene = load(&text);
    let st = operating_state(&scene, At::Static).unwrap();
    let o = scene.outputs.iter().find(|o| o.name == "tip_x").unwrap();
    let mut k = scene.system.marker_kin(&o.marker);
    k.eval(&o.marker, &st.q);
    let (sx, sy) = (k.pos[0] - l1, k.pos[1] - l2);
    println!(
        "static: δx = {sx:.9e} ({:.1e}), δy = {sy:.9e} ({:.1e}; {:.1e} to second order)",
        rel(sx, dx),
        rel(sy, dy),
        rel(sy, dy2)
    );
    assert!(rel(sx, dx) < 1e-6, "{sx} vs {dx}");
    assert!(rel(sy, dy) < 1e-4, "{sy} vs {dy}");
    assert!(rel(sy, dy2) < 1e-6, "{sy} vs {dy2}");
    // The shipped scene: a damped run, the load ramped by the profile.
    let r = run(&edited("l_frame.toml", &[]));
    let (x, y) = (column(&r, "tip_x"), column(&r, "tip_y"));
    let (ex, ey) = (x[x.len() - 1] - l1, y[y.len() - 1] - l2);
    println!(
        "run, t = {:.3}: δx = {ex:.9e} ({:.1e} from static), δy = {ey:.9e} ({:.1e})",
        r.t[r.t.len() - 1],
        rel(ex, sx),
        rel(ey, sy)
    );
    assert!(rel(ex, sx) < 1e-5, "{ex} vs {sx}");
    assert!(rel(ey, sy) < 1e-5, "{ey} vs {sy}");
    let (corner, leg2) = (column(&r, "corner_angle"), column(&r, "leg2_angle"));
    let apart = corner
        .iter()
        .zip(leg2)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    println!("max |corner − leg 2| = {apart:.2e} rad");
    assert!(apart < 1e-10, "{apart:e}");
    assert!((leg2[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    // Leg 2 turned with leg 1's tip (by θ = P L2 L1/(EI) = 1.03e-4 rad).
    let turn = leg2[leg2.len() - 1] - leg2[0];
    println!("leg 2 turned by {turn:.4e} rad");
    assert!(rel(-turn, p * l2 * l1 / (E * IZ)) < 1e-4, "{turn}");
    let (work, elastic) = (column(&r, "work"), column(&r, "elastic"));
    let (w, u) = (work[work.len() - 1], elastic[elastic.len() - 1]);
    println!(
        "work {w:.6e} J, elastic {u:.6e} J, P δx/2 = {:.6e} J",
        p * dx / 2.0
    );
    assert!(rel(u, p * dx / 2.0) < 1e-5, "{u}");
    assert!(w > u, "{w} {u}");
}

/// The same frame in space with beam3 legs, leg 2 standing along z on leg
/// 1's tip: the marker's axes turned about y by −π/2 (`axis = [0, 1, 0]`),
/// which takes x to z; a load along x bends both legs in the x–z plane
/// (their `iy`), as the planar frame (static equilibrium, to 1e-6 with
/// the second-order drop of leg 2's tip), and nothing moves along y.
#[test]
fn a_spatial_marker_turned_about_an_axis_joins_the_frame_in_space() {
    let text = r#"
dimension = 3
t_end = 0.01
dt = 1e-3

[bodies.leg1]
shape = "beam3"
elements = 4
params = { length = 1.0, rho = 2700.0, area = 1e-4, iy = 8.333333333333334e-10, iz = 8.333333333333334e-10, e = 7.0e10, g = 2.6e10, j = 1.4e-9 }

[bodies.leg2]
shape = "beam3"
elements = 3
params = { length = 0.6, rho = 2700.0, area = 1e-4, iy = 8.333333333333334e-10, iz = 8.333333333333334e-10, e = 7.0e10, g = 2.6e10, j = 1.4e-9 }
position = [1.0, 0.0, 0.0]
orientation = { axis = [0.0, 1.0, 0.0], angle = -1.5707963267948966 }

[[joints]]
kind = "ground"
b = "leg1"

[[joints]]
kind = "fixed"
a = { at = "leg1@x=1.0", axes = { axis = [0.0, 2.0, 0.0], angle = -1.5707963267948966 } }
b = "leg2"

[[forces]]
kind = "point"
at = "leg2@x=0.6"
force = [0.01, 0.0, 0.0]

[[outputs]]
name = "tip_x"
kind = "position"
at = "leg2@x=0.6"
component = "x"
"#;
    let (dx, _, dz) = l_frame_deflection(0.01, 1.0, 0.6);
    let scene = load(text);
    let st = operating_state(&scene, At::Static).unwrap();
    let o = &scene.outputs[0];
    let mut k = scene.system.marker_kin(&o.marker);
    k.eval(&o.marker, &st.q);
    let (sx, sy, sz) = (k.pos[0] - 1.0, k.pos[1], k.pos[2] - 0.6);
    println!(
        "spatial static: δx = {sx:.6e} ({:.2e}), δz = {sz:.6e} ({:.2e}), y = {sy:.1e}",
        (sx - dx) / dx,
        (sz - dz) / dz
    );
    assert!(((sx - dx) / dx).abs() < 1e-6, "{sx} vs {dx}");
    assert!(((sz - dz) / dz).abs() < 1e-6, "{sz} vs {dz}");
    assert!(sy.abs() < 1e-12 * dx.abs(), "{sy}");
}

/// A planar `angle` output at a marker with its axes turned by φ reads the
/// angle of the same marker without them plus φ, at every step: at a
/// body's frame (rigid axes) and at a beam section (whose axes the
/// deformation turns further), to round-off (1e-14 rad).
#[test]
fn an_angle_at_a_turned_marker_is_the_unturned_angle_plus_the_turn() {
    let outputs = r#"
[[outputs]]
name = "frame_turned"
kind = "angle"
at = { at = "bar", axes = { angle = 0.3 } }

[[outputs]]
name = "tip"
kind = "angle"
at = "bar@x=1.0"

[[outputs]]
name = "tip_turned"
kind = "angle"
at = { at = "bar@x=1.0", axes = { angle = -0.7 } }
"#;
    let r = run(&format!("{}{outputs}", edited("pendulum.toml", &[])));
    for (turned, plain, phi) in [("frame_turned", "angle", 0.3), ("tip_turned", "tip", -0.7)] {
        let (a, b) = (column(&r, turned), column(&r, plain));
        let worst = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y - phi).abs())
            .fold(0.0f64, f64::max);
        println!("{turned} − {plain} − ({phi}): {worst:.1e}");
        assert!(worst < 1e-14, "{turned}: {worst:e}");
        // The bar swung and bent: the comparison is of moving angles.
        assert!(peak(b) > 1.0);
    }
    let bend: Vec<f64> = column(&r, "tip")
        .iter()
        .zip(column(&r, "angle"))
        .map(|(t, f)| t - f)
        .collect();
    assert!(
        peak(&bend) > 1e-5,
        "the tip section did not turn against the frame"
    );
}

/// A marker written as a string and the same marker as a table, without
/// `axes` or with a turn of 0 (planar `angle = 0`, spatial about any axis),
/// in joints, forces and outputs: the same run, bit for bit.
#[test]
fn a_string_marker_and_its_table_without_a_turn_run_bit_for_bit() {
    let extra = "[[forces]]\nkind = \"spring-damper\"\na = \"ground@[1.2, -0.4]\"\nb = \"bar@x=0.7\"\nstiffness = 30.0\nrest_length = 0.5\ndamping = 0.2\n\n[[forces]]\nkind = \"point\"\nat = \"bar@x=1.0\"\nforce = [0.0, 1.0]\naxes = \"body\"\n";
    let plain = format!("{}\n{extra}", edited("pendulum.toml", &[]));
    let reference = run(&plain);
    let tables: [fn(&str) -> String; 2] = [
        |s| format!("{{ at = {s} }}"),
        |s| format!("{{ at = {s}, axes = {{ angle = 0.0 }} }}"),
    ];
    for table in tables {
        let mut text = plain.clone();
        for m in [
            "at = \"bar\"",
            "\"ground@[0.0, 0.0]\"",
            "b = \"bar\"",
            "\"ground@[1.2, -0.4]\"",
            "\"bar@x=0.7\"",
            "at = \"bar@x=1.0\"\nforce",
        ] {
            let (key, s) = match m.split_once(" = ") {
                Some((k, rest)) => (format!("{k} = "), rest.to_string()),
                None => (String::new(), m.to_string()),
            };
            let (s, tail) = match s.split_once('\n') {
                Some((s, t)) => (s.to_string(), format!("\n{t}")),
                None => (s, String::new()),
            };
            assert_eq!(text.matches(m).count(), 1, "{m}");
            text = text.replace(m, &format!("{key}{}{tail}", table(&s)));
        }
        assert_eq!(bits(&reference), bits(&run(&text)), "{text}");
    }
    // Spatial: a turn of 0 about any axis is no turn.
    let spatial = |b: &str| {
        format!(
            r#"
dimension = 3
gravity = [0.0, -9.81, 0.0]
t_end = 0.05
dt = 1e-3
integrator = {{ kind = "generalized-alpha", rho_inf = 1.0 }}

[bodies.bar]
shape = "beam3"
elements = 2
params = {{ length = 1.0, rho = 2700.0, area = 1e-4, iy = 8.333e-10, iz = 8.333e-10, e = 7.0e10, g = 2.6e10, j = 1.4e-9 }}
omega = [0.0, 2.0, 0.0]

[[joints]]
kind = "spherical"
a = "ground@[0.0, 0.0, 0.0]"
b = {b}

[[outputs]]
name = "tip_z"
kind = "position"
at = "bar@x=1.0"
component = "z"
"#
        )
    };
    let plain = run(&spatial("\"bar\""));
    let turned = run(&spatial(
        "{ at = \"bar\", axes = { axis = [0.3, -1.0, 2.0], angle = 0.0 } }",
    ));
    assert_eq!(bits(&plain), bits(&turned));
    assert!(peak(column(&plain, "tip_z")) > 0.05);
}

/// A Campbell diagram turns the rotor about global z: a driven joint whose
/// ground marker's own axes tilt z away is refused (naming the tilted z),
/// one turned about z only is not.
#[test]
fn a_campbell_diagram_refuses_a_rotor_axis_tilted_by_marker_axes() {
    let campbell = |a: &str| {
        let text = edited(
            "precone.toml",
            &[("a = \"ground@[0.0, 0.0, 0.0]\"", &format!("a = {a}"))],
        );
        let spec = ffr::codegen::scene::resolve_str(&text, "precone.toml", &scenes()).unwrap();
        ffr::scene::linear::campbell(&spec, &DefaultKernels, &[0.0], None, 2)
    };
    let e = campbell(
        "{ at = \"ground@[0.0, 0.0, 0.0]\", axes = { axis = [1.0, 0.0, 0.0], angle = 0.1 } }",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("a Campbell diagram turns the rotor about global z")
            && e.contains("has axes whose z is [0.000e0, -9.983e-2, 9.950e-1]"),
        "{e}"
    );
    let about_z = campbell(
        "{ at = \"ground@[0.0, 0.0, 0.0]\", axes = { axis = [0.0, 0.0, 2.0], angle = 0.1 } }",
    );
    assert!(
        about_z.is_ok(),
        "{:?}",
        about_z.err().map(|e| e.to_string())
    );
}
