//! `ffr static` (issue 35): the static equilibrium under a scene's loads,
//! against closed forms (a cantilever under gravity, a hanging pendulum),
//! against the elastica at large deflection (Bisshopp & Drucker's
//! cantilever with a dead tip load, `bench/elastica/`), its text, CSV and
//! JSON, load stepping, and the errors of loads that have no equilibrium.

mod common;

use common::cli::{ffr, scene};
use std::path::Path;

/// Write `text` as `name` in `dir`; its path as a string.
fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// `ffr static ARGS --json`, parsed (panics with stderr on failure).
fn static_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["static"];
    all.extend_from_slice(args);
    all.push("--json");
    let (ok, out, err) = ffr(&all);
    assert!(ok, "{all:?}: {err}");
    serde_json::from_str(&out).unwrap()
}

fn output(js: &serde_json::Value, name: &str) -> f64 {
    js["outputs"][name]
        .as_f64()
        .unwrap_or_else(|| panic!("{name} in {js}"))
}

/// A steel cantilever (2 m, clamped) under gravity `g` along −z,
/// `elements` beam3 elements: the tip's elastic deflection in z.
fn cantilever(elements: usize, g: f64) -> String {
    format!(
        r#"description = "cantilever under gravity"
dimension = 3
gravity = [0.0, 0.0, {g:?}]
t_end = 1.0
dt = 1e-3
[bodies.beam]
shape = "beam3"
elements = {elements}
reference = "clamped"
params = {{ length = 2.0, rho = 7800.0, area = 1e-4, iy = 8.0e-12, iz = 2.0e-11, e = 2.1e11, g = 8.0e10, j = 1.5e-11 }}
[[joints]]
kind = "ground"
b = "beam"
[[outputs]]
name = "tip_z"
kind = "deflection"
at = "beam@x=2.0"
component = "z"
[[outputs]]
name = "elastic"
kind = "energy"
component = "elastic"
"#
    )
}

/// The cantilever under its own weight `q = ρ A g`: the tip deflection
/// `q L⁴/(8 E I_y)` of Euler–Bernoulli theory. Cubic Hermite elements with
/// consistent loads are exact at the nodes, so 4 elements give it to the
/// geometric nonlinearity (`(w/L)² ≈ 1e-10` here, at `g = 1e-3`): measured
/// below 1e-12 relative, asserted 1e-9. The elastic energy is half the work of
/// the load, `q² L⁵/(40 E I)`, which the stiffer mesh underestimates:
/// 1.1e-4 relative with 4 elements, 7e-6 with 8 (asserted 2e-4, 1.5e-5:
/// the fourth power of the element length).
#[test]
fn cantilever_under_gravity_equals_beam_theory() {
    let dir = tempfile::tempdir().unwrap();
    let g = -1e-3;
    let p = write(dir.path(), "c.toml", &cantilever(4, g));
    let js = static_json(&[&p]);
    let (rho, a, e, iy, l) = (7800.0, 1e-4, 2.1e11, 8.0e-12, 2.0f64);
    let q = rho * a * g.abs();
    let w = -q * l.powi(4) / (8.0 * e * iy);
    let u = q * q * l.powi(5) / (40.0 * e * iy);
    let (tip, elastic) = (output(&js, "tip_z"), output(&js, "elastic"));
    println!("tip {tip:.12e} m (theory {w:.12e}), elastic {elastic:.6e} J (theory {u:.6e})");
    assert!((tip - w).abs() <= 1e-9 * w.abs(), "{tip} vs {w}");
    assert!(elastic < u && u - elastic <= 2e-4 * u, "{elastic} vs {u}");
    let p8 = write(dir.path(), "c8.toml", &cantilever(8, g));
    let e8 = output(&static_json(&[&p8]), "elastic");
    println!("8 elements: elastic {e8:.6e} J");
    assert!(e8 < u && u - e8 <= 1.5e-5 * u, "{e8} vs {u}");
    // The JSON's keys are the contract: exactly these three (`warnings`
    // joins them only when a body turned past one frame's accuracy).
    let keys: Vec<&str> = js.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(keys, ["iterations", "outputs", "steps"]);
    let names: Vec<&str> = js["outputs"]
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.as_str())
        .collect();
    assert_eq!(names, ["elastic", "tip_z"]);
    assert_eq!(js["steps"], 1);
    assert!(js["iterations"].as_u64().unwrap() >= 1);
}

/// The text, the CSV row and `--steps K`: the text names the scene and
/// prints each output with its unit; the CSV is `t` and the outputs, the
/// JSON's numbers bit for bit; `--steps 5` takes 5 increments to the same
/// state (to 1e-12 relative: Newton's tolerance).
#[test]
fn text_csv_and_load_steps() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "c.toml", &cantilever(8, -0.01));
    let csv = dir.path().join("out.csv");
    let (ok, out, err) = ffr(&["static", &p, "--csv", csv.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(
        out.contains("(cantilever under gravity): static equilibrium at t = 0"),
        "{out}"
    );
    assert!(out.contains("  tip_z: ") && out.contains(" m\n"), "{out}");
    assert!(out.contains("  elastic: ") && out.contains(" J\n"), "{out}");
    assert!(out.contains("1 load increment, "), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    assert_eq!(lines[0], "t,tip_z,elastic");
    let row: Vec<f64> = lines[1].split(',').map(|x| x.parse().unwrap()).collect();
    // The JSON's numbers as written (serde_json's default parsing may be
    // one ulp off; `str::parse` is exact).
    let (ok, json, err) = ffr(&["static", &p, "--json"]);
    assert!(ok, "{err}");
    let raw = |name: &str| -> f64 {
        let key = format!("\"{name}\":");
        let at = json.find(&key).unwrap() + key.len();
        let end = json[at..].find([',', '}']).unwrap() + at;
        json[at..end].parse().unwrap()
    };
    assert_eq!(row, [0.0, raw("tip_z"), raw("elastic")]);
    let js: serde_json::Value = serde_json::from_str(&json).unwrap();

    let js5 = static_json(&[&p, "--steps", "5"]);
    assert_eq!(js5["steps"], 5);
    for name in ["tip_z", "elastic"] {
        let (a, b) = (output(&js, name), output(&js5, name));
        assert!((a - b).abs() <= 1e-12 * a.abs(), "{name}: {a} vs {b}");
    }
    assert!(js5["iterations"].as_u64() > js["iterations"].as_u64());
}

/// The flexible pendulum released horizontal (`scenes/pendulum.toml`)
/// hangs straight down at its static state: angle −π/2, tip at
/// `(0, −L(1 + ε))` with the small stretch `ε` of its weight, no bending,
/// nothing kinetic; the energy is the gravity energy of the hanging bar,
/// `−m g L/2` less the stretch's.
#[test]
fn pendulum_hangs_straight_down() {
    let js = static_json(&[&scene("pendulum.toml")]);
    let angle = output(&js, "angle");
    assert!(
        (angle + std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "{angle}"
    );
    let (x, y) = (output(&js, "tip_x"), output(&js, "tip_y"));
    // Stretch at the tip: ∫ ρ g (L − s)/E ds = ρ g L²/(2E).
    let stretch = 2700.0 * 9.81 / (2.0 * 7.0e10);
    assert!(x.abs() < 1e-9, "{x}");
    assert!((y + 1.0 + stretch).abs() < 1e-3 * stretch, "{y}");
    assert_eq!(output(&js, "kinetic"), 0.0);
    assert!(output(&js, "tip_deflection").abs() < 1e-12);
    let mgl2 = 2700.0 * 1e-4 * 9.81 * 0.5;
    let gravity = output(&js, "gravity");
    assert!((gravity + mgl2).abs() < 1e-5 * mgl2, "{gravity}");
}

/// Loads without an equilibrium exit non-zero with a message that says
/// so and where: a free body (a mechanism), the pendulum without gravity
/// (nothing holds its swing: the coordinate named), a torque above the
/// pendulum's weight (no equilibrium on the load path). `--steps 0` and a
/// CSV onto the scene file are refused before anything is solved.
#[test]
fn no_equilibrium_is_an_error_that_says_so() {
    let (ok, out, err) = ffr(&["static", &scene("free_floating.toml")]);
    assert!(!ok && out.is_empty(), "{out}");
    assert!(
        err.contains("free_floating.toml: no static equilibrium found at t = 0 s")
            && err.contains("mechanism"),
        "{err}"
    );

    let dir = tempfile::tempdir().unwrap();
    let base = include_str!("../../scenes/pendulum.toml");
    let unloaded = base.replace("gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]");
    assert_ne!(unloaded, base);
    let p = write(dir.path(), "unloaded.toml", &unloaded);
    let (ok, _, err) = ffr(&["static", &p, "--json"]);
    assert!(!ok, "{err}");
    assert!(
        err.contains("mechanism") && err.contains("coordinate `θ` of body `bar`"),
        "{err}"
    );

    let torque = format!(
        "{base}\n[[forces]]\nkind = \"torque\"\na = \"ground@[0.0, 0.0]\"\nb = \"bar\"\ntorque = 100.0\n"
    );
    let p = write(dir.path(), "torque.toml", &torque);
    let (ok, _, err) = ffr(&["static", &p]);
    assert!(!ok, "{err}");
    assert!(err.contains("no static equilibrium found"), "{err}");
    let (ok, _, err) = ffr(&["static", &p, "--steps", "3"]);
    assert!(!ok && err.contains("load increment"), "{err}");

    let p = scene("pendulum.toml");
    let (ok, _, err) = ffr(&["static", &p, "--steps", "0"]);
    assert!(
        !ok && err.contains("--steps") && err.contains("0 load increments"),
        "{err}"
    );
    let (ok, _, err) = ffr(&["static", &p, "--steps", "2.5"]);
    assert!(!ok && err.contains("`2.5` is not a whole number"), "{err}");
    let copy = write(dir.path(), "copy.toml", base);
    let (ok, _, err) = ffr(&["static", &copy, "--csv", &copy]);
    assert!(
        !ok && err.contains("--csv would overwrite the scene file"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&copy).unwrap(), base);
}

/// The elastica's tip displacements over L by α = PL²/EI, from
/// `bench/elastica/reference.csv` (scipy shooting, checked there against
/// Bisshopp & Drucker's table as Mattiasson 1981 gives it).
fn elastica() -> Vec<(f64, f64, f64)> {
    include_str!("../../bench/elastica/reference.csv")
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[0], v[1], v[2])
        })
        .collect()
}

/// The cantilever of `bench/elastica/convergence.py` (stiffening on): N
/// one-element bodies of length 1/N joined by `fixed` joints, the dead tip
/// load α EI/L² along −y (planar) or −z (spatial: out of the beam's x–y
/// plane, about its weak axis).
fn chain(n: usize, alpha: f64, dim: usize) -> String {
    let (e, a, i) = (1e9, 1e-4, 1e-10);
    let l = 1.0 / n as f64;
    let mut s = format!("dimension = {dim}\nt_end = 1.0\ndt = 1e-3\n");
    for k in 1..=n {
        let x0 = (k - 1) as f64 * l;
        s += &format!(
            "[bodies.b{k}]\nshape = \"beam{dim}\"\nelements = 1\nreference = \"clamped\"\nstiffening = true\n"
        );
        if dim == 2 {
            s += &format!("params = {{ length = {l:?}, rho = 1000.0, area = {a:?}, iz = {i:?}, e = {e:?} }}\nposition = [{x0:?}, 0.0]\n");
        } else {
            s += &format!(
                "params = {{ length = {l:?}, rho = 1000.0, area = {a:?}, iy = {i:?}, iz = {:?}, e = {e:?}, g = {:?}, j = {:?} }}\nposition = [{x0:?}, 0.0, 0.0]\n",
                2.0 * i,
                e / 2.6,
                2.0 * i
            );
        }
    }
    s += "[[joints]]\nkind = \"ground\"\nb = \"b1\"\n";
    for k in 1..n {
        s += &format!(
            "[[joints]]\nkind = \"fixed\"\na = \"b{k}@x={l:?}\"\nb = \"b{}@x=0.0\"\n",
            k + 1
        );
    }
    let p = alpha * e * i;
    let force = if dim == 2 {
        format!("[0.0, {:?}]", -p)
    } else {
        format!("[0.0, 0.0, {:?}]", -p)
    };
    s += &format!("[[forces]]\nkind = \"point\"\nat = \"b{n}@x={l:?}\"\nforce = {force}\n");
    for c in ["x", "y", "z"].iter().take(dim) {
        s += &format!(
            "[[outputs]]\nname = \"tip_{c}\"\nkind = \"position\"\nat = \"b{n}@x={l:?}\"\ncomponent = \"{c}\"\n"
        );
    }
    s
}

/// Bisshopp & Drucker's cantilever at α = 1, 2, 5, 10 (tip rotation up to
/// 1.43 rad) as chains of N = 4, 8, 16 bodies, planar and spatial: the
/// error of the tip displacement falls with N at a rate of at least 3 from
/// 8 to 16 bodies (measured 3.6–3.8; bench/elastica/convergence.csv) and
/// is within 1e-3 L at N = 16 (measured at most 2.3e-4 L, at α = 10).
#[test]
fn elastica_chain_converges_to_bisshopp_drucker() {
    let dir = tempfile::tempdir().unwrap();
    for dim in [2, 3] {
        for (alpha, ru, rv) in elastica() {
            let mut errs = Vec::new();
            for n in [4, 8, 16] {
                let p = write(
                    dir.path(),
                    &format!("c{dim}_{n}.toml"),
                    &chain(n, alpha, dim),
                );
                let js = static_json(&[&p]);
                let u = output(&js, "tip_x") - 1.0;
                let v = output(&js, if dim == 2 { "tip_y" } else { "tip_z" });
                if dim == 3 {
                    assert!(output(&js, "tip_y").abs() < 1e-12, "{js}");
                }
                let err = (u - ru).abs().max((v - rv).abs());
                println!("dim {dim} alpha {alpha} N {n}: u/L {u:.6} v/L {v:.6}, error {err:.3e}");
                errs.push(err);
            }
            assert!(errs[0] > errs[1] && errs[1] > errs[2], "{errs:?}");
            let rate = (errs[1] / errs[2]).log2();
            assert!(rate >= 3.0, "alpha {alpha}: rate {rate}");
            assert!(errs[2] < 1e-3, "alpha {alpha}: {errs:?}");
        }
    }
}

/// The same cantilever as one body of `n` elements run as `segments`
/// segments (`segments = N`, issue 35).
fn segmented(n: usize, segments: usize, alpha: f64, dim: usize) -> String {
    let (e, a, i) = (1e9, 1e-4, 1e-10);
    let mut s = format!(
        "dimension = {dim}\nt_end = 1.0\ndt = 1e-3\n[bodies.b]\nshape = \"beam{dim}\"\nelements = {n}\nsegments = {segments}\nreference = \"clamped\"\nstiffening = true\n"
    );
    if dim == 2 {
        s += &format!("params = {{ length = 1.0, rho = 1000.0, area = {a:?}, iz = {i:?}, e = {e:?} }}\nposition = [0.0, 0.0]\n");
    } else {
        s += &format!(
            "params = {{ length = 1.0, rho = 1000.0, area = {a:?}, iy = {i:?}, iz = {:?}, e = {e:?}, g = {:?}, j = {:?} }}\nposition = [0.0, 0.0, 0.0]\n",
            2.0 * i,
            e / 2.6,
            2.0 * i
        );
    }
    s += "[[joints]]\nkind = \"ground\"\nb = \"b\"\n";
    let p = alpha * e * i;
    let force = if dim == 2 {
        format!("[0.0, {:?}]", -p)
    } else {
        format!("[0.0, 0.0, {:?}]", -p)
    };
    s += &format!("[[forces]]\nkind = \"point\"\nat = \"b@x=1.0\"\nforce = {force}\n");
    for c in ["x", "y", "z"].iter().take(dim) {
        s += &format!(
            "[[outputs]]\nname = \"tip_{c}\"\nkind = \"position\"\nat = \"b@x=1.0\"\ncomponent = \"{c}\"\n"
        );
    }
    s
}

/// `segments = 16` on a body of 16 elements is the hand-made chain of 16
/// one-element bodies with `fixed` joints (the same equations, numbered
/// differently: the tip agrees to the solver's tolerance, 1e-9 L), planar
/// and spatial, at α = 10; the body on one frame is not a valid state there
/// (deformed beyond its length), and at α = 5 far off, with the
/// single-frame warning in `ffr static --json` (only then: the chain's
/// JSON has the three keys).
#[test]
fn segments_are_the_hand_made_chain() {
    let dir = tempfile::tempdir().unwrap();
    let (alpha, ru, rv) = *elastica().last().unwrap();
    assert_eq!(alpha, 10.0);
    for dim in [2, 3] {
        let side = if dim == 2 { "tip_y" } else { "tip_z" };
        let tip = |js: &serde_json::Value| (output(js, "tip_x"), output(js, side));
        let chain_js = static_json(&[&write(dir.path(), "chain.toml", &chain(16, alpha, dim))]);
        let seg_js = static_json(&[&write(
            dir.path(),
            "seg.toml",
            &segmented(16, 16, alpha, dim),
        )]);
        let (c, s) = (tip(&chain_js), tip(&seg_js));
        let d = (c.0 - s.0).abs().max((c.1 - s.1).abs());
        println!("dim {dim}: chain {c:?}, segments {s:?}: {d:.2e}");
        assert!(d < 1e-9, "dim {dim}: {c:?} against {s:?}");
        assert!((s.0 - 1.0 - ru).abs().max((s.1 - rv).abs()) < 1e-3, "{s:?}");
        let keys: Vec<&str> = seg_js
            .as_object()
            .unwrap()
            .keys()
            .map(|k| k.as_str())
            .collect();
        assert_eq!(keys, ["iterations", "outputs", "steps"], "{seg_js}");
        // One frame at α = 10: the stiffening model alone displaces the
        // tip by more than the body's length, not a valid state (the
        // validity check of every state, issue 36; a time run there is
        // stopped by the same bound).
        let p = write(dir.path(), "one.toml", &segmented(16, 1, alpha, dim));
        let (ok, _, e) = ffr(&["static", &p]);
        assert!(
            !ok && e.contains("the state reached is not valid")
                && e.contains("more than 1 × its length 1.0000 m"),
            "{e}"
        );
        // At α = 5 one frame is valid, far from the elastica, and warned
        // about.
        let (a5, ru5, rv5) = elastica()[2];
        assert_eq!(a5, 5.0);
        let one = static_json(&[&write(dir.path(), "one5.toml", &segmented(16, 1, a5, dim))]);
        let o = tip(&one);
        let err = (o.0 - 1.0 - ru5).abs().max((o.1 - rv5).abs());
        println!(
            "dim {dim}: one frame {o:?}, error {err:.3e}: {}",
            one["warnings"]
        );
        assert!(err > 0.05, "{err}");
        let w = one["warnings"].as_array().expect("warnings");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].as_str()
                .unwrap()
                .contains("body `b`: elastic rotation"),
            "{w:?}"
        );
    }
}

/// The FE cantilever of `tests/data/fe` (a 1 m steel box, 99 nodes, 12
/// modes) clamped to the ground by a fixed joint under gravity `g` along
/// −y, its files named by absolute path.
fn fe_cantilever(g: f64) -> String {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/fe");
    let f = |n: &str| d.join(n).display().to_string();
    format!(
        r#"description = "FE cantilever under gravity"
dimension = 3
gravity = [0.0, {g:e}, 0.0]
t_end = 0.01
dt = 1e-4

[bodies.bar]
fe = {{ nodes = "{}", mass = "{}", stiffness = "{}" }}
reference = "clamped"
interface = [0, 1, 2, 33, 34, 35, 66, 67, 68]
modes = 12

[[joints]]
kind = "fixed"
a = "ground@[0.0, 0.0, 0.0]"
b = "bar"

[[outputs]]
name = "tip_y"
kind = "deflection"
at = "bar@node=64"
component = "y"
"#,
        f("cantilever_nodes.csv"),
        f("cantilever_mass.mtx"),
        f("cantilever_stiffness.mtx")
    )
}

/// Issue 36: the validity check applies to FE bodies as to beams. Under
/// 8 × 10⁵ m/s² the 1 m FE cantilever's linear static deflection is about
/// 5 m (5.8e-5 m at 9.81 m/s², linear in g: checked below at a
/// reasonable gravity), far beyond what one floating frame with small
/// elastic coordinates describes: `ffr static` and `linearize --at
/// static` refuse the state, naming the body and the node, and a time run
/// is stopped by the divergence monitor (before, all three exited 0).
#[test]
fn an_fe_body_deformed_beyond_its_size_is_not_a_valid_state() {
    let dir = common::cli::temp_dir("static", "fe-valid");
    let mild = write(&dir, "mild.toml", &fe_cantilever(-9.81));
    let js = static_json(&[&mild]);
    let d = output(&js, "tip_y");
    assert!(d < 0.0 && d.abs() < 1e-3, "{d}");
    let heavy = write(&dir, "heavy.toml", &fe_cantilever(-8.0e5));
    // The linear model's deflection scales with g: meters at 8e5.
    assert!(d.abs() * 8.0e5 / 9.81 > 1.0);
    for args in [
        vec!["static", heavy.as_str()],
        vec!["linearize", heavy.as_str(), "--at", "static"],
    ] {
        let (ok, _, err) = ffr(&args);
        assert!(!ok, "{args:?} succeeded");
        assert!(
            err.contains("is not valid")
                && err.contains("body `bar` is deformed by")
                && err.contains("at node ")
                && err.contains("its size (nodes' bounding-box diagonal) 1.0"),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    let csv = dir.join("run.csv");
    let (ok, _, err) = ffr(&["run", &heavy, "--csv", csv.to_str().unwrap()]);
    assert!(
        !ok,
        "the run of an FE body deformed beyond its size exited 0"
    );
    assert!(
        err.contains("the run diverged") && err.contains("body `bar` is deformed by"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
