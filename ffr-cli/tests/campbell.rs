//! Campbell diagrams (issue 20): the rotating uniform cantilever's flap and
//! lag frequencies against the published table of Wright, Smith, Thompson
//! & Hodges (1982) and an independent classical rotating-beam model, a
//! slender one against Hamza Cherif & Houmat (2004) and a coupled lag–axial
//! linear model, the
//! lag relation `λ_lag² = λ_flap² − η²`, the hub radius, `Ω = 0` against
//! `ffr modes`, and a Campbell run that finds no steady state.

mod common;

use common::cli::ffr;
use ffr::runtime::nalgebra::{DMatrix, SymmetricEigen};
use ffr::scene::linear::{campbell, Campbell};
use ffr::scene::DefaultKernels;
use std::path::Path;

/// The first flap frequency `λ₁ = ω₁ √(ρA L⁴/EI)` of a uniform clamped
/// Euler–Bernoulli beam rotating about an axis through its root (hub
/// radius 0) at `η = Ω √(ρA L⁴/EI) = 0, 1, …, 12`: Wright, Smith, Thompson
/// & Hodges, "Vibration modes of centrifugally stiffened beams", J. Appl.
/// Mech. 49 (1982) 197–202, Table 1 (also Banerjee 2000, J. Sound Vib.
/// 233(5), Table 1). Checked here against [`classical`].
const WRIGHT_FLAP1: [f64; 13] = [
    3.5160, 3.6816, 4.1373, 4.7973, 5.5850, 6.4495, 7.3604, 8.2996, 9.2568, 10.2257, 11.2023,
    12.1843, 13.1702,
];

/// 4-point Gauss–Legendre on [0, 1] as (point, weight): exact for the
/// element integrands here (`T N′N′`, degree 6).
fn gauss4() -> [(f64, f64); 4] {
    let (a, b) = (0.339_981_043_584_856_3, 0.861_136_311_594_052_6);
    let (wa, wb) = (0.652_145_154_862_546_1, 0.347_854_845_137_453_9);
    [
        (0.5 - 0.5 * b, 0.5 * wb),
        (0.5 - 0.5 * a, 0.5 * wa),
        (0.5 + 0.5 * a, 0.5 * wa),
        (0.5 + 0.5 * b, 0.5 * wb),
    ]
}

/// The classical linear model of a rotating uniform cantilever (flap),
/// written independently of ffr: Hermite cubic elements for
/// `EI w'''' − (T w')' + ρA ẅ = 0` with the centrifugal tension
/// `T(x) = ρA Ω² (R (L − x) + (L² − x²)/2)` (hub radius `R`), `L = ρA = EI =
/// 1`; the in-plane (lag) problem adds `−ρA Ω² v`. Its lowest `k`
/// nondimensional frequencies (flap, lag).
fn classical(eta: f64, delta: f64, elements: usize, k: usize) -> (Vec<f64>, Vec<f64>) {
    classical_with(eta, delta, elements, k, false)
}

/// [`classical`], with `mean` the tension of each element replaced by its
/// mean over the element (as ffr's stiffening models take the axial strain:
/// docs/theory.md, section 10, "The element mean").
fn classical_with(
    eta: f64,
    delta: f64,
    elements: usize,
    k: usize,
    mean: bool,
) -> (Vec<f64>, Vec<f64>) {
    let n = 2 * elements; // clamped root: node 0 removed
    let h = 1.0 / elements as f64;
    let (mut km, mut mm, mut kg) = (
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
    );
    // Hermite cubics on ξ ∈ [0, 1]: w = N · [w₀, θ₀, w₁, θ₁].
    let dn = |xi: f64| {
        [
            (-6.0 * xi + 6.0 * xi * xi) / h,
            1.0 - 4.0 * xi + 3.0 * xi * xi,
            (6.0 * xi - 6.0 * xi * xi) / h,
            -2.0 * xi + 3.0 * xi * xi,
        ]
    };
    let ke = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    let me = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
    ];
    let gauss = gauss4();
    for e in 0..elements {
        let dofs: [isize; 4] = std::array::from_fn(|i| 2 * e as isize + i as isize - 2);
        let mut ge = [[0.0; 4]; 4];
        let tension = |x: f64| delta * (1.0 - x) + 0.5 * (1.0 - x * x);
        let t_mean: f64 = gauss
            .iter()
            .map(|&(xi, w)| w * tension((e as f64 + xi) * h))
            .sum();
        for &(xi, w) in &gauss {
            let x = (e as f64 + xi) * h;
            let t = if mean { t_mean } else { tension(x) };
            let d = dn(xi);
            for i in 0..4 {
                for j in 0..4 {
                    ge[i][j] += w * h * t * d[i] * d[j];
                }
            }
        }
        for i in 0..4 {
            for j in 0..4 {
                let (Ok(r), Ok(c)) = (usize::try_from(dofs[i]), usize::try_from(dofs[j])) else {
                    continue;
                };
                km[(r, c)] += ke[i][j] / (h * h * h);
                mm[(r, c)] += me[i][j] * h / 420.0;
                kg[(r, c)] += ge[i][j];
            }
        }
    }
    let freq = |k_all: DMatrix<f64>| -> Vec<f64> {
        let l = mm.clone().cholesky().unwrap();
        let li = l.l().try_inverse().unwrap();
        let s: DMatrix<f64> = &li * k_all * li.transpose();
        let s = (&s + s.transpose()) * 0.5;
        let mut ev: Vec<f64> = SymmetricEigen::new(s)
            .eigenvalues
            .iter()
            .map(|x| x.sqrt())
            .collect();
        ev.sort_by(f64::total_cmp);
        ev.truncate(k);
        ev
    };
    let e2 = eta * eta;
    let flap = freq(&km + &kg * e2);
    let lag = freq(&km + &kg * e2 - &mm * e2);
    (flap, lag)
}

/// A uniform beam3 cantilever with `L = ρA = EI = 1` (both bending
/// planes; E = 10⁸, I = 10⁻⁸: the rotary inertia and the centrifugal
/// stretch are below 10⁻⁶) clamped to a rigid hub of radius `delta`
/// turning about global z.
fn scene(elements: usize, stiffening: &str, delta: f64) -> ffr::scene::SceneSpec {
    hub_scene(
        elements,
        stiffening,
        delta,
        "params = { length = 1.0, rho = 1.0, area = 1.0, iy = 1e-8, iz = 1e-8, e = 1e8, g = 4e7, j = 2e-8 }",
    )
}

/// A beam3 cantilever of `elements` elements with the section `section`
/// (a `params` or `sections` line) and stiffening model `stiffening`,
/// clamped to a rigid hub of radius `delta` turning about global z.
fn hub_scene(
    elements: usize,
    stiffening: &str,
    delta: f64,
    section: &str,
) -> ffr::scene::SceneSpec {
    let text = format!(
        r#"dimension = 3
t_end = 1.0
dt = 1e-3
[bodies.hub]
mass = 1.0
inertia = [1.0, 1.0, 1.0]
position = [0.0, 0.0, 0.0]
[bodies.beam]
shape = "beam3"
elements = {elements}
reference = "clamped"
stiffening = "{stiffening}"
{section}
position = [{delta}, 0.0, 0.0]
[[joints]]
kind = "revolute"
a = "ground@[0.0, 0.0, 0.0]"
b = "hub"
drive = {{ angle = "constant-rate", omega = 0.0 }}
[[joints]]
kind = "fixed"
a = "hub@[{delta}, 0.0, 0.0]"
b = "beam"
"#
    );
    ffr::codegen::scene::resolve_str(&text, "rotating.toml", Path::new(".")).unwrap()
}

/// The first mode labelled `label` at speed index `i` (at rest, flap and
/// lag are one double frequency, and its two modes get the two labels).
fn first(c: &Campbell, i: usize, label: &str) -> f64 {
    c.modes[i]
        .iter()
        .find(|m| m.label == label)
        .unwrap_or_else(|| panic!("no {label} mode at Ω = {}: {:?}", c.speeds[i], c.modes[i]))
        .omega
}

/// The table is transcribed right: the classical model (64 elements)
/// reproduces it to its last digit.
#[test]
fn the_published_table_matches_the_classical_model() {
    for (eta, &t) in WRIGHT_FLAP1.iter().enumerate() {
        let (flap, _) = classical(eta as f64, 0.0, 64, 1);
        assert!((flap[0] - t).abs() < 6e-5, "η = {eta}: {} vs {t}", flap[0]);
    }
}

/// Errors of a Campbell diagram of [`scene`] against the classical model:
/// (flap, lag) relative to the continuous model (64 elements, the exact
/// tension) and to the element-mean model of the same mesh; the worst
/// over the speeds, and the largest `|λ_lag² − (λ_flap² − η²)|/λ_lag²`.
fn errors(c: &Campbell, delta: f64, elements: usize) -> ([f64; 2], [f64; 2], f64) {
    let (mut cont, mut mean, mut rel) = ([0.0f64; 2], [0.0f64; 2], 0.0f64);
    for (i, &eta) in c.speeds.iter().enumerate() {
        let (cf, cl) = classical(eta, delta, 64, 1);
        let (mf, ml) = classical_with(eta, delta, elements, 1, true);
        let (f, l) = (first(c, i, "flap"), first(c, i, "lag"));
        println!(
            "δ = {delta}, {elements} elements, η = {eta}: flap {f:.7} (continuous {:.7}, element mean {:.7}), lag {l:.7} ({:.7}, {:.7})",
            cf[0], mf[0], cl[0], ml[0]
        );
        cont = [
            cont[0].max((f - cf[0]).abs() / cf[0]),
            cont[1].max((l - cl[0]).abs() / cl[0]),
        ];
        mean = [
            mean[0].max((f - mf[0]).abs() / mf[0]),
            mean[1].max((l - ml[0]).abs() / ml[0]),
        ];
        if delta == 0.0 {
            rel = rel.max((l * l - (f * f - eta * eta)).abs() / (l * l));
        }
    }
    (cont, mean, rel)
}

/// The rotating cantilever at `η = 0, 2, …, 12`, fourth-order stiffening.
/// ffr's Campbell frequencies are those of the classical rotating beam with
/// each element's tension its mean over the element (the stiffening
/// models' element mean, docs/theory.md §10) to 3e-6 (flap) and 5e-6 (lag,
/// which also feels the Coriolis coupling to the axial motion); the lag
/// obeys `λ_lag² = λ_flap² − η²` to 5e-6. Against the continuous theory
/// (Wright et al. 1982, the classical model) the element mean costs
/// `O(h²)`: measured, worst over η ≤ 12, flap 8.3e-4 and lag 3.3e-3 with 8
/// elements, 2.1e-4 and 8.2e-4 with 16 (the element-mean agreement 3e-8
/// and 1.1e-6 at both); asserted below 1e-3 / 4e-3 at 8 and 3.5× smaller
/// at 16.
#[test]
fn rotating_cantilever_flap_and_lag_follow_the_literature() {
    let speeds: Vec<f64> = (0..=6).map(|k| 2.0 * k as f64).collect();
    let mut cont = Vec::new();
    for elements in [8, 16] {
        let c = campbell(
            &scene(elements, "fourth-order", 0.0),
            &DefaultKernels,
            &speeds,
            None,
            8,
        )
        .unwrap();
        let (e, m, rel) = errors(&c, 0.0, elements);
        let table = speeds
            .iter()
            .enumerate()
            .map(|(i, &eta)| {
                let t = WRIGHT_FLAP1[eta as usize];
                (first(&c, i, "flap") - t).abs() / t
            })
            .fold(0.0f64, f64::max);
        println!("{elements} elements: continuous flap {:.2e} lag {:.2e} (table {table:.2e}); element mean {:.1e} / {:.1e}; lag relation {rel:.1e}", e[0], e[1], m[0], m[1]);
        assert!(m[0] < 3e-6 && m[1] < 5e-6, "{elements}: {m:?}");
        assert!(rel < 5e-6, "{rel:e}");
        assert!(
            (table - e[0]).abs() < 2e-5,
            "the table and the classical model"
        );
        cont.push(e);
    }
    assert!(cont[0][0] < 1e-3 && cont[0][1] < 4e-3, "{:?}", cont[0]);
    for k in 0..2 {
        assert!(cont[1][k] < cont[0][k] / 3.5, "{cont:?}");
    }
}

/// The second-order (von Kármán) stiffening model has the same linearized
/// centrifugal stiffening about the steady stretched state (the axial
/// force times the element mean of `v'² + w'²`): the same frequencies as
/// the fourth-order model, to the same element-mean classical model.
#[test]
fn second_order_stiffening_also_follows_the_classical_model() {
    let speeds = [0.0, 6.0, 12.0];
    let c = campbell(
        &scene(8, "second-order", 0.0),
        &DefaultKernels,
        &speeds,
        None,
        8,
    )
    .unwrap();
    let (e, m, rel) = errors(&c, 0.0, 8);
    println!(
        "second order, 8 elements: continuous {e:?}, element mean {m:?}, lag relation {rel:.1e}"
    );
    assert!(m[0] < 3e-6 && m[1] < 5e-6, "{m:?}");
}

/// A hub of radius `δ = R/L = 1`: the tension gains `ρA Ω² R (L − x)`;
/// flap and lag as the element-mean classical model with the same tension
/// (3e-6, 5e-6) at 16 elements; against the continuous model the element
/// mean's error (measured 4.4e-4 flap, 7.0e-4 lag at η = 12).
#[test]
fn hub_radius_raises_the_stiffening_as_the_classical_model() {
    let speeds = [0.0, 4.0, 8.0, 12.0];
    let c = campbell(
        &scene(16, "fourth-order", 1.0),
        &DefaultKernels,
        &speeds,
        None,
        8,
    )
    .unwrap();
    let (e, m, _) = errors(&c, 1.0, 16);
    println!("δ = 1, 16 elements: continuous {e:?}, element mean {m:?}");
    assert!(m[0] < 3e-6 && m[1] < 5e-6, "{m:?}");
    assert!(e[0] < 1e-3 && e[1] < 1.5e-3, "{e:?}");
}

/// At `Ω = 0` the Campbell frequencies are `ffr modes` of the same body
/// (the spin-up beam, planar), and `--json` has `speeds` and per speed the
/// modes with `omega, hz, zeta, label`; the SVG is written.
#[test]
fn campbell_at_rest_equals_modes_and_its_json() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("c.svg");
    let (ok, out, err) = ffr(&[
        "campbell",
        "../scenes/spin_up.toml",
        "--speeds",
        "0,4",
        "--count",
        "5",
        "--json",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(js["speeds"], serde_json::json!([0.0, 4.0]));
    let modes = js["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 2);
    let m0: Vec<f64> = modes[0]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            let keys: Vec<&str> = m.as_object().unwrap().keys().map(|k| k.as_str()).collect();
            assert_eq!(keys.len(), 4, "{keys:?}");
            assert!(
                (m["hz"].as_f64().unwrap() - m["omega"].as_f64().unwrap() / std::f64::consts::TAU)
                    .abs()
                    < 1e-12
            );
            m["omega"].as_f64().unwrap()
        })
        .collect();
    assert_eq!(m0.len(), 5);
    let (ok, out, err) = ffr(&[
        "modes",
        "--scene",
        "../scenes/spin_up.toml",
        "--body",
        "beam",
        "--json",
        "--count",
        "5",
    ]);
    assert!(ok, "{err}");
    let mj: serde_json::Value = serde_json::from_str(&out).unwrap();
    for (a, b) in m0.iter().zip(mj["omega"].as_array().unwrap()) {
        let b = b.as_f64().unwrap();
        assert!((a - b).abs() < 1e-9 * b, "{a} vs {b}");
    }
    // Spinning raises the in-plane bending frequencies (lag, planar).
    let m4 = modes[1].as_array().unwrap();
    assert!(m4[0]["omega"].as_f64().unwrap() > m0[0]);
    assert_eq!(m4[0]["label"], "lag");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg") && text.contains("3P"));
}

/// The spin-up beam with its stiffening spins stably at 20 rad/s (no
/// eigenvalue off the imaginary axis beyond round-off); without stiffening
/// (a linear FFR beam) it is past its first bending frequency and spin
/// softening makes it diverge (section 5, planar case): a real pair,
/// `ζ = ±1`.
#[test]
fn spin_softening_shows_as_an_unstable_pair() {
    let text = include_str!("../../scenes/spin_up.toml");
    let mut zetas = Vec::new();
    for t in [
        text.to_string(),
        text.replace("stiffening = true", "stiffening = false"),
    ] {
        let spec = ffr::codegen::scene::resolve_str(&t, "spin_up.toml", Path::new(".")).unwrap();
        let c = campbell(&spec, &DefaultKernels, &[20.0], None, 6).unwrap();
        zetas.push(c.modes[0].iter().map(|m| m.zeta).collect::<Vec<_>>());
    }
    println!("ζ with stiffening {:?}, without {:?}", zetas[0], zetas[1]);
    assert!(zetas[0].iter().all(|z| z.abs() < 1e-9), "{:?}", zetas[0]);
    assert!(
        zetas[1].iter().any(|&z| (z + 1.0).abs() < 1e-9),
        "{:?}",
        zetas[1]
    );
}

/// Gravity in the plane of rotation turns with the rotor: there is no
/// steady state, and the command says so (at the gravity line) and exits
/// non-zero.
#[test]
fn no_steady_state_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("heavy.toml");
    let text = include_str!("../../scenes/spin_up.toml")
        .replace("dimension = 2", "dimension = 2\ngravity = [0.0, -9.81]");
    std::fs::write(&path, text).unwrap();
    let (ok, _, err) = ffr(&["campbell", path.to_str().unwrap(), "--speeds", "0,2"]);
    assert!(!ok, "{err}");
    assert!(
        err.contains("heavy.toml:6:11: gravity")
            && !err.contains("heavy.toml: ")
            && err.contains("no steady state"),
        "{err}"
    );
}

/// The NREL 5-MW blade (`scenes/blade_5mw.toml`: section table, hub radius
/// 1.5 m) up to its rated 12.1 rpm: its first flap, edge (lag) and second
/// flap frequencies rise with the speed, along Southwell's
/// `ω² = ω₀² + K Ω²` (the coefficient `K` from half and full speed agrees
/// to 3%; measured 0.9% for the first flap), flap more than edge (the edge
/// loses `Ω²` to the in-plane term). The diagram is `docs/campbell_5mw.svg`.
#[test]
fn nrel_5mw_blade_stiffens_as_southwell_predicts() {
    let text = include_str!("../../scenes/blade_5mw.toml");
    let spec =
        ffr::codegen::scene::resolve_str(text, "blade_5mw.toml", Path::new("../scenes")).unwrap();
    let rated = 12.1 * std::f64::consts::TAU / 60.0;
    let speeds = [0.0, 0.5 * rated, rated];
    let c = campbell(&spec, &DefaultKernels, &speeds, None, 4).unwrap();
    let labels: Vec<&str> = c.modes[0].iter().map(|m| m.label.as_str()).collect();
    assert_eq!(labels, ["flap", "lag", "flap", "lag"]);
    let mut k_flap = 0.0;
    for k in 0..3 {
        let w: Vec<f64> = c.modes.iter().map(|ms| ms[k].omega).collect();
        let ks: Vec<f64> = (1..3)
            .map(|i| (w[i] * w[i] - w[0] * w[0]) / (speeds[i] * speeds[i]))
            .collect();
        println!(
            "mode {} ({}): {:.4} → {:.4} → {:.4} Hz, Southwell K {:.4} / {:.4}",
            k + 1,
            labels[k],
            w[0] / std::f64::consts::TAU,
            w[1] / std::f64::consts::TAU,
            w[2] / std::f64::consts::TAU,
            ks[0],
            ks[1]
        );
        assert!(w[1] > w[0] && w[2] > w[1], "mode {k} does not rise: {w:?}");
        assert!((ks[0] - ks[1]).abs() < 0.03 * ks[1], "mode {k}: {ks:?}");
        if k == 0 {
            k_flap = ks[1];
        }
        if k == 1 {
            assert!(ks[1] < k_flap, "edge {} vs flap {k_flap}", ks[1]);
        }
    }
}

/// The modal spin-up beam (4 modes and the static modes of the same 8
/// elements; its own equations and tangents, from the projected
/// invariants) has the nodal beam's Campbell frequencies: equal at rest to
/// 1e-9 (the modes are kept exactly; measured 6e-12), and at 4 rad/s
/// within 5e-6 for the first three (the reduced basis; measured 3.5e-6 at
/// most).
#[test]
fn modal_body_campbell_equals_the_nodal_body() {
    let read =
        |text: &str| ffr::codegen::scene::resolve_str(text, "s.toml", Path::new(".")).unwrap();
    let nodal = read(include_str!("../../scenes/spin_up.toml"));
    let modal = read(include_str!("../../scenes/spin_up_modal.toml"));
    let speeds = [0.0, 4.0];
    let a = campbell(&nodal, &DefaultKernels, &speeds, None, 3).unwrap();
    let b = campbell(&modal, &DefaultKernels, &speeds, None, 3).unwrap();
    for i in 0..2 {
        for (x, y) in a.modes[i].iter().zip(&b.modes[i]) {
            let rel = (x.omega - y.omega).abs() / x.omega;
            println!(
                "Ω = {}: nodal {} modal {} ({rel:.1e})",
                speeds[i], x.omega, y.omega
            );
            assert!(rel < if i == 0 { 1e-9 } else { 5e-6 }, "{rel:e}");
        }
    }
}

/// The spin-up beam turning at a constant 4 rad/s, released from its steady
/// stretched state plus a little of its first lag mode (from `K̂`, `M̂` of
/// the Campbell model, the gyroscopic coupling left out): the nonlinear run
/// (generalized-α, dt = 1 ms) oscillates at the Campbell frequency — the
/// stiffening about the steady state and the spin softening as the
/// linearization has them — to 1e-5 (measured 1.0e-6; by upward zero
/// crossings of the tip's transverse deflection over 10 s).
#[test]
fn rotating_free_response_has_the_campbell_frequency() {
    use ffr::runtime::linear::{linearize, steady_state, SteadyMotion};
    let text = include_str!("../../scenes/spin_up.toml")
        .replace(
            r#"drive = { angle = "spin-up", omega = 4.0, ramp = 15.0 }"#,
            r#"drive = { angle = "constant-rate", omega = 4.0 }"#,
        )
        .replace("t_end = 20.0", "t_end = 10.0")
        .replace("dt = 0.01", "dt = 1e-3");
    assert!(text.contains("constant-rate"));
    let mut scene =
        ffr::scene::from_str(&text, "spin.toml", Path::new("."), &DefaultKernels).unwrap();
    let sys = &scene.system;
    let init = sys.initial_state(0.0).unwrap();
    let motion = SteadyMotion::Rotation {
        center: [0.0; 3],
        omega: 4.0,
    };
    let st = steady_state(sys, 0.0, &init, motion).unwrap();
    let model = linearize(sys, &st, &[], &[]).unwrap();
    let w1 = ffr::runtime::linear::eigenvalues(&model.a)
        .unwrap()
        .into_iter()
        .find(|l| l.im > 0.0)
        .unwrap()
        .im;
    // The first mode of (K̂, M̂).
    let l = model.m_hat.clone().cholesky().unwrap();
    let li = l.l().try_inverse().unwrap();
    let s = &li * &model.k_hat * li.transpose();
    let s = (&s + s.transpose()) * 0.5;
    let eig = SymmetricEigen::new(s);
    let k = eig.eigenvalues.imin();
    let phi = li.transpose() * eig.eigenvectors.column(k);
    let q_mode = &model.basis * phi;
    let beam = sys.body_id("beam").unwrap();
    let e = &sys.bodies()[beam.0];
    let (f0, nf) = (e.f_offset(), e.nf);
    let free = &model.parts.free;
    let mut q_f: Vec<f64> = st.q[f0..f0 + nf].to_vec();
    let scale = 1e-3 / q_mode.amax();
    for (i, &c) in free.iter().enumerate() {
        if (f0..f0 + nf).contains(&c) {
            q_f[c - f0] += scale * q_mode[i];
        }
    }
    scene
        .system
        .set_elastic(beam, &q_f, &vec![0.0; nf])
        .unwrap();
    let r = ffr::scene::run(&scene).unwrap();
    assert!(r.failed.is_none(), "{:?}", r.failed);
    let y = &r.columns[r.names.iter().position(|n| n == "tip_transverse").unwrap()];
    let mut ups = Vec::new();
    for k in 1..y.len() {
        if y[k - 1] < 0.0 && y[k] >= 0.0 {
            ups.push(r.t[k - 1] + (r.t[k] - r.t[k - 1]) * (-y[k - 1]) / (y[k] - y[k - 1]));
        }
    }
    assert!(ups.len() >= 4, "{ups:?}");
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    let w_run = std::f64::consts::TAU / period;
    println!("free response at 4 rad/s: {w_run} rad/s, Campbell {w1} rad/s, at rest 2.9108");
    assert!((w_run - w1).abs() / w1 < 1e-5, "{w_run} vs {w1}");
}

/// The spatial rotating cantilever (8 elements, clamped to a driven rigid
/// hub by a fixed joint: Euler parameters, joints and multipliers in the
/// linearization) at η = 6, released from its steady state with a little of
/// its first flap mode: the nonlinear run's flap frequency (zero crossings
/// of the tip's z deflection over 5 s, dt = 1 ms) equals the Campbell flap
/// frequency to 1e-5 (measured 4.2e-6: the integrator's period error
/// `(ω dt)²/12 = 4.5e-6`).
#[test]
fn spatial_flap_free_response_has_the_campbell_frequency() {
    use ffr::runtime::linear::{linearize, steady_state, SteadyMotion};
    let eta = 6.0;
    let mut spec = scene(8, "fourth-order", 0.0);
    let c = campbell(&spec, &DefaultKernels, &[eta], None, 4).unwrap();
    let w_flap = first(&c, 0, "flap");
    spec.joints[0].drive = spec.joints[0].drive.take().map(|(_, at)| {
        (
            ffr::runtime::spec::scene::ProfileSpec::ConstantRate {
                start: 0.0,
                rate: eta,
            },
            at,
        )
    });
    spec.t_end = 5.0;
    let text_out = r#"dimension = 3
t_end = 1.0
dt = 1e-3
[bodies.beam]
shape = "beam3"
elements = 2
reference = "clamped"
params = { length = 1.0, rho = 1.0, area = 1.0, iy = 1e-8, iz = 1e-8, e = 1e8, g = 4e7, j = 2e-8 }
[[joints]]
kind = "ground"
b = "beam"
[[outputs]]
name = "tip_w"
kind = "deflection"
at = "beam@x=1.0"
component = "z"
"#;
    // The output (its marker resolved against the same body index).
    let out = ffr::codegen::scene::resolve_str(text_out, "o.toml", Path::new(".")).unwrap();
    let mut o = out.outputs[0].clone();
    if let Some(m) = o.at.as_mut() {
        if let ffr::runtime::spec::scene::MarkerPoint::Axis(b, _) = &mut m.point {
            *b = spec.bodies.iter().position(|b| b.name == "beam").unwrap();
        }
    }
    spec.outputs = vec![o];
    let mut built = ffr::scene::build(&spec, &DefaultKernels).unwrap();
    let sys = &built.system;
    let init = sys.initial_state(0.0).unwrap();
    let motion = SteadyMotion::Rotation {
        center: [0.0; 3],
        omega: eta,
    };
    let st = steady_state(sys, 0.0, &init, motion).unwrap();
    let model = linearize(sys, &st, &[], &[]).unwrap();
    // The lowest mode of (K̂, M̂) whose motion is out of the plane (uz, ry).
    let l = model.m_hat.clone().cholesky().unwrap();
    let li = l.l().try_inverse().unwrap();
    let s = &li * &model.k_hat * li.transpose();
    let eig = SymmetricEigen::new((&s + s.transpose()) * 0.5);
    let labels = ffr::runtime::linear::coordinate_labels(sys);
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|a, b| eig.eigenvalues[*a].total_cmp(&eig.eigenvalues[*b]));
    let flap_share = |v: &ffr::runtime::nalgebra::DVector<f64>| {
        let q = &model.basis * v;
        let (mut w, mut all) = (0.0, 0.0);
        for (i, &g) in model.parts.free.iter().enumerate() {
            all += q[i] * q[i];
            if labels[g].contains(".uz_") || labels[g].contains(".ry_") {
                w += q[i] * q[i];
            }
        }
        w / all
    };
    let k = *order
        .iter()
        .find(|&&k| flap_share(&(li.transpose() * eig.eigenvectors.column(k))) > 0.5)
        .unwrap();
    let q_mode = &model.basis * (li.transpose() * eig.eigenvectors.column(k));
    let beam = sys.body_id("beam").unwrap();
    let e = &sys.bodies()[beam.0];
    let (f0, nf) = (e.f_offset(), e.nf);
    let mut q_f: Vec<f64> = st.q[f0..f0 + nf].to_vec();
    let scale = 1e-4 / q_mode.amax();
    for (i, &c) in model.parts.free.iter().enumerate() {
        if (f0..f0 + nf).contains(&c) {
            q_f[c - f0] += scale * q_mode[i];
        }
    }
    built
        .system
        .set_elastic(beam, &q_f, &vec![0.0; nf])
        .unwrap();
    let r = ffr::scene::run(&built).unwrap();
    assert!(r.failed.is_none(), "{:?}", r.failed);
    let y = &r.columns[0];
    let mut ups = Vec::new();
    for k in 1..y.len() {
        if y[k - 1] < 0.0 && y[k] >= 0.0 {
            ups.push(r.t[k - 1] + (r.t[k] - r.t[k - 1]) * (-y[k - 1]) / (y[k] - y[k - 1]));
        }
    }
    assert!(ups.len() >= 4, "{ups:?}");
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    let w_run = std::f64::consts::TAU / period;
    println!("spatial flap at η = {eta}: run {w_run}, Campbell {w_flap}");
    assert!(
        (w_run - w_flap).abs() / w_flap < 1e-5,
        "{w_run} vs {w_flap}"
    );
}

/// The rotating cantilever of slenderness `λ = L/√(I/A) = 70` (so `EA L²/EI
/// = 4900`: the lag mode's Coriolis coupling to the axial stretch is no
/// longer negligible), Euler–Bernoulli without rotary inertia, at
/// `μ = Ω √(ρA L⁴/EI) = 2, 4, 6, 8, 10`: flapwise and chordwise
/// non-dimensional first frequencies from Hamza Cherif & Houmat, "Natural
/// frequencies of rotating cantilever flexible beams by using the p-version
/// of the finite element method", 24th ICAS Congress (2004), Table 2 (as
/// quoted in the test suite of octave-user/mboct-fem-pkg, `fem_tests.m`).
const CHERIF_MU: [f64; 5] = [2.0, 4.0, 6.0, 8.0, 10.0];
const CHERIF_FLAP: [f64; 5] = [4.1373, 5.5850, 7.3603, 9.2568, 11.2023];
const CHERIF_LAG: [f64; 5] = [3.6195, 3.888, 4.2393, 4.6105, 4.97];

/// A uniform beam3 cantilever with `L = ρA = EI = 1`, `EA = λ²`, no rotary
/// inertia (resultant section form, `rho_iy = rho_iz = 0`), on a hub turning
/// about global z.
fn slender_scene(elements: usize, ea: f64) -> ffr::scene::SceneSpec {
    let row = |x: f64| {
        format!("{{ x = {x:?}, mass = 1.0, ea = {ea:?}, ei_y = 1.0, ei_z = 1.0, gj = 1.0, rho_iy = 0.0, rho_iz = 0.0, rho_j = 1e-4 }}")
    };
    let section = format!("sections = [{}, {}]", row(0.0), row(1.0));
    hub_scene(elements, "fourth-order", 0.0, &section)
}

/// The first flap and lag frequencies of the classical *linear* theory of a rotating
/// uniform cantilever with axial motion (`L = ρA = EI = 1`, hub radius 0),
/// written independently of ffr: the lag deflection `v` on Hermite cubics
/// and the axial displacement `u` on linear elements, about the undeformed
/// beam with the rigid-body tension `T = μ² (1 − x²)/2`:
/// `ρA (ü − 2Ω v̇ − Ω² u) − EA u″ = 0`,
/// `ρA (v̈ + 2Ω u̇ − Ω² v) + EI v⁗ − (T v′)′ = 0`;
/// the gyroscopic eigenproblem through its first-order form.
fn classical_coupled(mu: f64, ea: f64, elements: usize) -> (f64, f64) {
    let h = 1.0 / elements as f64;
    let nv = 2 * elements;
    let n = nv + elements;
    let (mut k, mut m, mut g) = (
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
    );
    let gauss = gauss4();
    let hermite = |xi: f64| {
        [
            1.0 - 3.0 * xi * xi + 2.0 * xi * xi * xi,
            h * (xi - 2.0 * xi * xi + xi * xi * xi),
            3.0 * xi * xi - 2.0 * xi * xi * xi,
            h * (-xi * xi + xi * xi * xi),
        ]
    };
    let hermite_x = |xi: f64| {
        [
            (-6.0 * xi + 6.0 * xi * xi) / h,
            1.0 - 4.0 * xi + 3.0 * xi * xi,
            (6.0 * xi - 6.0 * xi * xi) / h,
            -2.0 * xi + 3.0 * xi * xi,
        ]
    };
    let hermite_xx = |xi: f64| {
        [
            (-6.0 + 12.0 * xi) / (h * h),
            (-4.0 + 6.0 * xi) / h,
            (6.0 - 12.0 * xi) / (h * h),
            (-2.0 + 6.0 * xi) / h,
        ]
    };
    let mu2 = mu * mu;
    let mut kf = DMatrix::<f64>::zeros(nv, nv);
    for e in 0..elements {
        // v: global rows 2e − 2 … 2e + 1 (node 0 clamped); u: nv + e − 1, nv + e.
        let vd: [Option<usize>; 4] = std::array::from_fn(|i| (2 * e + i).checked_sub(2));
        let ud: [Option<usize>; 2] =
            std::array::from_fn(|i| (e + i).checked_sub(1).map(|j| nv + j));
        for &(xi, w) in &gauss {
            let t = 0.5 * mu2 * (1.0 - ((e as f64 + xi) * h).powi(2));
            let (nv_, dv, ddv) = (hermite(xi), hermite_x(xi), hermite_xx(xi));
            let (nu, du) = ([1.0 - xi, xi], [-1.0 / h, 1.0 / h]);
            let wh = w * h;
            for i in 0..4 {
                let Some(r) = vd[i] else { continue };
                for j in 0..4 {
                    let Some(c) = vd[j] else { continue };
                    k[(r, c)] += wh * (ddv[i] * ddv[j] + t * dv[i] * dv[j] - mu2 * nv_[i] * nv_[j]);
                    m[(r, c)] += wh * nv_[i] * nv_[j];
                    kf[(r, c)] += wh * (ddv[i] * ddv[j] + t * dv[i] * dv[j]);
                }
                for j in 0..2 {
                    let Some(c) = ud[j] else { continue };
                    // v equation: + 2Ω u̇; u equation: − 2Ω v̇ (Ω = μ here).
                    g[(r, c)] += wh * 2.0 * mu * nv_[i] * nu[j];
                    g[(c, r)] -= wh * 2.0 * mu * nv_[i] * nu[j];
                }
            }
            for i in 0..2 {
                let Some(r) = ud[i] else { continue };
                for j in 0..2 {
                    let Some(c) = ud[j] else { continue };
                    k[(r, c)] += wh * (ea * du[i] * du[j] - mu2 * nu[i] * nu[j]);
                    m[(r, c)] += wh * nu[i] * nu[j];
                }
            }
        }
    }
    let flap = {
        let mv: DMatrix<f64> = m.view((0, 0), (nv, nv)).into_owned();
        let li = mv.cholesky().unwrap().l().try_inverse().unwrap();
        let sym = &li * kf * li.transpose();
        SymmetricEigen::new((&sym + sym.transpose()) * 0.5)
            .eigenvalues
            .iter()
            .fold(f64::INFINITY, |a, &b| a.min(b))
            .sqrt()
    };
    let mi = m.try_inverse().unwrap();
    let mut a1 = DMatrix::zeros(2 * n, 2 * n);
    a1.view_mut((0, n), (n, n))
        .copy_from(&DMatrix::<f64>::identity(n, n));
    a1.view_mut((n, 0), (n, n)).copy_from(&(-&mi * &k));
    a1.view_mut((n, n), (n, n)).copy_from(&(-&mi * &g));
    let lag = a1
        .complex_eigenvalues()
        .iter()
        .map(|l| l.im)
        .filter(|&w| w > 1e-6)
        .fold(f64::INFINITY, f64::min);
    (flap, lag)
}

/// The slender table is transcribed right and is the linear theory: the
/// classical coupled model (64 elements) reproduces every value *truncated*
/// to four decimals (the quote drops trailing zeros: 5.585 is 5.5850), i.e.
/// `0 ≤ model − table < 1e-4` (measured 1.4e-6 … 9.3e-5; rounding would
/// fail at 3.61956 and 4.61059). Its flap column is Wright et al.'s
/// (`WRIGHT_FLAP1`, rounded: 7.3604 where this table truncates 7.36037 to
/// 7.3603).
#[test]
fn the_slender_table_is_the_linear_theory() {
    for (i, &mu) in CHERIF_MU.iter().enumerate() {
        let (flap, lag) = classical_coupled(mu, 4900.0, 64);
        let (tf, tl) = (CHERIF_FLAP[i], CHERIF_LAG[i]);
        println!("μ = {mu}: flap {flap:.6} ({tf}), lag {lag:.6} ({tl})");
        assert!((0.0..1e-4).contains(&(flap - tf)), "μ = {mu}: flap {flap}");
        assert!((0.0..1e-4).contains(&(lag - tl)), "μ = {mu}: lag {lag}");
        assert!((tf - WRIGHT_FLAP1[mu as usize]).abs() < 1.5e-4);
    }
}

/// The slender rotating cantilever in ffr (16 and 32 elements, Richardson
/// extrapolated in `h²`, the stiffening models' element-mean order): the
/// lag mode's Coriolis coupling to the axial stretch lowers it from
/// `√(λ_flap² − μ²)` (5.049 at μ = 10) to the table's 4.970; ffr gives
/// 4.979. ffr linearizes its nonlinear beam about the steady *stretched*
/// state (the stretch is `u(L)/L ≈ μ²/(3 λ²) = 6.8e-3` at μ = 10; its
/// linearization is checked against its own nonlinear runs in
/// `rotating_free_response_has_the_campbell_frequency`), the table's theory
/// about the undeformed beam; the difference grows with the speed:
/// measured 9e-6, 1.1e-4, 4.2e-4, 9.8e-4, 1.8e-3 (lag) and 1e-5 … 2.9e-4
/// (flap) at μ = 2 … 10; at `EA L²/EI = 4.9·10⁵` the flap is the table's
/// to 1.1e-5. Asserted: lag within 2.5e-3 and flap within 4e-4 of the table,
/// and the coupling captured: ffr's lag below `√(λ_flap² − μ²)` by at least
/// 85 % of the table's drop.
#[test]
fn slender_rotating_cantilever_follows_hamza_cherif_and_houmat() {
    let mut res = Vec::new();
    for elements in [16, 32] {
        let c = campbell(
            &slender_scene(elements, 4900.0),
            &DefaultKernels,
            &CHERIF_MU,
            None,
            8,
        )
        .unwrap();
        let v: Vec<(f64, f64)> = (0..CHERIF_MU.len())
            .map(|i| (first(&c, i, "flap"), first(&c, i, "lag")))
            .collect();
        res.push(v);
    }
    for (i, &mu) in CHERIF_MU.iter().enumerate() {
        let ((f16, l16), (f32_, l32)) = (res[0][i], res[1][i]);
        let (f, l) = ((4.0 * f32_ - f16) / 3.0, (4.0 * l32 - l16) / 3.0);
        let (tf, tl) = (CHERIF_FLAP[i], CHERIF_LAG[i]);
        let uncoupled = (tf * tf - mu * mu).sqrt();
        println!(
            "μ = {mu}: flap {f16:.6} {f32_:.6} → {f:.6} (table {tf}, {:.1e}), lag {l16:.6} {l32:.6} → {l:.6} (table {tl}, {:.1e}; uncoupled {uncoupled:.4})",
            (f - tf).abs() / tf,
            (l - tl).abs() / tl
        );
        assert!((f - tf).abs() / tf < 4e-4, "μ = {mu}: flap {f}");
        assert!((l - tl).abs() / tl < 2.5e-3, "μ = {mu}: lag {l}");
        assert!(uncoupled - l > 0.85 * (uncoupled - tl), "μ = {mu}: lag {l}");
    }
}

/// A flexible body turning with the Campbell joint without geometric
/// stiffening cannot show its flap frequencies rising with the speed:
/// `ffr campbell` warns once on stderr, at the body's table, saying what
/// to set, and lists the warning in `--json`; with stiffening, nothing.
#[test]
fn no_stiffening_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let text = include_str!("../../scenes/spin_up.toml");
    let off = text.replace("stiffening = true", "stiffening = false");
    assert_ne!(off, text);
    for (name, t, warned) in [
        ("on.toml", text.to_string(), false),
        ("off.toml", off, true),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, t).unwrap();
        let p = path.to_str().unwrap();
        let (ok, out, err) = ffr(&["campbell", p, "--speeds", "0,2", "--count", "2", "--json"]);
        assert!(ok, "{err}");
        let js: serde_json::Value = serde_json::from_str(&out).unwrap();
        let warnings = js["warnings"].as_array().unwrap();
        if warned {
            assert_eq!(err.matches("warning: ").count(), 1, "{err}");
            assert!(
                err.contains(&format!("warning: {p}:"))
                    && err
                        .contains("body `beam` turns with joint 1 but has no geometric stiffening")
                    && err.contains("set `stiffening = true`"),
                "{err}"
            );
            assert_eq!(warnings.len(), 1, "{js}");
        } else {
            assert!(!err.contains("warning"), "{err}");
            assert!(warnings.is_empty(), "{js}");
        }
    }
}

/// Issue 36: the slider-crank's slider turns with the crank (through the
/// rod) but its prismatic joint holds it to the ground: there is no
/// steady rotating state. Refused at that joint, before any computation
/// (before, `--speeds 1e15` spun forever and ordinary speeds printed a
/// diagram).
#[test]
fn a_rotor_body_held_to_the_ground_has_no_steady_state() {
    let p = common::cli::scene("slider_crank.toml");
    for speeds in ["150", "1e15"] {
        let (ok, out, err) = ffr(&["campbell", &p, "--speeds", speeds]);
        assert!(!ok && out.is_empty(), "{speeds}: {out}");
        assert!(
            err.contains("slider_crank.toml:82:")
                && err.contains("joint 4 (a prismatic joint of body `slider` to the ground)")
                && err.contains("no steady rotating state"),
            "{speeds}: {err}"
        );
        // Refused before the diagram's warnings.
        assert!(!err.contains("warning"), "{err}");
    }
}

/// Issue 36: the steady state passes the validity check. At 2000 rad/s
/// the 8 m spin-up beam's steady state (linear elasticity with
/// stiffening) has its elastic displacement beyond the beam's length;
/// at 1e20 rad/s too: both are refused, naming the speed and the body
/// (before, both printed a diagram and exited 0). Speeds so large that
/// the centrifugal forces overflow are values too large for double
/// precision, not a step to shorten (campbell has none).
#[test]
fn a_steady_state_beyond_the_body_size_is_refused() {
    let p = common::cli::scene("spin_up.toml");
    for (w, shown) in [("2000", "Ω = 2000.0 rad/s"), ("1e20", "Ω = 1e20 rad/s")] {
        let (ok, _, err) = ffr(&["campbell", &p, "--speeds", w, "--count", "2"]);
        assert!(!ok, "{w}");
        assert!(
            err.contains(shown)
                && err.contains("the state reached is not valid")
                && err.contains("body `beam` is deformed by")
                && err.contains("its length 8.0000 m"),
            "{w}: {err}"
        );
    }
    let (ok, _, err) = ffr(&["campbell", &p, "--speeds", "1e155", "--count", "2"]);
    assert!(!ok);
    assert!(
        err.contains("Ω = 1e155 rad/s")
            && err.contains("too large for double precision")
            && !err.contains("try a smaller step"),
        "{err}"
    );
    // A valid speed still gives its diagram.
    let (ok, out, err) = ffr(&["campbell", &p, "--speeds", "0,20", "--count", "2"]);
    assert!(ok && out.contains("Ω = 20.0 rad/s"), "{err}");
}

/// Issue 36: spin softening of a beam without stiffening turns its first
/// lag pair into a divergent pair (ζ = ±1, `spin_softening_shows_as_an_unstable_pair`):
/// the diagram says so, naming the speed and the mode, on stderr and in
/// `--json` `warnings`; with stiffening nothing is said.
#[test]
fn a_divergent_pair_is_warned_about_by_speed_and_mode() {
    let text = include_str!("../../scenes/spin_up.toml");
    let off = text.replace("stiffening = true", "stiffening = false");
    for (t, diverges) in [(text.to_string(), false), (off, true)] {
        let spec = ffr::codegen::scene::resolve_str(&t, "spin_up.toml", Path::new(".")).unwrap();
        let c = campbell(&spec, &DefaultKernels, &[0.0, 20.0], None, 4).unwrap();
        let growing: Vec<&String> = c
            .warnings
            .iter()
            .filter(|w| w.contains("the steady rotation is unstable"))
            .collect();
        if diverges {
            assert_eq!(growing.len(), 1, "{:?}", c.warnings);
            let k = c.modes[1]
                .iter()
                .position(|m| (m.zeta + 1.0).abs() < 1e-9)
                .unwrap();
            assert!(
                growing[0].starts_with("Ω = 20.0 rad/s")
                    && growing[0].contains(&format!("mode {} (", k + 1))
                    && growing[0].contains("divergent"),
                "{}",
                growing[0]
            );
        } else {
            assert!(growing.is_empty(), "{:?}", c.warnings);
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("off.toml");
    std::fs::write(
        &path,
        text.replace("stiffening = true", "stiffening = false"),
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let (ok, out, err) = ffr(&["campbell", p, "--speeds", "20", "--count", "4", "--json"]);
    assert!(ok, "{err}");
    assert!(
        err.contains(&format!(
            "warning: {p}: Ω = 20.0 rad/s: the steady rotation is unstable"
        )),
        "{err}"
    );
    let js: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(js["warnings"].as_array().unwrap().len(), 2, "{js}");
}
