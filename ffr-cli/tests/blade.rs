//! The NREL 5-MW blade (`scenes/blade_5mw.toml`, 49 section stations from
//! `scenes/data/nrel5mw_blade.csv`): a body whose sections vary along the
//! span, checked by routes that share no code with the generator.
//!
//! - Mass, first and second mass moment about the root: the exact integrals
//!   of the piecewise-linear mass per length, written out here.
//! - Clamped, non-rotating frequencies: an independent finite-element
//!   program in Python (`bench/blade/blade_fe.py`, numpy/scipy, its results
//!   committed in `bench/blade/results.json`; the variant that interpolates
//!   the twisted stiffnesses linearly between stations, as ffr does), on the
//!   same meshes.
//! - The spun-up blade's axial tip displacement against the quasi-static
//!   stretch under the centrifugal load `u(L) = ∫ N/EA dx`, `N(x) = ω² ∫_x^L
//!   m(s) (r_hub + s) ds`, integrated here.

use ffr::runtime::Body;
use ffr::scene::{self, DefaultKernels};
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

/// The CSV's columns, read here (independently of the scene reader).
fn table() -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(scenes().join("data/nrel5mw_blade.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |k: &str| header.iter().position(|h| *h == k).unwrap();
    let (x, m, ea) = (col("x"), col("mass"), col("ea"));
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
            [v[x], v[m], v[ea]]
        })
        .collect()
}

fn blade_scene(edits: &[(&str, &str)]) -> scene::Scene {
    let mut text = std::fs::read_to_string(scenes().join("blade_5mw.toml")).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "no `{from}`");
        text = text.replace(from, to);
    }
    scene::from_str(&text, "blade_5mw.toml", &scenes(), &DefaultKernels)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The `count` lowest clamped frequencies (Hz) of the scene's flexible body
/// `name`, as `ffr modes --scene` computes them.
fn frequencies(s: &scene::Scene, name: &str, count: usize) -> Vec<f64> {
    let f = s.flex.iter().find(|f| f.name == name).unwrap();
    let body = s.system.body(s.system.body_id(name).unwrap());
    ffr::modal::ReducibleBody::of_scene_body(f, body.as_ref())
        .unwrap()
        .reduce(Some(count), &[], "count")
        .unwrap()
        .frequencies
        .iter()
        .map(|w| w / std::f64::consts::TAU)
        .collect()
}

/// The independent FE program's results (`bench/blade/results.json`).
fn fe_results() -> serde_json::Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../bench/blade/results.json");
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `nodes = [...]` at the table's stations.
fn on_stations(t: &[[f64; 3]]) -> String {
    let xs: Vec<String> = t.iter().map(|r| format!("{:?}", r[0])).collect();
    format!("nodes = [{}]", xs.join(", "))
}

/// `∫ m(x) x^p dx` over the table, exactly: on each piece `m` is linear.
fn moment(t: &[[f64; 3]], p: i32) -> f64 {
    t.windows(2)
        .map(|w| {
            let ([a, ma, _], [b, mb, _]) = (w[0], w[1]);
            let slope = (mb - ma) / (b - a);
            let c = ma - slope * a; // m = c + slope x
            let int = |x: f64| {
                c * x.powi(p + 1) / (p + 1) as f64 + slope * x.powi(p + 2) / (p + 2) as f64
            };
            int(b) - int(a)
        })
        .sum()
}

#[test]
fn mass_and_moments_are_the_exact_integrals_of_the_table() {
    let t = table();
    let (m0, m1, m2) = (moment(&t, 0), moment(&t, 1), moment(&t, 2));
    // The Python FE's quadrature of the same table (bench/blade/results.json).
    let fe = fe_results();
    let i = &fe["nrel5mw"]["integrals"];
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(m0, i["mass"].as_f64().unwrap()) < 1e-12);
    assert!(rel(m1, i["first_moment"].as_f64().unwrap()) < 1e-12);
    assert!(rel(m2, i["second_moment"].as_f64().unwrap()) < 1e-12);
    let on_stations = on_stations(&t);
    // Equal elements (stations inside elements), nodes on the stations, and
    // a graded mesh that cuts the table anywhere.
    let graded: Vec<String> = (0..=11)
        .map(|i| {
            let s = i as f64 / 11.0;
            format!("{:?}", if i == 11 { 61.5 } else { 61.5 * s.powf(1.3) })
        })
        .collect();
    let graded = format!("nodes = [{}]", graded.join(", "));
    for mesh in ["elements = 16", on_stations.as_str(), graded.as_str()] {
        let s = blade_scene(&[("elements = 16", mesh)]);
        let id = s.system.body_id("blade").unwrap();
        let inv = s.system.body(id).invariants();
        assert!(rel(inv.mass, m0) < 1e-13, "{mesh}: {} vs {m0}", inv.mass);
        assert!(
            rel(inv.s_t0[0], m1) < 1e-13,
            "{mesh}: {} vs {m1}",
            inv.s_t0[0]
        );
        assert!(
            rel(inv.theta[(0, 0)], m2) < 1e-13,
            "{mesh}: {} vs {m2}",
            inv.theta[(0, 0)]
        );
    }
}

#[test]
fn clamped_frequencies_agree_with_an_independent_fe_program() {
    let fe = fe_results();
    let series = &fe["nrel5mw"]["study"]["twist_components"]["series"];
    let t = table();
    let on_stations = on_stations(&t);
    let equal16 = "elements = 16".to_string();
    let equal32 = "elements = 32".to_string();
    for (mesh, row) in [
        (&equal16, &series["equal"]["rows"][1]),
        (&equal32, &series["equal"]["rows"][2]),
        (&on_stations, &series["stations"]["rows"][0]),
    ] {
        let s = blade_scene(&[("elements = 16", mesh)]);
        let hz = frequencies(&s, "blade", 4);
        // Ascending: 1st flap, 1st edge, 2nd flap, 2nd edge.
        let fe_hz = &row["f_hz"];
        for (i, key) in ["flap1", "edge1", "flap2", "edge2"].iter().enumerate() {
            let want = fe_hz[key].as_f64().unwrap();
            assert!(
                (hz[i] - want).abs() < 1e-9 * want,
                "{}: {key}: ffr {} vs FE {want}",
                row["mesh"],
                hz[i]
            );
        }
    }
}

#[test]
fn spun_up_blade_stretches_as_the_centrifugal_load_says() {
    // 12.5 s with dt = 0.02: the spin-up ends at 10 s.
    let s = blade_scene(&[("t_end = 15.0", "t_end = 12.5"), ("dt = 0.01", "dt = 0.02")]);
    let run = scene::run(&s).unwrap();
    assert!(run.failed.is_none(), "{:?}", run.failed);
    let col = run.names.iter().position(|n| n == "tip_axial").unwrap();
    let (t, u) = (&run.t, &run.columns[col]);
    // The mean over the last 2 s (the axial mode, 14.6 Hz, rings on it).
    let tail: Vec<f64> = t
        .iter()
        .zip(u)
        .filter(|(t, _)| **t >= 10.5)
        .map(|(_, u)| *u)
        .collect();
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    // Quasi-static stretch, by the trapezoidal rule on a fine grid.
    let tab = table();
    let (omega, r_hub, l) = (1.2671090369478832_f64, 1.5, 61.5);
    let interp = |x: f64, k: usize| {
        let i = tab.partition_point(|r| r[0] <= x).clamp(1, tab.len() - 1);
        let (a, b) = (tab[i - 1], tab[i]);
        a[k] + (b[k] - a[k]) * (x - a[0]) / (b[0] - a[0])
    };
    let n = 20_000;
    let h = l / n as f64;
    let xs: Vec<f64> = (0..=n).map(|i| i as f64 * h).collect();
    let load: Vec<f64> = xs
        .iter()
        .map(|x| omega * omega * interp(*x, 1) * (r_hub + x))
        .collect();
    let mut axial = vec![0.0; n + 1]; // N(x) = ∫_x^L load
    for i in (0..n).rev() {
        axial[i] = axial[i + 1] + 0.5 * h * (load[i] + load[i + 1]);
    }
    let stretch: f64 = (0..n)
        .map(|i| 0.5 * h * (axial[i] / interp(xs[i], 2) + axial[i + 1] / interp(xs[i + 1], 2)))
        .sum();
    // 16 elements, linear in the axial direction: the stretch is reproduced
    // to the discretization's error (measured: 0.67 % with 16 elements,
    // 0.28 % with 32, the mean over 10.5–12.5 s against this integral).
    assert!(
        (mean - stretch).abs() < 0.01 * stretch,
        "tip stretch {mean} vs quasi-static {stretch}"
    );
    eprintln!(
        "tip stretch {mean} vs quasi-static {stretch}: {:.2e} relative",
        (mean - stretch) / stretch
    );
}

/// A linearly double-tapered cantilever (depth and breadth 0.04 → 0.01 m
/// over L = 1 m, steel, clamped at the large end: Mabie & Rogers,
/// "Transverse vibrations of double-tapered cantilever beams", J. Acoust.
/// Soc. Am. 51 (1972) 1771–1774, table values as quoted by code_aster's
/// validation test SDLL09, V2.02.009) given to ffr as a section table of
/// 241 stations of its exact A(x), I(x) (linear between them), planar beam2
/// on 240 elements, no rotary inertia: the frequency parameters
/// `λ_i = 2π f_i L² / (h₁ √(E/(12ρ)))` agree with the published
/// 23.289, 73.9, 165.23, 299.7, 478.1 within 5e-4 (the published values are
/// 1.4e-4 … 3.4e-4 below the exact ones, bench/blade/README.md; the
/// interpolation between stations costs about 2e-5).
#[test]
fn tapered_cantilever_matches_the_published_frequencies() {
    let (l, e, rho, h0, h1, b0, b1) = (1.0_f64, 2e11_f64, 7800.0_f64, 0.04, 0.01, 0.04, 0.01);
    let n = 240;
    let mut csv = String::from("x,mass,ea,ei_y,ei_z,gj,rho_iy,rho_iz,rho_j\n");
    for i in 0..=n {
        let x = if i == n { l } else { l * i as f64 / n as f64 };
        let (h, b) = (h0 + (h1 - h0) * x / l, b0 + (b1 - b0) * x / l);
        let (a, iz) = (b * h, b * h * h * h / 12.0);
        csv.push_str(&format!(
            "{x:?},{:?},{:?},0,{:?},0,0,0,0\n",
            rho * a,
            e * a,
            e * iz
        ));
    }
    let dir = std::env::temp_dir().join(format!("ffr-taper-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("taper.csv"), csv).unwrap();
    let text = format!(
        "dimension = 2\nt_end = 1.0\ndt = 0.01\n\n[bodies.bar]\nshape = \"beam2\"\nelements = {n}\nsections = \"taper.csv\"\n"
    );
    let s = scene::from_str(&text, "taper.toml", &dir, &DefaultKernels)
        .unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    let hz = frequencies(&s, "bar", 5);
    // Bending modes only: the axial ones are far above (EA/m).
    let published = [23.289, 73.9, 165.23, 299.7, 478.1];
    let scale = h1 / (l * l) * (e / (12.0 * rho)).sqrt();
    for (i, want) in published.iter().enumerate() {
        let lambda = hz[i] * std::f64::consts::TAU / scale;
        eprintln!(
            "mode {}: λ = {lambda:.6} (published {want}, {:+.1e})",
            i + 1,
            (lambda - want) / want
        );
        assert!(
            (lambda - want).abs() < 5e-4 * want,
            "mode {}: λ = {lambda} vs published {want}",
            i + 1
        );
    }
}

/// `params` may give the polar mass moment `rho_j` (kg m) of its own: the
/// body then runs the varying-section kernels on a one-section table. With
/// `rho_j = ρ(I_y + I_z)` its modes are those of the plain `params` (to
/// round-off); with another `rho_j` the first torsion mode of the clamped
/// bar moves to `√(GJ/rho_j)/(4L)` (32 linear torsion elements: within
/// 3e-4) and the bending modes stay.
#[test]
fn params_with_a_polar_mass_moment() {
    let (l, rho, area, iy, iz, e, g, j) = (2.0, 7850.0, 1e-4, 8e-10, 9e-10, 2.1e11, 8.1e10, 1.5e-9);
    let scene = |rho_j: Option<f64>| {
        let extra = rho_j.map_or(String::new(), |x| format!(", rho_j = {x:?}"));
        let text = format!(
            "dimension = 3\nt_end = 1.0\ndt = 0.01\n\n[bodies.bar]\nshape = \"beam3\"\nelements = 32\nparams = {{ length = {l:?}, rho = {rho:?}, area = {area:?}, iy = {iy:?}, iz = {iz:?}, e = {e:?}, g = {g:?}, j = {j:?}{extra} }}\n"
        );
        let s = scene::from_str(&text, "bar.toml", Path::new("."), &DefaultKernels)
            .unwrap_or_else(|e| panic!("{e}"));
        let hz = frequencies(&s, "bar", 12);
        (s.flex[0].sections.is_some(), hz)
    };
    let (varying_plain, plain) = scene(None);
    let (varying_same, same) = scene(Some(rho * (iy + iz)));
    assert!(!varying_plain && varying_same);
    for (a, b) in plain.iter().zip(&same) {
        assert!((a - b).abs() < 1e-10 * a, "{a} vs {b}");
    }
    // Ten times the polar moment: the torsion frequency falls by √10.
    let rho_j = 10.0 * rho * (iy + iz);
    let (_, heavy) = scene(Some(rho_j));
    let torsion = (g * j / rho_j).sqrt() / (4.0 * l);
    let closest = heavy
        .iter()
        .copied()
        .min_by(|a, b| (a - torsion).abs().total_cmp(&(b - torsion).abs()))
        .unwrap();
    assert!(
        (closest - torsion).abs() < 3e-4 * torsion,
        "{closest} vs {torsion}: {heavy:?}"
    );
    // The bending modes (those of the plain bar below the torsion mode) stay.
    let below: Vec<&f64> = plain.iter().filter(|f| **f < 0.5 * torsion).collect();
    assert!(below.len() >= 4, "{plain:?}");
    for f in below {
        assert!(
            heavy.iter().any(|h| (h - f).abs() < 1e-10 * f),
            "{f} not in {heavy:?}"
        );
    }
}

/// A section table of one uniform section in the material form is the body
/// of those `params`: it resolves to them (no section table) and runs bit
/// for bit like them on the same kernels, whatever its number of stations.
#[test]
fn a_uniform_material_table_is_its_params_bit_for_bit() {
    let text = std::fs::read_to_string(scenes().join("spin_up.toml")).unwrap();
    let params = "params = { length = 8.0, rho = 2766.67, area = 7.2968e-5, iy = 8.2189e-9, iz = 8.2189e-9, e = 6.8952e10, g = 2.6e10, j = 1.6438e-8 }";
    assert!(text.contains(params));
    let row = |x: f64| {
        format!("{{ x = {x:?}, rho = 2766.67, area = 7.2968e-5, iy = 8.2189e-9, iz = 8.2189e-9, e = 6.8952e10, g = 2.6e10, j = 1.6438e-8 }}")
    };
    let table = format!("sections = [{}, {}, {}]", row(0.0), row(3.1), row(8.0));
    let run = |text: &str| {
        let mut s = scene::from_str(text, "spin_up.toml", &scenes(), &DefaultKernels)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(s.flex[0].sections.is_none());
        s.t_end = 2.0;
        let r = scene::run(&s).unwrap();
        r.t.iter()
            .chain(r.columns.iter().flatten())
            .map(|x| x.to_bits())
            .collect::<Vec<u64>>()
    };
    let a = run(&text);
    let b = run(&text.replace(params, &table));
    assert!(a.len() > 200);
    assert_eq!(a, b);
    // A varying value (or a `twist` column) keeps the table.
    let varying = text.replace(params, &table.replacen("rho = 2766.67", "rho = 2766.68", 1));
    let s = scene::from_str(&varying, "spin_up.toml", &scenes(), &DefaultKernels).unwrap();
    assert!(s.flex[0].sections.is_some());
}
