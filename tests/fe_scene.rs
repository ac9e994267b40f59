//! FE bodies in scenes (issue 23): the solid cantilever of `tests/data/fe`
//! (steel box 1 × 0.1 × 0.1 m along x, 10 × 2 × 2 trilinear hexahedra, 99
//! nodes; scikit-fem) as a pendulum — energy conservation, the rigid
//! compound pendulum's period when it is stiff, the same bar as a `beam3`
//! scene — and hostile scene inputs.

use ffr::scene::{self, DefaultKernels, SceneRun};
use std::path::{Path, PathBuf};

/// The steel box: density, Young's modulus, Poisson's ratio, dimensions.
const RHO: f64 = 7850.0;
const E: f64 = 210e9;
const NU: f64 = 0.3;
const L: f64 = 1.0;
const B: f64 = 0.1;
const G: f64 = 9.81;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fe")
}

fn pendulum_text() -> String {
    std::fs::read_to_string(dir().join("pendulum.toml")).unwrap()
}

fn load(text: &str) -> Result<scene::Scene, ffr::SceneError> {
    scene::from_str(text, "pendulum.toml", &dir(), &DefaultKernels)
}

fn run(text: &str) -> SceneRun {
    let s = load(text).unwrap_or_else(|e| panic!("{e}"));
    let r = scene::run(&s).unwrap();
    assert!(r.failed.is_none(), "{:?}", r.failed);
    r
}

fn column<'a>(r: &'a SceneRun, name: &str) -> &'a [f64] {
    let i = r.names.iter().position(|n| n == name).unwrap();
    &r.columns[i]
}

/// `max |E − E(0)| / (m g L/2)` (the potential energy the swing turns over).
fn energy_drift(r: &SceneRun) -> f64 {
    let e = column(r, "energy");
    let m = RHO * L * B * B;
    e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / (m * G * L / 2.0)
}

/// The times the frame angle passes `level`, linearly interpolated between
/// steps.
fn crossings(r: &SceneRun, level: f64) -> Vec<f64> {
    let a = column(r, "angle");
    let mut out = Vec::new();
    for i in 1..a.len() {
        let (x0, x1) = (a[i - 1] - level, a[i] - level);
        if x0 != 0.0 && x0.signum() != x1.signum() {
            out.push(r.t[i - 1] + (r.t[i] - r.t[i - 1]) * x0 / (x0 - x1));
        }
    }
    out
}

/// The period of the rigid compound pendulum released from the horizontal:
/// `T = 4 √(I_O / (m g d)) K(sin 45°)`, the box's `I_O = m (L²/3 + B²/12)`
/// about the pin (the centre of the face x = 0), `d = L/2`; `K` by the
/// arithmetic-geometric mean.
fn rigid_period() -> f64 {
    let m = RHO * L * B * B;
    let io = m * (L * L / 3.0 + B * B / 12.0);
    let (mut a, mut g) = (1.0f64, (0.5f64).sqrt());
    for _ in 0..10 {
        (a, g) = ((a + g) / 2.0, (a * g).sqrt());
    }
    let k = std::f64::consts::PI / (2.0 * a);
    4.0 * (io / (m * G * L / 2.0)).sqrt() * k
}

/// Released from the horizontal with no damping and generalized-α at ρ∞ = 1
/// (12 clamped modes and 12 static modes): the continuous system conserves
/// energy, so the drift `max |E − E(0)| / (m g L/2)` over 1 s is the
/// integrator's error, second order in dt. Measured: 6.34e-6 at dt = 1e-3 s,
/// 1.11e-6 at 5e-4, 2.43e-7 at 2.5e-4 (ratios 5.7 and 4.6; the maximum over
/// a run of an oscillating error approaches the limit 4 unevenly: 4e-3 → 2e-3
/// gave 5.8, 2e-3 → 1e-3 gave 11). The beam3 pendulum of the same bar drifts
/// 5.0e-6 at dt = 1e-3.
#[test]
fn fe_pendulum_conserves_energy_to_second_order() {
    let drift: Vec<f64> = ["1e-3", "5e-4", "2.5e-4"]
        .iter()
        .map(|dt| {
            let r = run(&pendulum_text().replace("dt = 1e-3", &format!("dt = {dt}")));
            // The bar swings through the vertical to the other side.
            assert!(column(&r, "tip_y").iter().any(|y| *y < -0.99));
            energy_drift(&r)
        })
        .collect();
    println!("energy drift at dt 1e-3, 5e-4, 2.5e-4: {drift:?}");
    assert!(drift[0] < 1e-5, "{drift:?}");
    for w in drift.windows(2) {
        let ratio = w[0] / w[1];
        assert!((3.5..8.0).contains(&ratio), "second order: {drift:?}");
    }
}

/// The half period: between the first two passages through the vertical
/// (angle −π/2), on the way down and on the way back.
fn half_period(text: &str) -> f64 {
    let r = run(&text.replace("t_end = 1.0", "t_end = 1.6"));
    let c = crossings(&r, -std::f64::consts::FRAC_PI_2);
    assert!(c.len() >= 2, "{c:?}");
    c[1] - c[0]
}

/// The pendulum scene with the same bar as `elements` `beam3` elements:
/// `A = B²`, `I_y = I_z = B⁴/12`, `G = E/(2(1 + ν))`, `J = 0.1406 B⁴` (the
/// square's torsion constant), markers at the tip of the axis.
fn beam_text(elements: usize) -> String {
    let t = pendulum_text();
    let start = t.find("fe = {").unwrap();
    let end = start + t[start..].find("modes = 12").unwrap() + "modes = 12".len();
    let body = format!(
        "shape = \"beam3\"\nelements = {elements}\nreference = \"clamped\"\nparams = {{ length = {L:?}, rho = {RHO:?}, area = {:?}, iy = {i:?}, iz = {i:?}, e = {E:?}, g = {:?}, j = {:?} }}",
        B * B,
        E / (2.0 * (1.0 + NU)),
        0.1406 * B.powi(4),
        i = B.powi(4) / 12.0,
    );
    format!("{}{body}{}", &t[..start], &t[end..]).replace("bar@node=64", "bar@x=1.0")
}

/// The pendulum scene with `fe.stiffness_scale = scale`.
fn scaled(scale: f64) -> String {
    pendulum_text().replace(
        "stiffness = \"cantilever_stiffness.mtx\"",
        &format!("stiffness = \"cantilever_stiffness.mtx\", stiffness_scale = {scale:?}"),
    )
}

/// With `E` scaled up 10⁴ times (`stiffness_scale`: the bar's first
/// frequency 100 times higher) the FE pendulum's half period is the rigid
/// compound pendulum's (released at 90°, exact elliptic-integral period of
/// the box) to the integrator's error: measured relative errors 1.68e-6 at
/// dt = 1e-3 s and 4.19e-7 at 5e-4 (ratio 4.0: second order, the trapezoidal
/// rule's `(ω dt)²/12` period error); scaled 10² it is the same to 3e-9. The
/// steel bar itself (scale 1) swings slower by 1.2e-6 of the period at dt =
/// 5e-4: its elastic stretch and sag lengthen the pendulum.
#[test]
fn stiff_fe_pendulum_has_the_rigid_compound_pendulum_period() {
    let t = rigid_period();
    let stiff = scaled(1e4);
    let coarse = 2.0 * half_period(&stiff) / t - 1.0;
    let fine = 2.0 * half_period(&stiff.replace("dt = 1e-3", "dt = 5e-4")) / t - 1.0;
    let steel = 2.0 * half_period(&pendulum_text().replace("dt = 1e-3", "dt = 5e-4")) / t - 1.0;
    println!(
        "period error: stiff dt 1e-3 {coarse:.3e}, dt 5e-4 {fine:.3e}; steel dt 5e-4 {steel:.3e}"
    );
    assert!(fine.abs() < 1e-6, "{fine:e}");
    let ratio = coarse / fine;
    assert!(
        (3.5..4.5).contains(&ratio),
        "second order: {coarse:e} / {fine:e}"
    );
    // The elastic bar is slower, by far less than a part in 10⁵.
    let elastic = steel - fine;
    assert!(
        elastic > 0.0 && elastic < 1e-5,
        "steel − stiff: {elastic:e}"
    );
}

/// The same bar as 8 `beam3` elements (Euler–Bernoulli, `G = E/(2(1 + ν))`):
/// the tip (the FE node at the centre of the face x = 1, the beam's axis at x
/// = 1) swings the same to within the elastic deflection — measured max
/// |Δx| 2.4e-6 m, |Δy| 2.7e-6 m over the 1 m swing, while the tip deflects
/// 7.5e-6 m (FE) and 1.09e-5 m (beam). The deflections differ as the
/// stiffnesses do: the swing (about 3 rad/s) is far below the first bending
/// frequencies, so the deflection is quasi-static, ∝ 1/ω₁², and the coarse
/// trilinear hexahedra lock in shear (ω₁ 628.6 rad/s against Euler–Bernoulli's
/// 525: codegen/tests/fe.rs); measured FE/beam 0.688 against (ω_EB/ω_FE)² =
/// 0.698.
#[test]
fn fe_and_beam3_pendulums_swing_the_same() {
    use ffr::codegen::fe::{FeBody, FeModel, FeReference};
    use ffr::codegen::modal::Reduction;
    let fe = run(&pendulum_text());
    let beam = run(&beam_text(8));
    let max = |c: &[f64]| c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = |c: &str| {
        let (a, b) = (column(&fe, c), column(&beam, c));
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    let (dx, dy) = (diff("tip_x"), diff("tip_y"));
    let (defl_fe, defl_beam) = (
        max(column(&fe, "tip_deflection")),
        max(column(&beam, "tip_deflection")),
    );
    println!("tip |Δx| {dx:.3e}, |Δy| {dy:.3e}; deflection FE {defl_fe:.4e}, beam {defl_beam:.4e}");
    assert!(
        dx < 0.5 * defl_beam && dy < 0.5 * defl_beam,
        "{dx:e} {dy:e}"
    );
    // The quasi-static deflection ratio is the stiffness ratio, (ω_EB/ω_FE)².
    let model = FeModel::load(
        &dir().join("cantilever_nodes.csv"),
        &dir().join("cantilever_mass.mtx"),
        &dir().join("cantilever_stiffness.mtx"),
    )
    .unwrap();
    let body = FeBody::new(
        model,
        FeReference::Clamped,
        &[0, 1, 2, 33, 34, 35, 66, 67, 68],
    )
    .unwrap();
    let w_fe = body
        .reduce(&Reduction::Modal { modes: 1 })
        .unwrap()
        .frequencies[0];
    let w_eb = 1.875_104_068_711_961_f64.powi(2)
        * (E * B.powi(4) / 12.0 / (RHO * B * B * L.powi(4))).sqrt();
    let predicted = (w_eb / w_fe).powi(2);
    let measured = defl_fe / defl_beam;
    println!("deflection ratio {measured:.4}, (ω_EB/ω_FE)² {predicted:.4}");
    assert!(
        (measured / predicted - 1.0).abs() < 0.05,
        "{measured} vs {predicted}"
    );
}

/// The error loading the pendulum scene edited by `edit` (a text
/// replacement that must apply), as `line: message`.
fn refusal(from: &str, to: &str) -> (usize, String) {
    let text = pendulum_text();
    assert!(text.contains(from), "{from}");
    match load(&text.replacen(from, to, 1)) {
        Ok(_) => panic!("{from} → {to}: loaded"),
        Err(e) => {
            let line = e.location.as_ref().map_or(0, |l| l.line);
            (line, e.to_string())
        }
    }
}

/// Misuses of an FE body's keys and files: each refused with a message
/// saying what is wrong, at the line of the key to blame (line 14 is `fe`,
/// 15 `reference`, 16 `interface`, 17 `modes`), no panic.
#[test]
fn fe_scene_misuses_are_located_errors() {
    let fe = "fe = { nodes";
    let cases: &[(&str, &str, usize, &str)] = &[
        ("cantilever_nodes.csv", "missing.csv", 14, "missing.csv"),
        (
            "cantilever_mass.mtx",
            "cantilever_stiffness.mtx",
            14,
            "couples two directions",
        ),
        (
            fe,
            "shape = \"beam3\"\nfe = { nodes",
            14,
            "give `shape` (a beam) or `fe`, not both",
        ),
        (
            fe,
            "stiffening = true\nfe = { nodes",
            14,
            "geometric stiffening is not available from M and K alone",
        ),
        (
            fe,
            "params = { length = 1.0 }\nfe = { nodes",
            14,
            "properties are in its mass and stiffness matrices",
        ),
        (
            "66, 67, 68]",
            "66, 67, 500]",
            16,
            "interface node 500 out of range: the node file has 99 nodes (0 to 98)",
        ),
        ("66, 67, 68]", "66, 67, -1]", 16, "not a 0-based node index"),
        ("66, 67, 68]", "66, 67, 67]", 16, "appears twice"),
        (
            "interface = [0, 1, 2, 33, 34, 35, 66, 67, 68]",
            "",
            14,
            "a clamped FE body needs `interface",
        ),
        (
            "interface = [0, 1, 2, 33, 34, 35, 66, 67, 68]",
            "interface = [0]",
            16,
            "not positive definite",
        ),
        (
            "reference = \"clamped\"",
            "reference = \"pinned\"",
            15,
            "`reference` is \"clamped\"",
        ),
        // An interface on a free body did nothing, silently (issue 36).
        (
            "reference = \"clamped\"",
            "reference = \"free\"",
            16,
            "a free body (`reference = \"free\"`) keeps every node free and has no interface: remove `interface`",
        ),
        ("modes = 12", "", 14, "needs `modes = K`"),
        (
            "modes = 12",
            "modes = 271",
            17,
            "`modes` = 271 is more than the body has: 270 elastic modes",
        ),
        (
            "modes = 12",
            "modes = 0",
            17,
            "positive number of normal modes",
        ),
        (
            "modes = 12",
            "modes = 12\nreduction = \"craig-bampton\"",
            18,
            "needs `boundary_nodes",
        ),
        (
            "modes = 12",
            "modes = 12\nreduction = \"craig-bampton\"\nboundary_nodes = [1]",
            19,
            "boundary node 1 is an interface node",
        ),
        (
            "reference = \"clamped\"\ninterface = [0, 1, 2, 33, 34, 35, 66, 67, 68]",
            "reference = \"free\"\nreduction = \"craig-bampton\"",
            16,
            "Craig–Bampton on a free FE body is not available",
        ),
        (
            "modes = 12",
            "modes = 12\nreduction = \"craig-bampton\"\nboundary_nodes = [99]",
            17,
            "boundary node 99 out of range",
        ),
        (
            "modes = 12",
            "modes = 12\nreduction = \"craig-bampton\"\nboundary_nodes = [-1]",
            19,
            "boundary node -1 is not a 0-based node index",
        ),
        (
            "stiffness.mtx\" }",
            "stiffness.mtx\", stiffness_scale = -1.0 }",
            14,
            "`fe.stiffness_scale` must be a finite number > 0",
        ),
        (
            "stiffness.mtx\" }",
            "stiffness.mtx\", density = 1.0 }",
            14,
            "density",
        ),
        ("\"cantilever_nodes.csv\"", "\"\"", 14, "empty path"),
        ("dimension = 3", "dimension = 2", 14, "use `dimension = 3`"),
        (
            "\"bar@node=64\"",
            "\"bar@node=99\"",
            32,
            "node 99 out of range: the FE body has nodes 0 to 98",
        ),
        (
            "\"bar@node=64\"",
            "\"bar@node=x\"",
            32,
            "`node=` needs a 0-based node index",
        ),
        (
            "\"bar@node=64\"",
            "\"bar@x=1.0\"",
            32,
            "is an FE body and has no axis",
        ),
        (
            "\"bar@node=64\"",
            "\"ground@node=1\"",
            32,
            "the ground needs a point",
        ),
        (
            "modes = 12",
            "modes = 12\n[[bodies.bar.masses]]\nx = 0.5\nmass = 1.0",
            18,
            "attached masses",
        ),
    ];
    let mut wrong = Vec::new();
    for (from, to, line, message) in cases {
        let (at, e) = refusal(from, to);
        if !(e.contains(message) && at == *line && e.contains("pendulum.toml:")) {
            wrong.push(format!(
                "{from} → {to}: expected line {line}, `{message}`; got {e}"
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// A node marker is the node: at rest its position is the node's
/// coordinates in the body frame (here the global frame), with the modes'
/// displacement rows of Φ moving it; the free reference and Craig–Bampton
/// (clamped at x = 0, the tip's node 64 as boundary) load and run, and
/// conserve energy like the clamped modes (ρ∞ = 1, 0.2 s).
#[test]
fn node_markers_free_reference_and_craig_bampton_run() {
    let text = pendulum_text().replace("t_end = 1.0", "t_end = 0.2");
    let corner = text.replacen("bar@node=64", "bar@node=98", 2);
    let r = run(&corner);
    assert_eq!(column(&r, "tip_x")[0], 1.0);
    assert_eq!(column(&r, "tip_y")[0], 0.05);
    for (edit, what) in [
        (
            text.replace(
                "modes = 12",
                "modes = 12\nreduction = \"craig-bampton\"\nboundary_nodes = [64]",
            ),
            "Craig–Bampton",
        ),
        (
            text.replace(
                "reference = \"clamped\"",
                "reference = \"free\"\nstatic_modes = false",
            )
            .replace("interface = [0, 1, 2, 33, 34, 35, 66, 67, 68]", ""),
            "free",
        ),
    ] {
        let s = load(&edit).unwrap();
        println!("{what}: {:?}", s.kernels);
        let r = run(&edit);
        let d = energy_drift(&r);
        println!("{what}: energy drift {d:.3e}");
        assert!(d < 1e-5, "{what}: {d:e}");
        assert!(
            column(&r, "tip_y").last().unwrap() < &-0.1,
            "{what}: it falls"
        );
    }
}
