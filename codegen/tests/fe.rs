//! Bodies from finite-element matrices (issue 23, the foundation): the
//! files read and checked, the invariants of the nodal-based FFRF, and the
//! reduction through the modal machinery.
//!
//! Checks: with a diagonal (lumped) mass matrix the invariants are the
//! lumped-mass sums of docs/theory.md, computed independently here; the
//! scikit-fem cantilever (tests/data/fe, made by bench/fe/make_cantilever.py)
//! has the box's exact mass, first moment and `Θ_kl`, its clamped
//! frequencies with every mode kept are scikit-fem/scipy's own, and
//! Craig–Bampton frequencies converge to them from above; hostile files and
//! models get errors, not panics (also under random mutations, proptest).

#![cfg(feature = "fe")]

use ffr_codegen::fe::{
    read_matrix_str, read_nodes_str, FeBody, FeError, FeModel, FeReference, MAX_FE_ORDER,
};
use ffr_codegen::modal::{modal_truncation, Invariants, Reduction};
use ffr_codegen::ModalSettings;
use nalgebra::{DMatrix, Vector3};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------
// A small hand-made model: a triangular bipyramid truss with lumped masses.

/// Base triangle in z = 0 (nodes 0, 1, 2), apexes above and below (3, 4).
fn bipyramid_nodes() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.3, 0.25, 1.0),
        Vector3::new(0.35, 0.3, -0.8),
    ]
}

const LUMPED: [f64; 5] = [2.0, 3.0, 1.5, 0.75, 1.25];

/// Nine bars (the base triangle, three from each apex): statically
/// determinate and rigid, so `K` has exactly the six rigid motions as
/// zero-energy modes. `K = Σ EA/L [n nᵀ, −n nᵀ; −n nᵀ, n nᵀ]`.
fn truss_stiffness(nodes: &[Vector3<f64>]) -> DMatrix<f64> {
    let bars = [
        (0, 1),
        (1, 2),
        (2, 0),
        (3, 0),
        (3, 1),
        (3, 2),
        (4, 0),
        (4, 1),
        (4, 2),
    ];
    let mut k = DMatrix::zeros(3 * nodes.len(), 3 * nodes.len());
    for (i, j) in bars {
        let d = nodes[j] - nodes[i];
        // |d| without overflow for far-away nodes.
        let n = (d / d.amax()).normalize();
        let len = d.dot(&n);
        let ea = 1.0e6;
        let b = n * n.transpose() * (ea / len);
        for a in 0..3 {
            for c in 0..3 {
                k[(3 * i + a, 3 * i + c)] += b[(a, c)];
                k[(3 * j + a, 3 * j + c)] += b[(a, c)];
                k[(3 * i + a, 3 * j + c)] -= b[(a, c)];
                k[(3 * j + a, 3 * i + c)] -= b[(a, c)];
            }
        }
    }
    k
}

fn lumped_mass() -> DMatrix<f64> {
    DMatrix::from_fn(15, 15, |r, c| if r == c { LUMPED[r / 3] } else { 0.0 })
}

fn bipyramid() -> FeModel {
    let nodes = bipyramid_nodes();
    let k = truss_stiffness(&nodes);
    FeModel::new(nodes, lumped_mass(), k, "mass", "stiffness").unwrap()
}

fn close(a: f64, b: f64, rel: f64, scale: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * scale,
        "{what}: {a:e} vs {b:e} (difference {:e}, allowed {:e})",
        (a - b).abs(),
        rel * scale
    );
}

/// The lumped-mass sums of docs/theory.md ("Lumped (concentrated)
/// masses"), with `N_j` the 3 × n_f selection of node j's elastic
/// coordinates: `m = Σ m_j`, `S_t0 = Σ m_j ū₀_j`, `S̄ = Σ m_j N_j`,
/// `S̄_kl = Σ m_j N_jkᵀ N_jl`, `Ī_kl = Σ m_j ū₀_jk N_jl`,
/// `Θ_kl = Σ m_j ū₀_jk ū₀_jl`; compared with the body's.
fn check_lumped(body: &FeBody) {
    let nodes = bipyramid_nodes();
    let nf = body.nf();
    let n_j = |j: usize| {
        DMatrix::from_fn(
            3,
            nf,
            |k, a| {
                if body.dofs[a] == 3 * j + k {
                    1.0
                } else {
                    0.0
                }
            },
        )
    };
    let mut m = 0.0;
    let mut s_t0 = Vector3::zeros();
    let mut theta = nalgebra::Matrix3::zeros();
    let mut s_bar = DMatrix::zeros(3, nf);
    let mut s_kl: Vec<DMatrix<f64>> = vec![DMatrix::zeros(nf, nf); 9];
    let mut i_kl: Vec<DMatrix<f64>> = vec![DMatrix::zeros(1, nf); 9];
    for (j, p) in nodes.iter().enumerate() {
        let mj = LUMPED[j];
        let nj = n_j(j);
        m += mj;
        s_t0 += p * mj;
        theta += p * p.transpose() * mj;
        s_bar += &nj * mj;
        for k in 0..3 {
            for l in 0..3 {
                s_kl[3 * k + l] += nj.row(k).transpose() * nj.row(l) * mj;
                i_kl[3 * k + l] += nj.row(l) * (mj * p[k]);
            }
        }
    }
    let inv = &body.invariants;
    let tol = 1e-14;
    close(inv.mass, m, tol, m, "m");
    for k in 0..3 {
        close(inv.s_t0[k], s_t0[k], tol, m, "S_t0");
        for l in 0..3 {
            close(inv.theta[(k, l)], theta[(k, l)], tol, theta.amax(), "Θ");
            assert!(
                (&inv.s_kl[k][l] - &s_kl[3 * k + l]).amax() <= tol * m,
                "S̄_{k}{l}"
            );
            assert!(
                (inv.i_kl[k][l].transpose() - &i_kl[3 * k + l]).amax() <= tol * theta.amax(),
                "Ī_{k}{l}"
            );
        }
    }
    assert!((&inv.s_bar - &s_bar).amax() <= tol * m, "S̄");
    // m_ff = Σ_k S̄_kk is the lumped mass on the elastic coordinates.
    for a in 0..nf {
        for b in 0..nf {
            let want = if a == b {
                LUMPED[body.dofs[a] / 3]
            } else {
                0.0
            };
            assert_eq!(inv.m_ff[(a, b)], want, "m_ff[{a}][{b}]");
        }
    }
}

#[test]
fn lumped_mass_invariants_are_the_lumped_sums() {
    let clamped = FeBody::new(bipyramid(), FeReference::Clamped, &[0, 1, 2]).unwrap();
    assert_eq!(clamped.nf(), 6);
    assert_eq!(
        clamped.dof_names,
        ["ux_3", "uy_3", "uz_3", "ux_4", "uy_4", "uz_4"]
    );
    check_lumped(&clamped);
    let free = FeBody::new(bipyramid(), FeReference::Free, &[]).unwrap();
    assert_eq!(free.nf(), 15);
    check_lumped(&free);
    // The stiffness on the elastic coordinates is K's.
    let k = truss_stiffness(&bipyramid_nodes());
    assert_eq!(clamped.invariants.k_ff, k.view((9, 9), (6, 6)).into_owned());
}

#[test]
fn free_truss_modes_are_mass_orthogonal_to_rigid_motions() {
    let free = FeBody::new(bipyramid(), FeReference::Free, &[]).unwrap();
    assert_eq!(free.available_modes(), 9);
    let basis = free.reduce(&Reduction::Modal { modes: 9 }).unwrap();
    let r = free.rigid_motions().unwrap();
    let cross = r.transpose() * &free.invariants.m_ff * &basis.phi;
    assert!(cross.amax() < 1e-12, "Rᵀ M Φ = {:e}", cross.amax());
    assert!(basis.frequencies.iter().all(|w| *w > 0.0));
    // Asking for a rigid mode too is refused.
    assert!(free.reduce(&Reduction::Modal { modes: 10 }).is_err());
}

// ---------------------------------------------------------------------------
// The scikit-fem cantilever.

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/fe")
        .join(name)
}

/// bench/fe/make_cantilever.py: steel box L × B × H along x, y, z, the
/// x = 0 face clamped.
const RHO: f64 = 7850.0;
const L: f64 = 1.0;
const B: f64 = 0.1;
const H: f64 = 0.1;
const E: f64 = 210e9;

fn cantilever() -> FeModel {
    FeModel::load(
        &data("cantilever_nodes.csv"),
        &data("cantilever_mass.mtx"),
        &data("cantilever_stiffness.mtx"),
    )
    .unwrap()
}

/// One column of a small CSV file with a header.
fn column(name: &str, col: &str) -> Vec<String> {
    let mut r = csv::Reader::from_path(data(name)).unwrap();
    let i = r.headers().unwrap().iter().position(|h| h == col).unwrap();
    r.records().map(|rec| rec.unwrap()[i].to_string()).collect()
}

fn interface() -> Vec<usize> {
    column("cantilever_interface.csv", "node")
        .iter()
        .map(|s| s.parse().unwrap())
        .collect()
}

#[test]
fn cantilever_mass_moments_are_the_box_exact_values() {
    let model = cantilever();
    assert_eq!(model.len(), 99);
    // The node file spans the box.
    for k in 0..3 {
        let lo = model.nodes.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
        let hi = model.nodes.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
        assert_eq!(hi - lo, [L, B, H][k]);
    }
    // The trilinear hexahedra reproduce the box exactly and x_k x_l is in
    // the span of products of their shape functions, so 1ᵀ M_s 1, 1ᵀ M_s x̄
    // and x̄_kᵀ M_s x̄_l are the exact integrals, up to the round-off of
    // assembly and of the 17-digit files.
    let v = L * B * H;
    let mass = RHO * v;
    let first = [RHO * v * L / 2.0, 0.0, 0.0];
    // ∫ρ x² dV, ∫ρ y² dV, ∫ρ z² dV over [0, L] × [−B/2, B/2] × [−H/2, H/2].
    let second = [
        RHO * B * H * L.powi(3) / 3.0,
        RHO * L * H * B.powi(3) / 12.0,
        RHO * L * B * H.powi(3) / 12.0,
    ];
    for reference in [FeReference::Clamped, FeReference::Free] {
        let body = FeBody::new(model.clone(), reference, &interface()).unwrap();
        let inv = &body.invariants;
        close(inv.mass, mass, 1e-14, mass, "m");
        for k in 0..3 {
            close(inv.s_t0[k], first[k], 1e-14, first[0], "S_t0");
            for l in 0..3 {
                let want = if k == l { second[k] } else { 0.0 };
                close(inv.theta[(k, l)], want, 1e-14, second[0], "Θ");
            }
        }
        // The diagonal Θ_yy, Θ_zz to round-off relative to themselves.
        close(inv.theta[(1, 1)], second[1], 1e-14, second[1], "Θ_yy");
        close(inv.theta[(2, 2)], second[2], 1e-14, second[2], "Θ_zz");
    }
    // A free body's S̄ row k sums to m, its Ī_kl over the direction-l
    // coordinates to S_t0,k (1ᵀ M_s 1 and 1ᵀ M_s x̄_k once more).
    let free = FeBody::new(model, FeReference::Free, &[]).unwrap();
    let inv = &free.invariants;
    for k in 0..3 {
        close(inv.s_bar.row(k).sum(), mass, 1e-14, mass, "Σ S̄");
        for l in 0..3 {
            close(inv.i_kl[k][l].sum(), first[k], 1e-14, first[0], "Σ Ī_kl");
        }
    }
}

/// The reference eigenvalues λ = ω² of the clamped model, from
/// scipy.linalg.eigh on the same matrices.
fn reference_lambda() -> Vec<f64> {
    column("cantilever_eigen.csv", "lambda")
        .iter()
        .map(|s| s.parse().unwrap())
        .collect()
}

/// Every mode kept: the reduction's frequencies are scipy's eigenvalues to
/// a relative 1e-9. (This caught nalgebra's `SymmetricEigen` returning two
/// eigenvectors with their eigenvalues swapped, modes 10 and 12; see
/// `repair_pairing` in codegen/src/modal/basis.rs.)
#[test]
fn cantilever_clamped_frequencies_are_the_fe_codes_own() {
    let body = FeBody::new(cantilever(), FeReference::Clamped, &interface()).unwrap();
    assert_eq!(body.nf(), 270);
    let want = reference_lambda();
    assert_eq!(want.len(), body.available_modes());
    let basis = body
        .reduce(&Reduction::Modal {
            modes: body.available_modes(),
        })
        .unwrap();
    for (i, (w, l)) in basis.frequencies.iter().zip(&want).enumerate() {
        close(w * w, *l, 1e-9, *l, &format!("λ_{}", i + 1));
    }
}

/// The free-free body: modal truncation with every elastic mode (the six
/// rigid motions removed exactly, in the mass-orthogonal complement) gives
/// scipy's eigenvalues of the full `(K, M)` less its six rigid ones, to a
/// relative 1e-9; the modes are mass-orthogonal to the rigid motions.
#[test]
fn cantilever_free_frequencies_are_the_fe_codes_own() {
    let body = FeBody::new(cantilever(), FeReference::Free, &[]).unwrap();
    assert_eq!(body.nf(), 297);
    let want: Vec<f64> = column("cantilever_eigen_free.csv", "lambda")
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
    assert_eq!(want.len(), body.available_modes());
    let basis = body
        .reduce(&Reduction::Modal {
            modes: body.available_modes(),
        })
        .unwrap();
    for (i, (w, l)) in basis.frequencies.iter().zip(&want).enumerate() {
        close(w * w, *l, 1e-9, *l, &format!("free λ_{}", i + 1));
    }
    let r = body.rigid_motions().unwrap();
    let cross = r.transpose() * &body.invariants.m_ff * &basis.phi;
    assert!(
        cross.amax() < 1e-10 * body.invariants.mass.sqrt(),
        "Rᵀ M Φ = {:e}",
        cross.amax()
    );
}

/// The lowest bending frequency against Euler–Bernoulli,
/// `ω₁ = 1.875104² √(E I / (ρ A L⁴))` with `I = B H³/12`: about 525 rad/s.
/// The FE model gives 628.6 rad/s, 19.7 % higher: the trilinear hexahedra
/// are fully integrated and shear-lock in bending (parasitic shear strain,
/// two elements through the depth, 10 along the span), which stiffens
/// far more than the 3D effects soften (shear deformation and rotary inertia
/// at L/H = 10 lower ω₁ by about 1 %; the clamped face's Poisson constraint
/// raises it slightly). So only a band is asserted: above 0.97 × EB (the
/// continuum's Timoshenko-like softening is a few per cent at most, and a
/// conforming displacement model is stiffer than the continuum) and below
/// 1.3 × EB (a coarse but not broken mesh); the y and z bending modes agree
/// (square section).
#[test]
fn cantilever_first_bending_frequency_near_euler_bernoulli() {
    let body = FeBody::new(cantilever(), FeReference::Clamped, &interface()).unwrap();
    let basis = body.reduce(&Reduction::Modal { modes: 2 }).unwrap();
    let i = B * H.powi(3) / 12.0;
    let eb = 1.875_104_068_711_961_f64.powi(2) * (E * i / (RHO * B * H * L.powi(4))).sqrt();
    let ratio = basis.frequencies[0] / eb;
    assert!(
        (0.97..1.3).contains(&ratio),
        "ω₁ = {} rad/s, Euler–Bernoulli {eb} rad/s, ratio {ratio}",
        basis.frequencies[0]
    );
    close(
        basis.frequencies[0],
        basis.frequencies[1],
        1e-9,
        eb,
        "ω₁ (y) vs ω₂ (z)",
    );
}

/// Craig–Bampton with the tip face (x = L) as boundary: the reduced
/// model's frequencies are Rayleigh–Ritz upper bounds of the clamped
/// model's, falling as fixed-interface modes are added, and with every
/// interior mode the reduced model is the full one.
#[test]
fn cantilever_craig_bampton_converges_from_above() {
    let body = FeBody::new(cantilever(), FeReference::Clamped, &interface()).unwrap();
    let tip: Vec<usize> = (0..body.model.len())
        .filter(|&i| body.model.nodes[i][0] == L)
        .collect();
    assert_eq!(tip.len(), 9);
    let want = reference_lambda();
    let lowest = 6;
    let interior = body.nf() - 3 * tip.len();
    let mut previous = vec![f64::INFINITY; lowest];
    for modes in [0, 1, 2, 4, 8, 16, 32, 64, 128, interior] {
        let basis = body
            .reduce(&Reduction::CraigBampton {
                boundary_nodes: tip.clone(),
                modes,
            })
            .unwrap();
        // The reduced eigenproblem through the same solver.
        let reduced =
            modal_truncation(&basis.modal_mass, &basis.modal_stiffness, lowest, None).unwrap();
        for j in 0..lowest {
            let l = reduced.frequencies[j].powi(2);
            assert!(
                l >= want[j] * (1.0 - 1e-9),
                "{modes} modes: λ_{} = {l:e} below the full model's {:e}",
                j + 1,
                want[j]
            );
            assert!(
                l <= previous[j] * (1.0 + 1e-9),
                "{modes} modes: λ_{} = {l:e} rose from {:e}",
                j + 1,
                previous[j]
            );
            previous[j] = l;
            if modes == interior {
                close(l, want[j], 1e-9, want[j], "λ with every interior mode");
            }
        }
    }
}

#[test]
fn cantilever_projected_invariants_keep_mass_and_moments() {
    let body = FeBody::new(cantilever(), FeReference::Clamped, &interface()).unwrap();
    let basis = body.reduce(&Reduction::Modal { modes: 8 }).unwrap();
    let p: Invariants = body.invariants.project(&basis.phi);
    assert_eq!(p.nf(), 8);
    assert_eq!(p.mass, body.invariants.mass);
    assert!((p.m_ff - DMatrix::<f64>::identity(8, 8)).amax() < 1e-12);
    for (j, w) in basis.frequencies.iter().enumerate() {
        close(p.k_ff[(j, j)], w * w, 1e-12, w * w, "Φᵀ K Φ");
    }
}

/// The reduced body a scene's settings make: with static modes the basis
/// holds the static response to the frame's inertia loads, so the reduced
/// body's static deflection under a uniform acceleration along y (gravity)
/// is the full body's to round-off; four normal modes alone miss it by far
/// more. Modal damping `2 ζ ω_i` on the normal modes.
#[test]
fn cantilever_modal_model_with_static_modes_and_damping() {
    let body = FeBody::new(cantilever(), FeReference::Clamped, &interface()).unwrap();
    let inv = &body.invariants;
    let f: nalgebra::DVector<f64> = inv.s_bar.row(1).transpose();
    let full = nalgebra::Cholesky::new(inv.k_ff.clone()).unwrap().solve(&f);
    let static_error = |settings: &ModalSettings| {
        let model = body.modal_model(settings).unwrap();
        let phi = &model.basis.phi;
        let kr = &model.projected.k_ff;
        let eta = nalgebra::Cholesky::new(kr.clone())
            .unwrap()
            .solve(&(phi.transpose() * &f));
        ((phi * eta - &full).norm() / full.norm(), model)
    };
    let with = ModalSettings {
        modes: 4,
        boundary: Vec::new(),
        static_modes: true,
        damping: vec![0.02],
    };
    let (err_with, model) = static_error(&with);
    assert!(err_with < 1e-9, "with static modes: {err_with:e}");
    assert_eq!(model.normal, 4);
    assert!(model.len() > 4, "static modes added");
    assert!(model.basis.labels.iter().any(|l| l == "static_a_y"));
    let d = model.damping.as_ref().unwrap();
    for (i, w) in model.basis.frequencies.iter().enumerate() {
        close(d[(i, i)], 2.0 * 0.02 * w, 1e-12, 2.0 * 0.02 * w, "D_ii");
    }
    let without = ModalSettings {
        static_modes: false,
        ..with
    };
    let (err_without, model) = static_error(&without);
    assert_eq!(model.len(), 4);
    assert!(
        err_without > 1e-4,
        "four normal modes alone: {err_without:e}"
    );
}

// ---------------------------------------------------------------------------
// Hostile files and models.

fn tmp(name: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fe");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn mtx_symmetric(a: &DMatrix<f64>) -> String {
    let n = a.nrows();
    let mut entries = Vec::new();
    for j in 0..n {
        for i in j..n {
            if a[(i, j)] != 0.0 {
                entries.push(format!("{} {} {:e}", i + 1, j + 1, a[(i, j)]));
            }
        }
    }
    format!(
        "%%MatrixMarket matrix coordinate real symmetric\n% test\n{n} {n} {}\n{}\n",
        entries.len(),
        entries.join("\n")
    )
}

fn nodes_csv(nodes: &[Vector3<f64>]) -> String {
    let mut s = String::from("x,y,z\n");
    for p in nodes {
        s += &format!("{:e},{:e},{:e}\n", p[0], p[1], p[2]);
    }
    s
}

/// Load the bipyramid with the given file texts (`None`: the good one).
fn load(
    tag: &str,
    nodes: Option<&str>,
    mass: Option<&str>,
    stiffness: Option<&str>,
) -> Result<FeModel, FeError> {
    let good_nodes = nodes_csv(&bipyramid_nodes());
    let good_m = mtx_symmetric(&lumped_mass());
    let good_k = mtx_symmetric(&truss_stiffness(&bipyramid_nodes()));
    FeModel::load(
        &tmp(&format!("{tag}_nodes.csv"), nodes.unwrap_or(&good_nodes)),
        &tmp(&format!("{tag}_mass.mtx"), mass.unwrap_or(&good_m)),
        &tmp(
            &format!("{tag}_stiffness.mtx"),
            stiffness.unwrap_or(&good_k),
        ),
    )
}

fn err(r: Result<FeModel, FeError>) -> String {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_good_files_load() {
    let m = load("good", None, None, None).unwrap();
    assert_eq!(m.len(), 5);
    assert_eq!(m.mass, lumped_mass());
}

#[test]
fn hostile_matrix_files_are_refused_with_located_errors() {
    let m = lumped_mass();
    let good = mtx_symmetric(&m);
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "wrong_size",
            good.replacen("15 15 15", "12 12 12", 1),
            "must be 15 × 15 (3 per node)",
        ),
        (
            "nan",
            good.replacen("4 4 3e0", "4 4 NaN", 1),
            "_mass.mtx:7:5: mass matrix entry (4, 4) is NaN (`NaN`): NaN is not a finite number",
        ),
        (
            "inf",
            good.replacen("4 4 3e0", "4 4 1e999", 1),
            "entry (4, 4) is inf",
        ),
        (
            "huge_size",
            good.replacen(
                "15 15 15",
                "99999999999999999999999 99999999999999999999999 15",
                1,
            ),
            "_mass.mtx:3:1: the size line must be three integers",
        ),
        (
            "large_size",
            good.replacen("15 15 15", "1000000 1000000 15", 1),
            "larger than order 1536",
        ),
        (
            "huge_entries",
            good.replacen("15 15 15", "15 15 1000000000000", 1),
            "declares 1000000000000 entries",
        ),
        (
            "huge_index",
            good.replacen("4 4 3e0", "4 99999999999999999999999 3e0", 1),
            "_mass.mtx:7:3: column index `99999999999999999999999` out of range",
        ),
        (
            "glued_index",
            good.replacen("4 4 3e0", "4 99999999999999999999999.5", 1),
            "_mass.mtx:7:1: an entry is `row column value`, three fields; found 2",
        ),
        (
            "glued_row",
            good.replacen("4 4 3e0", "99999999999999999999999.5 4 3e0", 1),
            "_mass.mtx:7:1: row index `99999999999999999999999.5` is not a whole number",
        ),
        (
            "zero_index",
            good.replacen("4 4 3e0", "0 4 3e0", 1),
            "_mass.mtx:7:1: row index `0` out of range",
        ),
        (
            "upper",
            good.replacen("4 4 3e0", "4 5 3e0", 1),
            "_mass.mtx:7:1: entry (4, 5) above the diagonal",
        ),
        (
            "too_many",
            good.replacen("15 15 15", "15 15 14", 1),
            "more entries than the 14",
        ),
        (
            "too_few",
            good.replacen("15 15 15", "15 15 16", 1),
            "has 15 entries, the size line declares 16",
        ),
        (
            "repeated",
            good.replacen("5 5 3e0", "4 4 3e0", 1),
            "entry (4, 4) given twice",
        ),
        (
            "banner",
            good.replacen("coordinate real", "array real", 1),
            "_mass.mtx:1:1: the mass matrix must be a Matrix Market file",
        ),
        (
            "complex",
            good.replacen("coordinate real", "coordinate complex", 1),
            "must be a Matrix Market file",
        ),
        (
            "garbage",
            good.replacen("4 4 3e0", "4 4 three", 1),
            "_mass.mtx:7:5: mass matrix entry (4, 4): `three` is not a number",
        ),
        ("empty", String::new(), "is empty"),
        (
            "minus_nan",
            good.replacen("4 4 3e0", "4 4 -NaN", 1),
            "entry (4, 4) is NaN",
        ),
        (
            "plus_inf",
            good.replacen("4 4 3e0", "4 4 +inf", 1),
            "entry (4, 4) is inf",
        ),
        (
            "half_exponent",
            good.replacen("4 4 3e0", "4 4 3e", 1),
            "`3e` is not a number",
        ),
        // Issue 36: a line of terminal escapes reached the terminal raw in
        // a 7-line parser dump; now one line, escaped.
        (
            "escapes",
            good.replacen("4 4 3e0", "4 4 \u{1b}]0;owned\u{7}\u{1b}[2J", 1),
            "_mass.mtx:7:5: mass matrix entry (4, 4): `\\u{1b}]0;owned",
        ),
        (
            "one_field",
            good.replacen("4 4 3e0", "4", 1),
            "_mass.mtx:7:1: an entry is `row column value`, three fields; found 1",
        ),
        (
            "four_fields",
            good.replacen("4 4 3e0", "4 4 3e0 1", 1),
            "three fields; found 4 in `4 4 3e0 1`",
        ),
    ];
    for (tag, text, want) in cases {
        let e = err(load(tag, None, Some(&text), None));
        assert!(e.contains(want), "{tag}: {e}");
        assert!(
            !e.contains('\n') && !e.chars().any(|c| c.is_control()),
            "{tag}: one line, no control characters: {e:?}"
        );
    }
}

#[test]
fn unusual_but_valid_numbers_are_read() {
    let good = mtx_symmetric(&lumped_mass());
    let text = good
        .replacen("4 4 3e0", "4 4 3.e0", 1)
        .replacen("1 1 2e0", "1 1 +2.0", 1)
        .replacen("15 15 1.25e0", "15 15 .125E+1", 1)
        .replace('\n', "\r\n");
    for token in ["3.e0", "+2.0", ".125E+1", "\r\n"] {
        assert!(text.contains(token), "{token}");
    }
    let m = load("unusual", None, Some(&text), None).unwrap();
    assert_eq!(m.mass, lumped_mass());
}

#[test]
fn asymmetric_general_files_are_refused_and_symmetric_ones_kept() {
    let k = truss_stiffness(&bipyramid_nodes());
    let general = |a: &DMatrix<f64>| {
        let n = a.nrows();
        let mut entries = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if a[(i, j)] != 0.0 {
                    entries.push(format!("{} {} {:e}", i + 1, j + 1, a[(i, j)]));
                }
            }
        }
        format!(
            "%%MatrixMarket matrix coordinate real general\n{n} {n} {}\n{}\n",
            entries.len(),
            entries.join("\n")
        )
    };
    let ok = load("general", None, None, Some(&general(&k))).unwrap();
    assert_eq!(ok.stiffness, k);
    let mut bad = k.clone();
    bad[(0, 3)] += 1.0;
    let e = err(load("asymmetric", None, None, Some(&general(&bad))));
    assert!(
        e.contains("the stiffness matrix is not symmetric: entries (4, 1)"),
        "{e}"
    );
}

#[test]
fn indefinite_and_ill_formed_models_are_refused() {
    let nodes = bipyramid_nodes();
    let k = truss_stiffness(&nodes);
    // Negative mass.
    let mut m = lumped_mass();
    for a in 0..3 {
        m[(6 + a, 6 + a)] = -1.5;
    }
    let e = err(load("neg_mass", None, Some(&mtx_symmetric(&m)), None));
    assert!(e.contains("mass matrix is not positive definite"), "{e}");
    // Indefinite stiffness: −K resists nothing rigid either, but is
    // negative on the rest.
    let e = err(load("neg_k", None, None, Some(&mtx_symmetric(&(-&k)))));
    assert!(e.contains("not positive semi-definite"), "{e}");
    // A support (a grounded spring) resists a rigid motion.
    let mut grounded = k.clone();
    grounded[(0, 0)] += 1e3;
    let e = err(load(
        "grounded",
        None,
        None,
        Some(&mtx_symmetric(&grounded)),
    ));
    assert!(e.contains("resists a rigid translation along x"), "{e}");
    assert!(e.contains("grounded_stiffness.mtx"), "{e}");
    // A node file whose rows are not K's nodes (two nodes swapped): K is
    // free in translation, so the node file is to blame, not supports in K
    // (issue 36: the message named K and said to export without supports).
    let mut swapped = nodes.clone();
    swapped.swap(0, 4);
    let e = err(load("swapped", Some(&nodes_csv(&swapped)), None, None));
    assert!(
        e.starts_with(&format!(
            "{}: the nodes do not match the stiffness matrix: K is free in translation but resists the rigid rotation about",
            Path::new(env!("CARGO_TARGET_TMPDIR"))
                .join("fe/swapped_nodes.csv")
                .display()
        )),
        "{e}"
    );
    assert!(!e.contains("without supports"), "{e}");
    // Unequal direction blocks and coupled directions.
    let mut m = lumped_mass();
    m[(1, 1)] = 2.5;
    let e = err(load("blocks", None, Some(&mtx_symmetric(&m)), None));
    assert!(
        e.contains("entry (2, 2) (uy_0, uy_0)")
            && e.contains("direction blocks of M must be equal"),
        "{e}"
    );
    let mut m = lumped_mass();
    m[(1, 0)] = 0.1;
    m[(0, 1)] = 0.1;
    let e = err(load("coupled", None, Some(&mtx_symmetric(&m)), None));
    assert!(e.contains("couples two directions"), "{e}");
    // Nodes on a line.
    let line: Vec<Vector3<f64>> = (0..5).map(|i| Vector3::new(i as f64, 0.0, 0.0)).collect();
    let e = FeModel::new(line, lumped_mass(), k.clone(), "m", "k").unwrap_err();
    assert!(e.to_string().contains("lie on one line"), "{e}");
    // Entries whose norm overflows f64.
    let e = err(load(
        "huge_mass",
        None,
        Some(&mtx_symmetric(&(lumped_mass() * 1e200))),
        None,
    ));
    assert!(e.contains("the mass matrix's entries are too large"), "{e}");
    // Coordinates whose second moments overflow f64.
    let far: Vec<Vector3<f64>> = nodes.iter().map(|p| p * 1e200).collect();
    let k_far = truss_stiffness(&far);
    let model = FeModel::new(far, lumped_mass(), k_far, "m", "k").unwrap();
    let e = FeBody::new(model, FeReference::Free, &[]).unwrap_err();
    assert!(e.to_string().contains("the invariants overflow f64"), "{e}");
    // Matrices of the wrong order given directly.
    let e = FeModel::new(
        nodes.clone(),
        DMatrix::identity(12, 12),
        k.clone(),
        "m",
        "k",
    )
    .unwrap_err();
    assert!(e.to_string().contains("must be 15 × 15"), "{e}");
}

#[test]
fn hostile_node_files_are_refused() {
    let cases = [
        ("hdr", "x,y,w\n0,0,0\n", "header must be `x,y,z`"),
        (
            "nan",
            "x,y,z\n0,0,0\n1,0,0\n0,1,0\n0.3,NaN,1\n0.3,0.3,-1\n",
            "_nodes.csv:5:1: node 3: `y` must be a finite number",
        ),
        (
            "short",
            "x,y,z\n0,0,0\n1,0\n",
            "_nodes.csv:3:1: a row has 2 fields",
        ),
        ("none", "x,y,z\n", "has no nodes"),
        (
            "count",
            "x,y,z\n0,0,0\n1,0,0\n0,1,0\n0.3,0.3,1\n",
            "the node file has 4 nodes, so it must be 12 × 12 (3 per node)",
        ),
    ];
    for (tag, text, want) in cases {
        let e = err(load(&format!("nodes_{tag}"), Some(text), None, None));
        assert!(e.contains(want), "{tag}: {e}");
    }
    // More than MAX_FE_NODES rows.
    let many = format!("x,y,z\n{}", "0,0,0\n".repeat(MAX_FE_ORDER / 3 + 1));
    let e = err(load("nodes_many", Some(&many), None, None));
    assert!(e.contains("more than 512 nodes"), "{e}");
}

#[test]
fn bad_interfaces_are_refused() {
    let e = FeBody::new(bipyramid(), FeReference::Clamped, &[]).unwrap_err();
    assert!(e.to_string().contains("needs interface nodes"), "{e}");
    let e = FeBody::new(bipyramid(), FeReference::Clamped, &[0, 7]).unwrap_err();
    assert!(
        e.to_string()
            .contains("interface node 7 out of range: the node file has 5 nodes"),
        "{e}"
    );
    let e = FeBody::new(bipyramid(), FeReference::Clamped, &[1, 1]).unwrap_err();
    assert!(e.to_string().contains("appears twice"), "{e}");
    // One clamped node leaves the rotations about it.
    let e = FeBody::new(bipyramid(), FeReference::Clamped, &[0]).unwrap_err();
    assert!(
        e.to_string()
            .contains("the interface does not hold the body"),
        "{e}"
    );
    let e = FeBody::new(bipyramid(), FeReference::Clamped, &[0, 1, 2, 3, 4]).unwrap_err();
    assert!(e.to_string().contains("no elastic coordinates"), "{e}");
    // Craig–Bampton on an interface node of a clamped body.
    let body = FeBody::new(bipyramid(), FeReference::Clamped, &[0, 1, 2]).unwrap();
    let e = body
        .reduce(&Reduction::CraigBampton {
            boundary_nodes: vec![1],
            modes: 1,
        })
        .unwrap_err();
    assert!(e.to_string().contains("is an interface node"), "{e}");
}

/// Characters that matter to the Matrix Market grammar and the CSV reader.
const INTERESTING: &[char] = &[
    '0', '1', '9', ' ', '\t', '.', 'e', 'E', '+', '-', '\n', '\r', '%', 'N', 'a', 'i', 'n', 'f',
    ',', '"', '#', 'x', '\u{a0}',
];

/// `text` with `edits` (position, character, insert or replace) applied.
fn mutate(text: &str, edits: &[(usize, usize, bool)]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for &(at, c, insert) in edits {
        let at = at % (chars.len() + 1);
        let c = INTERESTING[c % INTERESTING.len()];
        if insert || at == chars.len() {
            chars.insert(at, c);
        } else {
            chars[at] = c;
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Mutated matrix files give a matrix or an error, never a panic; what
    /// is accepted is finite, symmetric and of the order asked for.
    #[test]
    fn mutated_matrix_files_never_panic(
        edits in proptest::collection::vec((0usize..400, 0usize..64, any::<bool>()), 1..6),
        digits in 0usize..30,
    ) {
        let good = mtx_symmetric(&lumped_mass());
        let mut text = mutate(&good, &edits);
        // Sometimes a long digit run somewhere.
        if digits > 18 {
            let at = edits[0].0 % (text.len() + 1);
            if text.is_char_boundary(at) {
                text.insert_str(at, &"9".repeat(digits));
            }
        }
        if let Ok((a, _)) = read_matrix_str(&text, "m.mtx", "mass", 15) {
            prop_assert_eq!(a.shape(), (15, 15));
            prop_assert!(a.iter().all(|v| v.is_finite()));
            prop_assert_eq!(&a, &a.transpose());
        }
    }

    /// Mutated node files give nodes or an error, never a panic.
    #[test]
    fn mutated_node_files_never_panic(
        edits in proptest::collection::vec((0usize..120, 0usize..64, any::<bool>()), 1..6),
    ) {
        let text = mutate(&nodes_csv(&bipyramid_nodes()), &edits);
        if let Ok(nodes) = read_nodes_str(&text, "n.csv") {
            prop_assert!(!nodes.is_empty());
            prop_assert!(nodes.iter().all(|p| p.iter().all(|v| v.is_finite())));
        }
    }
}
