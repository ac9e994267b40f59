//! `ffr modes` and `ffr export`: frequencies against Euler–Bernoulli theory,
//! the full basis reproducing the body that `ffr invariants` evaluates from
//! its element kernels, exported files read back by readers written here
//! (independently of the writers) and compared with `ffr modes --json` and
//! `ffr invariants --json`, byte-identical output across runs, and clear
//! errors that leave no half-written file.

mod common;
use common::cli::ffr;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ffr-modes-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 2 m steel bar; `I_y ≠ I_z` so that no two bending modes coincide.
const PARAMS: [&str; 16] = [
    "--length", "2.0", "--rho", "7850", "--area", "1e-4", "--iy", "8e-10", "--iz", "9e-10", "--e",
    "2.1e11", "--g", "8.1e10", "--j", "1.5e-9",
];
const L: f64 = 2.0;
const RHO: f64 = 7850.0;
const AREA: f64 = 1e-4;
const E: f64 = 2.1e11;
/// The same bar, so slender (`I_z = 1e-14` m⁴, radius of gyration 1e-5 m)
/// that the section's rotary inertia, which the consistent mass has and
/// Euler–Bernoulli theory lacks, moves the frequencies by ~(β r/L)² ≈ 1e-10
/// (with `PARAMS` it would be ~5e-6, above the mesh error at 16 elements).
const SLENDER: [&str; 16] = [
    "--length", "2.0", "--rho", "7850", "--area", "1e-4", "--iy", "1e-14", "--iz", "1e-14", "--e",
    "2.1e11", "--g", "8.1e10", "--j", "1.5e-9",
];
const IZ_SLENDER: f64 = 1e-14;

fn body_args<'a>(cmd: &'a str, shape: &'a str, n: &'a str, reference: &'a str) -> Vec<&'a str> {
    body_args_with(cmd, shape, n, reference, &PARAMS)
}

fn body_args_with<'a>(
    cmd: &'a str,
    shape: &'a str,
    n: &'a str,
    reference: &'a str,
    params: &[&'a str],
) -> Vec<&'a str> {
    let mut a = vec![
        cmd,
        "--shape",
        shape,
        "--elements",
        n,
        "--reference",
        reference,
    ];
    a.extend(params);
    a
}

fn json_of(args: &[&str]) -> Value {
    let (ok, out, err) = ffr(args);
    assert!(ok, "{args:?}: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

fn modes_json(shape: &str, n: &str, reference: &str, count: Option<&str>) -> Value {
    modes_json_with(shape, n, reference, count, &PARAMS)
}

fn modes_json_with(
    shape: &str,
    n: &str,
    reference: &str,
    count: Option<&str>,
    params: &[&str],
) -> Value {
    let mut a = body_args_with("modes", shape, n, reference, params);
    if let Some(c) = count {
        a.extend(["--count", c]);
    }
    a.push("--json");
    json_of(&a)
}

fn invariants_json(shape: &str, n: &str, reference: &str) -> Value {
    let mut a = body_args("invariants", shape, n, reference);
    a.push("--json");
    json_of(&a)
}

fn vec_of(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn mat_of(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(vec_of).collect()
}

fn strings(v: &Value) -> Vec<String> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap().to_string())
        .collect()
}

/// `a · b` of row-major matrices.
fn mul(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<Vec<f64>> {
    (0..a.len())
        .map(|i| {
            (0..b[0].len())
                .map(|j| (0..b.len()).map(|k| a[i][k] * b[k][j]).sum())
                .collect()
        })
        .collect()
}

fn transpose(a: &[Vec<f64>]) -> Vec<Vec<f64>> {
    (0..a[0].len())
        .map(|j| a.iter().map(|r| r[j]).collect())
        .collect()
}

/// `a` and `b` equal to a few units in the last place: numbers read back
/// from a file (Rust's correctly rounded `parse`) against numbers from
/// `--json` (serde_json's default float parser, which is fast but may be off
/// by an ulp).
fn same(a: &[Vec<f64>], b: &[Vec<f64>], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (i, (r, s)) in a.iter().zip(b).enumerate() {
        assert_eq!(r.len(), s.len(), "{what}");
        for (j, (x, y)) in r.iter().zip(s).enumerate() {
            assert!(
                (x - y).abs() <= 4.0 * f64::EPSILON * x.abs().max(y.abs()),
                "{what} [{i}][{j}]: {x:e} vs {y:e}"
            );
        }
    }
}

fn max_abs(a: &[Vec<f64>]) -> f64 {
    a.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
}

fn max_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(r, s)| {
            assert_eq!(r.len(), s.len());
            r.iter().zip(s).map(|(x, y)| (x - y).abs())
        })
        .fold(0.0, f64::max)
}

/// Roots of the clamped-free and free-free beam frequency equations
/// (`cos βL cosh βL = −1` and `= +1`), to 10 decimals.
const CLAMPED_BETA_L: [f64; 3] = [1.8751040687, 4.6940911330, 7.8547574382];
const FREE_BETA_L: [f64; 2] = [4.7300407449, 7.8532046241];

/// `(βL)² √(EI/ρAL⁴)` of the slender bar.
fn euler_bernoulli(beta_l: f64) -> f64 {
    beta_l * beta_l * (E * IZ_SLENDER / (RHO * AREA * L.powi(4))).sqrt()
}

fn rel_errors(omega: &[f64], beta: &[f64]) -> Vec<f64> {
    beta.iter()
        .zip(omega)
        .map(|(b, w)| (w - euler_bernoulli(*b)).abs() / euler_bernoulli(*b))
        .collect()
}

#[test]
fn clamped_frequencies_match_euler_bernoulli_to_the_mesh_accuracy() {
    let coarse = modes_json_with("beam2", "8", "clamped", Some("3"), &SLENDER);
    let fine = modes_json_with("beam2", "16", "clamped", Some("3"), &SLENDER);
    let w8 = vec_of(&coarse["omega"]);
    let w16 = vec_of(&fine["omega"]);
    assert_eq!(w16.len(), 3);
    let e8 = rel_errors(&w8, &CLAMPED_BETA_L);
    let e16 = rel_errors(&w16, &CLAMPED_BETA_L);
    for i in 0..3 {
        // Cubic elements: the frequency error falls as h⁴ (×1/16 per halving);
        // at least ×1/8 leaves room for the pre-asymptotic range and round-off.
        assert!(e16[i] < 1e-4, "mode {}: {:e}", i + 1, e16[i]);
        assert!(
            e16[i] < e8[i] / 8.0,
            "mode {}: {:e} at 16 elements, {:e} at 8",
            i + 1,
            e16[i],
            e8[i]
        );
        // The discrete model is stiffer than the continuum: frequencies from above.
        assert!(w16[i] > euler_bernoulli(CLAMPED_BETA_L[i]));
    }
    // Hz is ω/2π.
    for (w, f) in w16.iter().zip(vec_of(&fine["hz"])) {
        assert!((f - w / std::f64::consts::TAU).abs() <= 1e-15 * f);
    }
    // The text output prints the same numbers (shortest round-trip form; the
    // JSON side may be an ulp off, see `same`).
    let (ok, text, err) = ffr(&{
        let mut a = body_args_with("modes", "beam2", "16", "clamped", &SLENDER);
        a.extend(["--count", "3"]);
        a
    });
    assert!(ok, "{err}");
    let rows: Vec<(f64, f64)> = text
        .lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 3 && f[0].parse::<usize>().is_ok())
                .then(|| (f[1].parse().unwrap(), f[2].parse().unwrap()))
        })
        .collect();
    assert_eq!(rows.len(), 3, "{text}");
    let hz = vec_of(&fine["hz"]);
    let text_rows: Vec<Vec<f64>> = rows.iter().map(|(w, f)| vec![*w, *f]).collect();
    let json_rows: Vec<Vec<f64>> = (0..3).map(|i| vec![w16[i], hz[i]]).collect();
    same(&text_rows, &json_rows, "text vs JSON");
}

#[test]
fn all_modes_reproduce_the_body_of_ffr_invariants() {
    // Every mode kept (no --count): Φ is square and invertible, and with
    // Φᵀ M Φ = I, Φ⁻¹ = Φᵀ M. The body's m_ff, K_ff and S̄ here come from
    // `ffr invariants` (generated element kernels), not from the modal code.
    let m = modes_json("beam3", "3", "clamped", None);
    let inv = invariants_json("beam3", "3", "clamped");
    let phi = mat_of(&m["phi"]);
    let nf = mat_of(&inv["mff"]).len();
    assert_eq!(nf, 18);
    assert_eq!(phi.len(), nf);
    assert_eq!(phi[0].len(), nf, "every elastic mode is kept by default");
    assert_eq!(strings(&m["dofs"]), strings(&inv["dofs"]));
    let mff = mat_of(&inv["mff"]);
    let kff = mat_of(&inv["Kff"]);
    let pt = transpose(&phi);
    let identity: Vec<Vec<f64>> = (0..nf)
        .map(|i| (0..nf).map(|j| f64::from(i == j)).collect())
        .collect();
    let ptm = mul(&pt, &mff);
    assert!(max_diff(&mul(&ptm, &phi), &identity) < 1e-11);
    // K = M Φ Λ Φᵀ M with Λ = diag(ω²), to round-off of the largest entry.
    let omega = vec_of(&m["omega"]);
    let lambda: Vec<Vec<f64>> = (0..nf)
        .map(|i| {
            (0..nf)
                .map(|j| if i == j { omega[i] * omega[i] } else { 0.0 })
                .collect()
        })
        .collect();
    let k_back = mul(&mul(&transpose(&ptm), &lambda), &ptm);
    let rel = max_diff(&k_back, &kff) / max_abs(&kff);
    assert!(rel < 1e-11, "K_ff reproduced to {rel:e}");
    // The projected S̄Φ maps back to S̄: (S̄Φ)(Φᵀ M) = S̄.
    let s_bar_phi = mat_of(&m["invariants"]["Sbar"]);
    let s_back = mul(&s_bar_phi, &ptm);
    let s_bar = mat_of(&inv["Sbar"]);
    let rel = max_diff(&s_back, &s_bar) / max_abs(&s_bar);
    assert!(rel < 1e-11, "S̄ reproduced to {rel:e}");
    // The projected mass matrix is the modal mass.
    assert_eq!(
        mat_of(&m["invariants"]["mff"]),
        mat_of(&m["modal_mass"]),
        "projected m_ff and modal mass are the same matrix"
    );
    // Frequencies ascend.
    assert!(omega.windows(2).all(|w| w[0] <= w[1]), "{omega:?}");
}

#[test]
fn free_modes_exclude_rigid_motion() {
    // A free planar beam: 51 coordinates, 3 rigid-body motions, 48 elastic modes.
    let m = modes_json_with("beam2", "16", "free", None, &SLENDER);
    let omega = vec_of(&m["omega"]);
    assert_eq!(omega.len(), 48);
    for (i, e) in rel_errors(&omega, &FREE_BETA_L).iter().enumerate() {
        assert!(*e < 1e-4, "free-free mode {}: {e:e}", i + 1);
    }
    // M-orthogonal to the translations: S̄φ = 0; to the rotation about z:
    // Ī_xy − Ī_yx = 0 (mass-normalized modes, so the scales are √m and √Θ).
    let inv = &m["invariants"];
    let mass = inv["mass"].as_f64().unwrap();
    let theta = inv["theta"]["xx"].as_f64().unwrap() + inv["theta"]["yy"].as_f64().unwrap();
    let s = mat_of(&inv["Sbar"]);
    assert!(max_abs(&s) < 1e-10 * mass.sqrt(), "{:e}", max_abs(&s));
    let (ixy, iyx) = (vec_of(&inv["Ikl"]["xy"]), vec_of(&inv["Ikl"]["yx"]));
    let rot = ixy
        .iter()
        .zip(&iyx)
        .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
    assert!(rot < 1e-10 * theta.sqrt(), "{rot:e}");
    // Asking for more than the elastic modes is refused, naming the count.
    let mut a = body_args("modes", "beam2", "16", "free");
    a.extend(["--count", "49"]);
    let (ok, _, err) = ffr(&a);
    assert!(!ok);
    assert!(err.contains("between 1 and 48"), "{err}");
    assert!(err.contains("less 3 rigid-body motions"), "{err}");
}

/// The record groups of an MBDyn modal .fem file: number → data lines
/// (comment lines, starting `**`, dropped).
fn fem_records(text: &str) -> Vec<(usize, Vec<Vec<f64>>, Vec<String>)> {
    let mut out: Vec<(usize, Vec<Vec<f64>>, Vec<String>)> = Vec::new();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("** RECORD GROUP ") {
            let n: usize = rest.split(',').next().unwrap().trim().parse().unwrap();
            out.push((n, Vec::new(), Vec::new()));
        } else if line.starts_with("**") || line.trim().is_empty() {
            continue;
        } else if let Some(last) = out.last_mut() {
            let nums: Option<Vec<f64>> = line.split_whitespace().map(|w| w.parse().ok()).collect();
            match nums {
                Some(v) => last.1.push(v),
                None => last.2.push(line.to_string()),
            }
        }
    }
    out
}

/// Translation and rotation rows of each mode at each node, from
/// `ffr modes --json` (`phi` rows labelled by `dofs`, e.g. `uy_2`).
fn nodal_rows(m: &Value, nodes: usize) -> Vec<Vec<[f64; 6]>> {
    let phi = mat_of(&m["phi"]);
    let dofs = strings(&m["dofs"]);
    let k = phi[0].len();
    let mut out = vec![vec![[0.0; 6]; nodes]; k];
    let kinds = ["ux", "uy", "uz", "rx", "ry", "rz"];
    for (i, d) in dofs.iter().enumerate() {
        let (kind, node) = d.split_once('_').unwrap();
        let c = kinds.iter().position(|x| *x == kind).unwrap();
        let node: usize = node.parse().unwrap();
        for j in 0..k {
            out[j][node][c] = phi[i][j];
        }
    }
    out
}

fn export(format: &str, shape: &str, n: &str, modes: &str, out: &Path) -> (bool, String) {
    let mut a = body_args("export", shape, n, "clamped");
    let out = out.to_str().unwrap();
    a.extend(["--format", format, "--modes", modes, "--out", out]);
    let (ok, _, err) = ffr(&a);
    (ok, err)
}

/// `tr(Θ) I − Θ` from `ffr invariants --json` (a spatial body).
fn inertia_about_origin(inv: &Value) -> [[f64; 3]; 3] {
    let ax = ["x", "y", "z"];
    let th = |k: usize, l: usize| {
        inv["theta"][format!("{}{}", ax[k], ax[l])]
            .as_f64()
            .unwrap()
    };
    let tr = th(0, 0) + th(1, 1) + th(2, 2);
    std::array::from_fn(|k| std::array::from_fn(|l| f64::from(k == l) * tr - th(k, l)))
}

fn close(a: f64, b: f64, rel: f64, scale: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * scale,
        "{what}: {a:e} vs {b:e} (scale {scale:e})"
    );
}

#[test]
fn mbdyn_fem_reads_back() {
    let dir = temp_dir("fem");
    let path = dir.join("beam.fem");
    let (ok, err) = export("mbdyn-fem", "beam3", "4", "5", &path);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    let rec = fem_records(&text);
    let get = |n: usize| &rec.iter().find(|r| r.0 == n).unwrap().1;
    let m = modes_json("beam3", "4", "clamped", Some("5"));
    let inv = invariants_json("beam3", "4", "clamped");
    // Record 1 `REV0 nodes normal attachment constraint rejected`.
    let header = &rec.iter().find(|r| r.0 == 1).unwrap().2[0];
    let h: Vec<&str> = header.split_whitespace().collect();
    assert_eq!(h, ["REV0", "5", "5", "0", "0", "0"], "{header}");
    // Nodes 0..=4 at x = jL/4.
    assert_eq!(get(2)[0], [0.0, 1.0, 2.0, 3.0, 4.0]);
    for j in 0..5 {
        assert_eq!(get(5)[j], [j as f64 * L / 4.0]);
        assert_eq!(get(6)[j], [0.0]);
    }
    // Mode shapes, modal mass and stiffness: the numbers of `ffr modes
    // --json` (17 significant digits read back to the same f64).
    let shapes = nodal_rows(&m, 5);
    let rows = get(8);
    assert_eq!(rows.len(), 5 * 5);
    for (j, shape) in shapes.iter().enumerate() {
        for node in 0..5 {
            same(
                &[rows[j * 5 + node].clone()],
                &[shape[node].to_vec()],
                &format!("mode {j} node {node}"),
            );
        }
    }
    same(get(9), &mat_of(&m["modal_mass"]), "modal mass");
    same(get(10), &mat_of(&m["modal_stiffness"]), "modal stiffness");
    // Rigid-body inertia (record 12): mass, centre of mass and the inertia
    // tensor about it, against the kernels' invariants.
    let r12 = get(12);
    let mass = inv["mass"].as_f64().unwrap();
    close(r12[0][0], mass, 1e-14, mass, "mass");
    let st0 = vec_of(&inv["St0"]);
    let c: Vec<f64> = st0.iter().map(|s| s / mass).collect();
    for k in 0..3 {
        close(r12[1][k], c[k], 1e-14, L, "centre of mass");
    }
    let j0 = inertia_about_origin(&inv);
    let c2 = c.iter().map(|x| x * x).sum::<f64>();
    for k in 0..3 {
        for l in 0..3 {
            let jc = j0[k][l] - mass * (f64::from(k == l) * c2 - c[k] * c[l]);
            close(
                r12[2 + k][l],
                jc,
                1e-12,
                j0[1][1],
                "inertia about the centre of mass",
            );
        }
    }
    // Lumped nodal masses (record 11) add up to the body's mass.
    let lumped: f64 = get(11).iter().map(|r| r[0]).sum();
    close(lumped, mass, 1e-14, mass, "lumped masses");
    let _ = std::fs::remove_dir_all(dir);
}

/// The blocks of a SID file's `modal` part: name → entries `m0(i, j)` and
/// `m1(i, j, q)`, and the `refmod` scalars.
#[derive(Default)]
struct SidBlock {
    m0: Vec<(usize, usize, f64)>,
    m1: Vec<(usize, usize, usize, f64)>,
    structure: Option<usize>,
}

fn sid_blocks(text: &str) -> (f64, Vec<(String, SidBlock)>) {
    let mut mass = f64::NAN;
    let mut blocks: Vec<(String, SidBlock)> = Vec::new();
    let mut in_frame = false;
    for line in text.lines() {
        let t = line.trim();
        let indent = line.len() - line.trim_start().len();
        if let Some(v) = t.strip_prefix("mass") {
            if let Some(v) = v.trim().strip_prefix('=') {
                mass = v.trim().parse().unwrap();
            }
        }
        if indent == 8 {
            if t == "frame" {
                in_frame = true;
            } else if t == "end frame" {
                in_frame = false;
            } else if !t.starts_with("end") && !in_frame && t != "refmod" {
                blocks.push((t.to_string(), SidBlock::default()));
            }
            continue;
        }
        if in_frame || indent != 12 {
            continue;
        }
        let Some((_, b)) = blocks.last_mut() else {
            continue;
        };
        let (lhs, rhs) = match t.split_once('=') {
            Some((l, r)) => (l.trim(), r.trim()),
            None => continue,
        };
        if lhs == "structure" {
            b.structure = Some(rhs.parse().unwrap());
        }
        let idx =
            |s: &str| -> Vec<usize> { s.split(',').map(|x| x.trim().parse().unwrap()).collect() };
        if let Some(i) = lhs.strip_prefix("m0(").and_then(|s| s.strip_suffix(')')) {
            let i = idx(i);
            b.m0.push((i[0], i[1], rhs.parse().unwrap()));
        } else if let Some(i) = lhs.strip_prefix("m1(").and_then(|s| s.strip_suffix(')')) {
            let i = idx(i);
            b.m1.push((i[0], i[1], i[2], rhs.parse().unwrap()));
        }
    }
    (mass, blocks)
}

/// A block's `m0` as a dense `rows × cols` matrix (1-based entries; a
/// symmetric block, structure 2, stores one triangle).
fn dense(b: &SidBlock, rows: usize, cols: usize) -> Vec<Vec<f64>> {
    let mut out = vec![vec![0.0; cols]; rows];
    for &(i, j, v) in &b.m0 {
        out[i - 1][j - 1] = v;
        if b.structure == Some(2) {
            out[j - 1][i - 1] = v;
        }
    }
    out
}

#[test]
fn sid_reads_back() {
    let dir = temp_dir("sid");
    let path = dir.join("beam.sid");
    let (ok, err) = export("sid", "beam3", "4", "5", &path);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    let (mass, blocks) = sid_blocks(&text);
    let block = |name: &str| {
        &blocks
            .iter()
            .find(|b| b.0 == name)
            .unwrap_or_else(|| panic!("no block {name}"))
            .1
    };
    let m = modes_json("beam3", "4", "clamped", Some("5"));
    let inv = invariants_json("beam3", "4", "clamped");
    let inv_mass = inv["mass"].as_f64().unwrap();
    close(mass, inv_mass, 1e-14, inv_mass, "refmod mass");
    // Modal mass and stiffness: the numbers of `ffr modes --json`.
    assert_eq!(block("Me").structure, Some(2));
    same(&dense(block("Me"), 5, 5), &mat_of(&m["modal_mass"]), "Me");
    same(
        &dense(block("Ke"), 5, 5),
        &mat_of(&m["modal_stiffness"]),
        "Ke",
    );
    // mdCM: m0 = S_t0, m1(k, 1, j) = (S̄Φ)_kj with S̄ from the kernels.
    let md = block("mdCM");
    let st0 = vec_of(&inv["St0"]);
    for k in 0..3 {
        close(dense(md, 3, 1)[k][0], st0[k], 1e-14, inv_mass * L, "S_t0");
    }
    let s_phi = mul(&mat_of(&inv["Sbar"]), &mat_of(&m["phi"]));
    let scale = max_abs(&s_phi);
    assert_eq!(md.m1.len(), 3 * 5);
    for &(k, c, j, v) in &md.m1 {
        assert_eq!(c, 1);
        close(v, s_phi[k - 1][j - 1], 1e-12, scale, "S̄Φ");
    }
    // J: the inertia tensor about the body-frame origin.
    let j0 = inertia_about_origin(&inv);
    let jm = dense(block("J"), 3, 3);
    for k in 0..3 {
        for l in 0..3 {
            close(jm[k][l], j0[k][l], 1e-13, j0[1][1], "J");
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn craig_bampton_from_the_command_line() {
    // Clamped at node 0, boundary node 16 (ux, uy, rz) fixed: the
    // fixed-interface modes are those of a clamped-clamped beam, whose βL are
    // the free-free roots.
    let mut a = body_args_with("modes", "beam2", "16", "clamped", &SLENDER);
    a.extend(["--boundary", "16", "--count", "2", "--json"]);
    let m = json_of(&a);
    assert_eq!(m["reduction"], "Craig-Bampton");
    let omega = vec_of(&m["omega"]);
    assert_eq!(omega.len(), 2);
    for (i, e) in rel_errors(&omega, &FREE_BETA_L).iter().enumerate() {
        assert!(*e < 1e-4, "clamped-clamped mode {}: {e:e}", i + 1);
    }
    assert_eq!(
        strings(&m["labels"]),
        [
            "mode_1",
            "mode_2",
            "constraint_ux_16",
            "constraint_uy_16",
            "constraint_rz_16"
        ]
    );
    let phi = mat_of(&m["phi"]);
    let dofs = strings(&m["dofs"]);
    let b: Vec<usize> = ["ux_16", "uy_16", "rz_16"]
        .iter()
        .map(|d| dofs.iter().position(|x| x == d).unwrap())
        .collect();
    // Normal modes vanish at the boundary; constraint mode c is 1 at its own
    // boundary coordinate and 0 at the others.
    for (c, &i) in b.iter().enumerate() {
        for j in 0..2 {
            assert_eq!(phi[i][j], 0.0);
        }
        for (c2, &i2) in b.iter().enumerate() {
            assert_eq!(phi[i2][2 + c], f64::from(c == c2));
        }
    }
    // Constraint modes are static: K_ff ψ has no interior force (K_ff from
    // `ffr invariants`, the element kernels).
    let mut inv_args = body_args_with("invariants", "beam2", "16", "clamped", &SLENDER);
    inv_args.push("--json");
    let kff = mat_of(&json_of(&inv_args)["Kff"]);
    let kpsi = mul(&kff, &phi);
    for c in 2..5 {
        let scale = (0..phi.len())
            .map(|i| {
                (0..phi.len())
                    .map(|j| (kff[i][j] * phi[j][c]).abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max);
        for (i, row) in kpsi.iter().enumerate() {
            if !b.contains(&i) {
                assert!(
                    row[c].abs() <= 1e-12 * scale,
                    "row {i} mode {c}: {:e}",
                    row[c]
                );
            }
        }
    }
    // The MBDyn header counts the constraint modes apart.
    let dir = temp_dir("cb");
    let path = dir.join("cb.fem");
    let mut e = body_args_with("export", "beam2", "16", "clamped", &SLENDER);
    e.extend(["--format", "mbdyn-fem", "--boundary", "16", "--modes", "2"]);
    e.extend(["--out", path.to_str().unwrap()]);
    let (ok, _, err) = ffr(&e);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&path).unwrap();
    let rec = fem_records(&text);
    let header = &rec.iter().find(|r| r.0 == 1).unwrap().2[0];
    assert_eq!(
        header.split_whitespace().collect::<Vec<_>>(),
        ["REV0", "17", "2", "0", "3", "0"]
    );
    // Node 0 of a clamped body has no coordinates to be a boundary.
    let (ok, _, err) = ffr(&["modes", "--elements", "4", "--boundary", "0"]);
    assert!(!ok);
    assert!(err.contains("no elastic coordinates"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn output_is_byte_identical_across_runs() {
    let dir = temp_dir("det");
    for format in ["mbdyn-fem", "sid"] {
        let (a, b) = (
            dir.join(format!("a.{format}")),
            dir.join(format!("b.{format}")),
        );
        assert!(export(format, "beam3", "6", "8", &a).0);
        assert!(export(format, "beam3", "6", "8", &b).0);
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    }
    let mut args = body_args("modes", "beam3", "6", "free");
    args.push("--json");
    let (_, first, _) = ffr(&args);
    let (_, second, _) = ffr(&args);
    assert!(!first.is_empty());
    assert_eq!(first, second);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_input_is_a_clear_error_and_leaves_no_file() {
    let dir = temp_dir("err");
    let path = dir.join("beam.fem");
    assert!(export("mbdyn-fem", "beam2", "2", "2", &path).0);
    let before = std::fs::read(&path).unwrap();
    // A failing export leaves the existing file as it was and no temporary.
    let (ok, err) = export("mbdyn-fem", "beam2", "2", "0", &path);
    assert!(!ok);
    assert!(err.contains("--modes must be between 1 and 6"), "{err}");
    let (ok, err) = export("sid", "beam2", "2", "7", &path);
    assert!(!ok);
    assert!(err.contains("found 7"), "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, [std::ffi::OsString::from("beam.fem")]);
    // A directory as --out.
    let (ok, err) = export("sid", "beam2", "2", "2", &dir);
    assert!(!ok);
    assert!(err.contains("--out"), "{err}");
    // An unknown format (clap) and an unknown shape.
    let (ok, _, err) = ffr(&["export", "--format", "nastran", "--out", "x"]);
    assert!(!ok);
    assert!(err.contains("nastran"), "{err}");
    let (ok, _, err) = ffr(&["modes", "--shape", "beam9"]);
    assert!(!ok);
    assert!(err.contains("beam9"), "{err}");
    // The lumped formalism's nodes have rotary inertia (HRZ): its modes exist.
    let (ok, out, err) = ffr(&["modes", "--elements", "2", "--formalism", "lumped"]);
    assert!(ok, "{err}");
    assert!(out.contains("lumped formalism"), "{out}");
    // A parameter the body needs at zero.
    let (ok, _, err) = ffr(&["modes", "--elements", "2", "--iz", "0"]);
    assert!(!ok);
    assert!(err.contains("iz"), "{err}");
    let (ok, _, err) = ffr(&["modes", "--count", "0"]);
    assert!(!ok);
    assert!(err.contains("--count must be between 1"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}
