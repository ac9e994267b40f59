//! Graded meshes (`KernelBody::with_nodes`, `nodes = [...]` in scene files):
//! elements of different lengths, each reading coefficients for its own
//! length.
//!
//! Independent routes: a uniform beam's mass, first and second moments are
//! `ρAL`, `ρAL²/2`, `ρAL³/3` whatever the mesh; cubic Hermite elements
//! reproduce the Euler–Bernoulli cantilever's static deflection
//! `w(x) = P x² (3L − x) / (6EI)` at every node exactly, whatever the
//! element lengths; and nodes at `e·L/N` give the equal-element body bit
//! for bit (the scene's CSV too).

use ffr::kernels::BeamSpec;
use ffr::runtime::nalgebra::{DMatrix, DVector};
use ffr::runtime::spec::{Params, Reference};
use ffr::runtime::{Body, KernelBody};
use std::path::Path;

fn params() -> Params {
    Params {
        length: 2.0,
        rho: 2700.0,
        area: 4e-4,
        iy: 3e-9,
        iz: 2e-9,
        e: 7e10,
        g: 2.6e10,
        j: 5e-9,
    }
}

/// Nodes crowded towards the root (`x = L t²`), as a blade mesh would be.
fn graded(l: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            if i == n {
                l
            } else {
                l * t * t
            }
        })
        .collect()
}

fn body(shape: &str, nodes: &[f64]) -> KernelBody<ffr::kernels::Kernels> {
    let spec = BeamSpec::new(shape, nodes.len() - 1, params());
    KernelBody::with_nodes(spec.kernels().unwrap(), params(), nodes, Reference::Clamped).unwrap()
}

#[test]
fn mass_and_moments_do_not_depend_on_the_mesh() {
    let p = params();
    let m = p.rho * p.area * p.length;
    for shape in ["beam2", "beam3"] {
        let nodes = graded(p.length, 7);
        // The nodes are graded (not equal), so the test exercises per-element
        // coefficients.
        assert!((nodes[1] - nodes[0] - (nodes[7] - nodes[6])).abs() > 0.05);
        let inv = body(shape, &nodes).invariants();
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(rel(inv.mass, m) < 1e-14, "{shape}: m = {}", inv.mass);
        assert!(rel(inv.s_t0[0], m * p.length / 2.0) < 1e-14, "{shape}");
        assert!(
            rel(inv.theta[(0, 0)], m * p.length * p.length / 3.0) < 1e-14,
            "{shape}"
        );
    }
}

#[test]
fn cantilever_static_deflection_is_exact_at_every_node_of_a_graded_mesh() {
    let p = params();
    let force = 10.0;
    for (shape, ei, w_of) in [("beam2", p.e * p.iz, "uy"), ("beam3", p.e * p.iy, "uz")] {
        let nodes = graded(p.length, 9);
        let b = body(shape, &nodes);
        let inv = b.invariants();
        let labels = &b.layout().labels;
        let nf = labels.len();
        let tip = labels
            .iter()
            .position(|l| *l == format!("{w_of}_9"))
            .unwrap_or_else(|| panic!("{shape}: {labels:?}"));
        let mut f = DVector::zeros(nf);
        f[tip] = force;
        let k: DMatrix<f64> = inv.k_ff.clone();
        let q = k
            .lu()
            .solve(&f)
            .expect("a clamped beam's stiffness is regular");
        for (i, x) in nodes.iter().enumerate().skip(1) {
            let exact = force * x * x * (3.0 * p.length - x) / (6.0 * ei);
            let at = labels
                .iter()
                .position(|l| *l == format!("{w_of}_{i}"))
                .unwrap();
            assert!(
                (q[at] - exact).abs() <= 1e-11 * exact.abs(),
                "{shape}: node {i} at x = {x}: {} vs {exact}",
                q[at]
            );
        }
    }
}

#[test]
fn nodes_at_equal_spacing_are_the_equal_mesh_bit_for_bit() {
    let p = params();
    let n = 6;
    let nodes: Vec<f64> = (0..=n).map(|e| e as f64 * p.elem_length(n)).collect();
    let spec = BeamSpec::new("beam3", n, p);
    let equal = spec.body().unwrap();
    let graded =
        KernelBody::with_nodes(spec.kernels().unwrap(), p, &nodes, Reference::Clamped).unwrap();
    let (a, b) = (equal.invariants(), graded.invariants());
    assert_eq!(a.m_ff, b.m_ff);
    assert_eq!(a.k_ff, b.k_ff);
    assert_eq!(a.s_bar, b.s_bar);
    assert_eq!(equal.nodes(), graded.nodes());
}

#[test]
fn bad_nodes_are_refused_with_what_is_wrong() {
    let p = params();
    let spec = BeamSpec::new("beam2", 2, p);
    let k = || spec.kernels().unwrap();
    for (nodes, says) in [
        (vec![0.0], "2 to"),
        (vec![0.1, 1.0, 2.0], "first node"),
        (vec![0.0, 1.0, 1.9], "last node"),
        (vec![0.0, 1.0, 1.0, 2.0], "increase strictly"),
        (vec![0.0, f64::NAN, 2.0], "finite"),
    ] {
        let e = KernelBody::with_nodes(k(), p, &nodes, Reference::Clamped)
            .err()
            .unwrap_or_else(|| panic!("{nodes:?} accepted"));
        assert!(e.to_string().contains(says), "{nodes:?}: {e}");
    }
}

/// `nodes = [0, L/4, …, L]` in a scene runs bit for bit like `elements = 4`;
/// graded nodes run too and are refused where they are wrong.
#[test]
fn scene_nodes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenes");
    let text = std::fs::read_to_string(dir.join("spin_up.toml")).unwrap();
    assert!(
        text.contains("elements = 8"),
        "the spin-up scene has 8 elements"
    );
    let l = 8.0_f64; // the KRB beam
    assert!(text.contains("length = 8.0"));
    let equal_nodes: Vec<String> = (0..=8)
        .map(|e| format!("{:?}", e as f64 * (l / 8.0)))
        .collect();
    let with_nodes = text.replace(
        "elements = 8",
        &format!("nodes = [{}]", equal_nodes.join(", ")),
    );
    let run = |t: &str| {
        let mut s = ffr::scene::from_str(t, "s.toml", &dir, &ffr::scene::DefaultKernels)
            .unwrap_or_else(|e| panic!("{e}"));
        s.t_end = 2.0;
        ffr::scene::run(&s).unwrap()
    };
    let (a, b) = (run(&text), run(&with_nodes));
    assert!(a.failed.is_none());
    assert_eq!(a.columns, b.columns);
    // A graded mesh runs.
    let graded_nodes: Vec<String> = graded(l, 8).iter().map(|x| format!("{x:?}")).collect();
    let graded_text = text.replace(
        "elements = 8",
        &format!("nodes = [{}]", graded_nodes.join(", ")),
    );
    let c = run(&graded_text);
    assert!(c.failed.is_none());
    assert_ne!(a.columns, c.columns);
    // Errors at the key.
    for (bad, says) in [
        ("nodes = [0.0, 5.0, 7.0]", "the last node is at x = 7.0"),
        ("nodes = [0.0, 6.0, 5.0, 8.0]", "must increase strictly"),
        ("nodes = [1.0, 8.0]", "the first node"),
    ] {
        let t = text.replace("elements = 8", bad);
        let e = ffr::scene::from_str(&t, "s.toml", &dir, &ffr::scene::DefaultKernels)
            .err()
            .unwrap_or_else(|| panic!("{bad} accepted"));
        let line = t.lines().position(|x| x.contains(bad)).unwrap() + 1;
        assert_eq!(e.location.as_ref().map(|l| l.line), Some(line), "{e}");
        assert!(e.message.contains(says), "{e}");
    }
    let both = text.replace("elements = 8", "elements = 8\nnodes = [0.0, 8.0]");
    let e = ffr::scene::from_str(&both, "s.toml", &dir, &ffr::scene::DefaultKernels)
        .err()
        .expect("elements and nodes together");
    assert!(e.message.contains("has `elements` and `nodes`"), "{e}");
}

/// `ffr invariants` and `ffr modes` with `--scene FILE --body NAME` print
/// what the flags describing the same body print (the spin-up beam: 8 beam2
/// elements, clamped); a graded mesh's modes come from its own elements (its
/// first frequency bounds the converged one from above, within 2e-6); wrong
/// names are errors.
#[test]
fn commands_take_a_body_from_a_scene() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/spin_up.toml");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_ffr"))
            .args(args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr,
        )
    };
    let flags = [
        "--shape",
        "beam2",
        "--elements",
        "8",
        "--length",
        "8.0",
        "--rho",
        "2766.67",
        "--area",
        "7.2968e-5",
        "--iy",
        "8.2189e-9",
        "--iz",
        "8.2189e-9",
        "--e",
        "6.8952e10",
        "--g",
        "2.6e10",
        "--j",
        "1.6438e-8",
    ];
    for cmd in ["invariants", "modes"] {
        let (ok_a, a, err_a) = run(&[&[cmd, "--json"][..], &flags[..]].concat());
        let (ok_b, b, err_b) = run(&[cmd, "--json", "--scene", scene, "--body", "beam"]);
        assert!(ok_a && ok_b, "{cmd}: {err_a} {err_b}");
        let (a, b): (serde_json::Value, serde_json::Value) = (
            serde_json::from_str(&a).unwrap(),
            serde_json::from_str(&b).unwrap(),
        );
        if cmd == "invariants" {
            // The flags' body runs on the kernels of a free frame, the
            // scene's on those it specializes: the invariants are the same
            // element integrals, assembled the same way.
            assert_eq!(a, b, "{cmd}");
        } else {
            assert_eq!(a["hz"], b["hz"], "{cmd}");
            assert_eq!(a["phi"], b["phi"], "{cmd}");
        }
    }
    // A graded mesh in a scene file (16 elements, x = L t²).
    let dir = std::env::temp_dir().join(format!("ffr-graded-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scene).unwrap();
    let nodes: Vec<String> = (0..=16)
        .map(|i| {
            let t = i as f64 / 16.0;
            format!("{:?}", if i == 16 { 8.0 } else { 8.0 * t * t })
        })
        .collect();
    let graded = text.replace("elements = 8", &format!("nodes = [{}]", nodes.join(", ")));
    let file = dir.join("graded.toml");
    std::fs::write(&file, graded).unwrap();
    let (ok, out, err) = run(&[
        "modes",
        "--json",
        "--scene",
        file.to_str().unwrap(),
        "--body",
        "beam",
    ]);
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        v["body"].as_str().unwrap().contains("16 graded elements"),
        "{}",
        v["body"]
    );
    let f1 = v["hz"][0].as_f64().unwrap();
    // The same beam on 64 equal elements (converged to about 1e-9): the
    // graded mesh is a Rayleigh–Ritz subspace of the same continuum, so its
    // frequency is above, and close.
    let mut fine = flags.to_vec();
    fine[3] = "64";
    let (ok, out, err) = run(&[&["modes", "--json"][..], &fine[..]].concat());
    assert!(ok, "{err}");
    let f64_ = serde_json::from_str::<serde_json::Value>(&out).unwrap()["hz"][0]
        .as_f64()
        .unwrap();
    assert!(f1 >= f64_ && f1 - f64_ < 2e-6 * f64_, "{f1} vs {f64_}");
    // Errors.
    let (ok, _, err) = run(&["modes", "--scene", scene, "--body", "nope"]);
    assert!(
        !ok && err.contains("no flexible body `nope`") && err.contains("beam"),
        "{err}"
    );
    let (ok, _, err) = run(&["invariants", "--scene", scene]);
    assert!(!ok && err.contains("--body"), "{err}");
    let (ok, _, err) = run(&[
        "invariants",
        "--scene",
        scene,
        "--body",
        "beam",
        "--elements",
        "3",
    ]);
    assert!(!ok && err.contains("cannot be used with"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
