//! Modal reduction: numeric invariants correctly rounded, modal truncation and
//! Craig–Bampton bases, projected invariants and energies.
//!
//! Checks: all modes kept reproduces the full body (matrices, frequencies,
//! energy); clamped-beam frequencies against Euler–Bernoulli theory; free-free
//! modes M-orthogonal to rigid motions (and against free-free theory);
//! Craig–Bampton with all interior modes spans the full space; degenerate
//! modes come out canonical; determinism.

#![cfg(feature = "modal")]

use ffr_codegen::body::ExactInvariants;
use ffr_codegen::modal::{
    self, craig_bampton, modal_truncation, project_energy, reduce, rigid_body_modes,
    substitute_params, Invariants, ModalBasis, ModeKind, Reduction,
};
use ffr_codegen::poly::{to_f64, Poly, Rational, Sym};
use ffr_codegen::{BodySpec, Params, Reference, Shape, Stiffening};
use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen};

fn spec(shape: &str, n: usize, r: Reference) -> BodySpec {
    BodySpec::new(Shape::resolve(shape, None).unwrap(), n, r).unwrap()
}

fn exact(s: &BodySpec) -> ExactInvariants {
    s.exact_invariants().unwrap()
}

/// The spin-up (Kane–Ryan–Banerjee) beam; `iy = iz`.
fn krb() -> Params {
    Params {
        length: 8.0,
        rho: 2766.67,
        area: 7.2968e-5,
        iy: 8.2189e-9,
        iz: 8.2189e-9,
        e: 6.8952e10,
        g: 2.6e10,
        j: 1.6438e-8,
    }
}

/// A steel bar with different principal stiffnesses.
fn steel() -> Params {
    Params {
        length: 1.3,
        rho: 7850.0,
        area: 2e-4,
        iy: 1.6667e-9,
        iz: 6.6667e-9,
        e: 2.1e11,
        g: 8.1e10,
        j: 4.5e-9,
    }
}

fn numeric(s: &BodySpec, p: &Params) -> Invariants {
    Invariants::from_exact(&exact(s), p).unwrap()
}

fn rat(x: f64) -> Rational {
    Rational::from_float(x).unwrap()
}

fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).norm() / b.norm().max(f64::MIN_POSITIVE)
}

/// Generalized eigenvalues by an independent route (the usual form with the
/// Cholesky factor of M), ascending.
fn eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let l = Cholesky::new(m.clone()).unwrap().l();
    let x = l.solve_lower_triangular(k).unwrap();
    let a = l.solve_lower_triangular(&x.transpose()).unwrap();
    let a = (&a + a.transpose()) * 0.5;
    let mut v: Vec<f64> = SymmetricEigen::new(a).eigenvalues.iter().copied().collect();
    v.sort_by(f64::total_cmp);
    v
}

/// Evaluate a polynomial in `Q(i)` at `q` in f64; also returns Σ|terms|.
fn eval_q(p: &Poly, q: &[f64]) -> (f64, f64) {
    let (mut s, mut a) = (0.0, 0.0);
    for (m, c) in p.terms() {
        let mut t = to_f64(c);
        for &(sym, e) in m.factors() {
            let Sym::Q(i) = sym else {
                panic!("unexpected symbol {sym}")
            };
            t *= q[i as usize].powi(e);
        }
        s += t;
        a += t.abs();
    }
    (s, a)
}

/// Deterministic pseudo-random numbers in [−1, 1].
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

#[test]
fn invariants_are_correctly_rounded() {
    for p in [krb(), steel()] {
        for n in [1, 3, 7] {
            let s = spec("beam2", n, Reference::Clamped);
            let inv = numeric(&s, &p);
            let (rho, a, l, e, iz) = (rat(p.rho), rat(p.area), rat(p.length), rat(p.e), rat(p.iz));
            let nn = Rational::from_integer((n as i64).into());
            // m = ρAL, S_t0,x = ρAL²/2.
            assert_eq!(inv.mass, to_f64(&(rho.clone() * &a * &l)));
            assert_eq!(
                inv.s_t0[0],
                to_f64(&(rho.clone() * &a * &l * &l / Rational::from_integer(2.into())))
            );
            // Tip node (one element): K[u_N,u_N] = EA N/L, K[v_N,v_N] = 12 E I_z N³/L³.
            let dofs = s.dofs();
            let at = |name: &str| dofs.iter().position(|d| d.to_string() == name).unwrap();
            let (u, v) = (at(&format!("ux_{n}")), at(&format!("uy_{n}")));
            assert_eq!(inv.k_ff[(u, u)], to_f64(&(e.clone() * &a * &nn / &l)));
            let twelve = Rational::from_integer(12.into());
            assert_eq!(
                inv.k_ff[(v, v)],
                to_f64(&(twelve * &e * &iz * &nn * &nn * &nn / (l.clone() * &l * &l)))
            );
            // m_ff[u_N,u_N] = ρAl/3 (axial, linear shape) exactly.
            let three = Rational::from_integer(3.into());
            assert_eq!(inv.m_ff[(u, u)], to_f64(&(rho * &a * &l / &nn / three)));
        }
    }
}

#[test]
fn all_modes_reproduce_the_full_body() {
    for (shape, n, r, p) in [
        ("beam2", 4, Reference::Clamped, krb()),
        ("beam2", 3, Reference::Pinned, steel()),
        ("beam3", 3, Reference::Clamped, steel()),
        ("beam3", 2, Reference::Pinned, krb()),
    ] {
        let s = spec(shape, n, r);
        let full = numeric(&s, &p);
        let nf = full.nf();
        let basis = reduce(&s, &p, &full, &Reduction::Modal { modes: nf }).unwrap();
        let phi = &basis.phi;
        assert_eq!(phi.shape(), (nf, nf));
        let inv = phi.clone().try_inverse().expect("Φ invertible");
        let red = full.project(phi);
        // Back to nodal coordinates: Φ⁻ᵀ (Φᵀ X Φ) Φ⁻¹ = X.
        let back = |x: &DMatrix<f64>| inv.transpose() * x * &inv;
        let tol = 1e-10;
        assert!(rel(&back(&red.m_ff), &full.m_ff) < tol, "{shape} m_ff");
        assert!(rel(&back(&red.k_ff), &full.k_ff) < tol, "{shape} K_ff");
        for k in 0..3 {
            for l in 0..3 {
                let sk = &full.s_kl[k][l];
                if sk.norm() > 0.0 {
                    assert!(rel(&back(&red.s_kl[k][l]), sk) < tol, "{shape} S_{k}{l}");
                }
                let ik = DMatrix::from_column_slice(nf, 1, full.i_kl[k][l].as_slice());
                if ik.norm() > 0.0 {
                    let b = inv.transpose() * &red.i_kl[k][l];
                    assert!(rel(&DMatrix::from_column_slice(nf, 1, b.as_slice()), &ik) < tol);
                }
            }
        }
        assert!(rel(&(&red.s_bar * &inv), &full.s_bar) < tol, "{shape} S̄");
        assert_eq!(red.mass, full.mass);
        assert_eq!(red.theta, full.theta);
        // Mass normalized, stiffness diagonal.
        let lam = eigenvalues(&full.k_ff, &full.m_ff);
        let kappa = lam[nf - 1] / lam[0];
        let eye = DMatrix::identity(nf, nf);
        eprintln!(
            "{shape} {n} {r}: κ = {kappa:e}, |ΦᵀMΦ − I| = {:e}, max diag dev {:e}",
            (&red.m_ff - &eye).amax(),
            (0..nf)
                .map(|i| (red.m_ff[(i, i)] - 1.0).abs())
                .fold(0.0, f64::max)
        );
        assert!(rel(&red.m_ff, &eye) < 1e-12);
        let w2 = DMatrix::from_diagonal(&DVector::from_iterator(
            nf,
            basis.frequencies.iter().map(|w| w * w),
        ));
        assert!(rel(&red.k_ff, &w2) < 1e-11, "{shape} Φᵀ K Φ");
        // Frequencies equal the full eigenvalues (independent route; its
        // accuracy is ε λ_max on every λ, so compare absolutely).
        let lmax = lam[nf - 1];
        for (w, l) in basis.frequencies.iter().zip(&lam) {
            assert!(
                (w * w - l).abs() <= 1e-12 * lmax,
                "{shape}: {} vs {l}",
                w * w
            );
        }
        // Energy: U(Φη) for random η, and back: U_red(Φ⁻¹ q) = U(q).
        let u = substitute_params(&s.stiffening_energy(Stiffening::SecondOrder), &p).unwrap();
        let ur = project_energy(&u, phi).unwrap();
        let mut seed = 7;
        for _ in 0..5 {
            let q: Vec<f64> = (0..nf).map(|_| 1e-2 * lcg(&mut seed)).collect();
            let eta = &inv * DVector::from_column_slice(&q);
            let (a, sa) = eval_q(&u, &q);
            let (b, _) = eval_q(&ur, eta.as_slice());
            assert!((a - b).abs() <= 1e-11 * sa, "{shape}: U {a} vs {b}");
        }
    }
}

/// Roots of cos β cosh β = −1 (clamped-free) and cos β cosh β = 1 (free-free).
fn roots(free: bool) -> [f64; 3] {
    let guesses = if free {
        [4.73, 7.853, 10.996]
    } else {
        [1.875, 4.694, 7.855]
    };
    let s = if free { -1.0 } else { 1.0 };
    guesses.map(|mut b: f64| {
        for _ in 0..50 {
            let f = b.cos() * b.cosh() + s;
            let df = -b.sin() * b.cosh() + b.cos() * b.sinh();
            b -= f / df;
        }
        b
    })
}

#[test]
fn clamped_frequencies_match_euler_bernoulli() {
    let p = krb();
    let scale = (p.e * p.iz / (p.rho * p.area * p.length.powi(4))).sqrt();
    let exact_roots = roots(false);
    let mut errors = Vec::new();
    for n in [4, 8, 16] {
        let s = spec("beam2", n, Reference::Clamped);
        let full = numeric(&s, &p);
        let b = reduce(&s, &p, &full, &Reduction::Modal { modes: 3 }).unwrap();
        let e: Vec<f64> = (0..3)
            .map(|i| b.frequencies[i] / (exact_roots[i].powi(2) * scale) - 1.0)
            .collect();
        eprintln!(
            "N = {n}: ω = {:?}, relative error vs EB {:?}",
            b.frequencies, e
        );
        errors.push(e);
        if n == 16 {
            // The brief's constants (5 digits: ≤ 1.1e-5 relative in β²).
            for (i, c) in [1.8751, 4.6941, 7.8548].iter().enumerate() {
                let theory = c * c * scale;
                let r = b.frequencies[i] / theory - 1.0;
                eprintln!(
                    "  mode {}: {} rad/s vs {theory} ({r:e})",
                    i + 1,
                    b.frequencies[i]
                );
                assert!(r.abs() < 1e-4, "mode {}: {r:e}", i + 1);
            }
        }
    }
}

#[test]
fn clamped_frequencies_converge_at_fourth_order() {
    // A very slender beam: the section's rotary inertia (in the consistent
    // mass, absent from Euler–Bernoulli) changes ω by ~(β r/L)²/2 ≈ 1e-12,
    // so what remains is the mesh error, O(h⁴) for cubic Hermite elements.
    let mut p = krb();
    p.iz = 8.2189e-15;
    p.iy = 8.2189e-15;
    let scale = (p.e * p.iz / (p.rho * p.area * p.length.powi(4))).sqrt();
    let exact_roots = roots(false);
    let mut prev: Option<Vec<f64>> = None;
    for n in [4, 8, 16, 32] {
        let s = spec("beam2", n, Reference::Clamped);
        let full = numeric(&s, &p);
        let b = reduce(&s, &p, &full, &Reduction::Modal { modes: 3 }).unwrap();
        let e: Vec<f64> = (0..3)
            .map(|i| b.frequencies[i] / (exact_roots[i].powi(2) * scale) - 1.0)
            .collect();
        eprintln!("slender N = {n}: relative error {e:?}");
        for &x in &e {
            assert!(x > 0.0, "a consistent-mass Ritz method bounds ω from above");
        }
        if let Some(pe) = &prev {
            for i in 0..3 {
                let ratio = pe[i] / e[i];
                eprintln!("  mode {}: error ratio {ratio:.2}", i + 1);
                if e[i] > 1e-11 {
                    assert!(
                        (12.0..20.0).contains(&ratio),
                        "mode {}: ratio {ratio}",
                        i + 1
                    );
                }
            }
        }
        prev = Some(e);
    }
}

#[test]
fn free_free_modes_are_orthogonal_to_rigid_motions() {
    for (shape, rigid_count) in [("beam2", 3), ("beam3", 6)] {
        let p = krb();
        let s = spec(shape, 16, Reference::Free);
        let full = numeric(&s, &p);
        let r = rigid_body_modes(&s, p.length);
        assert_eq!(r.ncols(), rigid_count, "{shape}");
        // The motions are rigid: K r = 0 to round-off.
        for c in r.column_iter() {
            assert!((&full.k_ff * c).norm() <= 1e-12 * full.k_ff.norm() * c.norm());
        }
        let b = reduce(&s, &p, &full, &Reduction::Modal { modes: 6 }).unwrap();
        let coupling = r.transpose() * &full.m_ff * &b.phi;
        let scale = (r.transpose() * &full.m_ff * &r).norm().sqrt();
        let worst = coupling.amax() / scale;
        eprintln!(
            "{shape} free: ω = {:?}, max |Rᵀ M φ| / ‖R‖_M = {worst:e}",
            b.frequencies
        );
        assert!(worst < 1e-12, "{shape}: {worst:e}");
        assert!(
            b.frequencies[0] > 1.0,
            "no rigid mode left: {:?}",
            b.frequencies
        );
        // Free-free bending against Euler–Bernoulli (β = 4.7300, 7.8532, …).
        let scale = (p.e * p.iz / (p.rho * p.area * p.length.powi(4))).sqrt();
        let beta = roots(true);
        let step = if shape == "beam2" { 1 } else { 2 }; // iy = iz: y and z pairs
        for (i, beta_i) in beta.iter().take(2).enumerate() {
            let w = b.frequencies[i * step];
            let r = w / (beta_i * beta_i * scale) - 1.0;
            eprintln!("  free-free mode {}: {w} rad/s ({r:e})", i + 1);
            assert!(r.abs() < 1e-4, "{shape} mode {}: {r:e}", i + 1);
        }
    }
}

#[test]
fn craig_bampton_with_all_interior_modes_spans_the_full_space() {
    for (shape, n, r, nodes) in [
        ("beam2", 6, Reference::Clamped, vec![6]),
        ("beam2", 5, Reference::Free, vec![0, 5]),
        ("beam3", 4, Reference::Clamped, vec![2, 4]),
    ] {
        let p = steel();
        let s = spec(shape, n, r);
        let full = numeric(&s, &p);
        let nf = full.nf();
        let dofs = s.dofs();
        let nb = dofs.iter().filter(|d| nodes.contains(&d.node)).count();
        let red = Reduction::CraigBampton {
            boundary_nodes: nodes.clone(),
            modes: nf - nb,
        };
        let b = reduce(&s, &p, &full, &red).unwrap();
        assert_eq!(b.phi.shape(), (nf, nf));
        let svd = b.phi.clone().svd(false, false);
        let cond = svd.singular_values.max() / svd.singular_values.min();
        assert!(cond < 1e8, "{shape}: Φ nearly singular ({cond:e})");
        // Same eigenvalues as the full body (for the free body, including its
        // zero rigid-body eigenvalues).
        let a = eigenvalues(&b.modal_stiffness, &b.modal_mass);
        let e = eigenvalues(&full.k_ff, &full.m_ff);
        let lmax = e[nf - 1];
        let worst = a
            .iter()
            .zip(&e)
            .map(|(x, y)| (x - y).abs() / lmax)
            .fold(0.0, f64::max);
        eprintln!("{shape} {r} CB {nodes:?}: max |Δλ|/λ_max = {worst:e}, cond Φ = {cond:e}");
        assert!(worst < 1e-11, "{shape}: {worst:e}");
        // Structure: normal modes vanish at the boundary, constraint modes are
        // 1 at their coordinate, 0 at the other boundary coordinates, and
        // statically balanced in the interior.
        let kphi = &full.k_ff * &b.phi;
        for (j, kind) in b.kinds.iter().enumerate() {
            match kind {
                ModeKind::Normal { .. } => {
                    for (i, d) in dofs.iter().enumerate() {
                        if nodes.contains(&d.node) {
                            assert_eq!(b.phi[(i, j)], 0.0);
                        }
                    }
                }
                ModeKind::Constraint { dof } => {
                    for (i, d) in dofs.iter().enumerate() {
                        if nodes.contains(&d.node) {
                            assert_eq!(b.phi[(i, j)], if i == *dof { 1.0 } else { 0.0 });
                        } else {
                            assert!(kphi[(i, j)].abs() <= 1e-9 * kphi.column(j).amax());
                        }
                    }
                    assert_eq!(b.labels[j], format!("constraint_{}", dofs[*dof]));
                }
                ModeKind::Static { load } => {
                    panic!("craig_bampton adds no static modes, found `static_{load}`")
                }
            }
        }
    }
}

#[test]
fn craig_bampton_basis_layout_and_errors() {
    let p = krb();
    let s = spec("beam2", 8, Reference::Clamped);
    let full = numeric(&s, &p);
    let b = reduce(
        &s,
        &p,
        &full,
        &Reduction::CraigBampton {
            boundary_nodes: vec![8, 4],
            modes: 3,
        },
    )
    .unwrap();
    assert_eq!(b.len(), 3 + 6);
    assert_eq!(b.frequencies.len(), 3);
    assert_eq!(
        b.labels,
        [
            "mode_1",
            "mode_2",
            "mode_3",
            "constraint_ux_4",
            "constraint_uy_4",
            "constraint_rz_4",
            "constraint_ux_8",
            "constraint_uy_8",
            "constraint_rz_8"
        ]
    );
    // Fixed-interface frequencies exceed the free-interface (cantilever) ones.
    let m = reduce(&s, &p, &full, &Reduction::Modal { modes: 3 }).unwrap();
    for i in 0..3 {
        assert!(b.frequencies[i] > m.frequencies[i]);
    }
    let err = |red: Reduction| reduce(&s, &p, &full, &red).unwrap_err().to_string();
    assert!(err(Reduction::CraigBampton {
        boundary_nodes: vec![0],
        modes: 2
    })
    .contains("boundary node 0 has no elastic coordinates"));
    assert!(err(Reduction::CraigBampton {
        boundary_nodes: vec![9],
        modes: 2
    })
    .contains("out of range"));
    assert!(err(Reduction::Modal { modes: 0 }).contains("between 1 and 24"));
    assert!(err(Reduction::Modal { modes: 25 }).contains("between 1 and 24"));
    // Direct calls.
    let names: Vec<String> = s.dofs().iter().map(|d| d.to_string()).collect();
    assert!(craig_bampton(&full.m_ff, &full.k_ff, &[3, 3], 1, &names).is_err());
    let b2 = craig_bampton(&full.m_ff, &full.k_ff, &[23, 22, 21], 3, &names).unwrap();
    assert_eq!(
        b2.labels[3..],
        ["constraint_ux_8", "constraint_uy_8", "constraint_rz_8"]
    );
    // A free body's modal truncation without rigid motions fails: K is singular.
    let f = spec("beam2", 4, Reference::Free);
    let ff = numeric(&f, &p);
    assert!(modal_truncation(&ff.m_ff, &ff.k_ff, 2, None)
        .unwrap_err()
        .to_string()
        .contains("not positive definite"));
}

#[test]
fn degenerate_modes_are_canonical() {
    // iy = iz: bending in y and z has equal frequencies; each pair comes out
    // as pure y bending then pure z bending, largest entry positive.
    let p = krb();
    let s = spec("beam3", 8, Reference::Clamped);
    let full = numeric(&s, &p);
    let b = reduce(&s, &p, &full, &Reduction::Modal { modes: 4 }).unwrap();
    let dofs = s.dofs();
    for pair in 0..2 {
        let (a, c) = (2 * pair, 2 * pair + 1);
        let r = b.frequencies[c] / b.frequencies[a] - 1.0;
        assert!(r.abs() < 1e-12, "pair {pair}: {r:e}");
        for (j, plane) in [(a, "y"), (c, "z")] {
            let col = b.phi.column(j);
            let max = col.amax();
            for (i, d) in dofs.iter().enumerate() {
                let k = d.kind.to_string();
                let in_plane = match plane {
                    "y" => k == "uy" || k == "rz",
                    _ => k == "uz" || k == "ry",
                };
                if !in_plane {
                    assert!(col[i].abs() <= 1e-12 * max, "mode {j} {d}: {}", col[i]);
                }
            }
            let imax = col.iamax();
            assert!(col[imax] > 0.0);
        }
    }
}

fn bits(m: &DMatrix<f64>) -> Vec<u64> {
    m.iter().map(|v| v.to_bits()).collect()
}

fn pipeline(shape: &str, red: &Reduction) -> (ModalBasis, Invariants, Poly) {
    let p = krb();
    let s = spec(shape, 6, Reference::Clamped);
    let full = numeric(&s, &p);
    let b = reduce(&s, &p, &full, red).unwrap();
    let inv = full.project(&b.phi);
    let u = substitute_params(&s.stiffening_energy(Stiffening::SecondOrder), &p).unwrap();
    let e = project_energy(&u, &b.phi).unwrap();
    (b, inv, e)
}

#[test]
fn deterministic() {
    for shape in ["beam2", "beam3"] {
        for red in [
            Reduction::Modal { modes: 5 },
            Reduction::CraigBampton {
                boundary_nodes: vec![3, 6],
                modes: 4,
            },
        ] {
            let (b1, i1, e1) = pipeline(shape, &red);
            let (b2, i2, e2) = pipeline(shape, &red);
            assert_eq!(bits(&b1.phi), bits(&b2.phi));
            assert_eq!(
                b1.frequencies
                    .iter()
                    .map(|w| w.to_bits())
                    .collect::<Vec<_>>(),
                b2.frequencies
                    .iter()
                    .map(|w| w.to_bits())
                    .collect::<Vec<_>>()
            );
            assert_eq!(bits(&b1.modal_mass), bits(&b2.modal_mass));
            assert_eq!(bits(&b1.modal_stiffness), bits(&b2.modal_stiffness));
            assert_eq!(b1.labels, b2.labels);
            for k in 0..3 {
                for l in 0..3 {
                    assert_eq!(bits(&i1.s_kl[k][l]), bits(&i2.s_kl[k][l]));
                }
            }
            assert_eq!(bits(&i1.s_bar), bits(&i2.s_bar));
            assert_eq!(e1, e2);
            assert_eq!(e1.to_string(), e2.to_string());
        }
    }
}

#[test]
fn projected_energy_matches_direct_evaluation() {
    // Truncated basis on a larger body: U_red(η) = U(Φ η).
    let p = krb();
    for shape in ["beam2", "beam3"] {
        let s = spec(shape, 16, Reference::Clamped);
        let full = numeric(&s, &p);
        let b = reduce(&s, &p, &full, &Reduction::Modal { modes: 8 }).unwrap();
        let u = substitute_params(&s.stiffening_energy(Stiffening::SecondOrder), &p).unwrap();
        let ur = project_energy(&u, &b.phi).unwrap();
        // Degree ≤ 4 in 8 modal coordinates: at most C(11,4)+C(10,3) terms.
        assert!(ur.len() <= 330 + 120, "{}", ur.len());
        let mut seed = 3;
        for _ in 0..5 {
            let eta: Vec<f64> = (0..8).map(|_| 0.05 * lcg(&mut seed)).collect();
            let q = &b.phi * DVector::from_column_slice(&eta);
            let (a, sa) = eval_q(&u, q.as_slice());
            let (c, _) = eval_q(&ur, &eta);
            assert!((a - c).abs() <= 1e-12 * sa, "{shape}: {a} vs {c}");
        }
    }
    // Errors: parameters left, index beyond the basis.
    let s = spec("beam2", 2, Reference::Clamped);
    let phi = DMatrix::identity(6, 2);
    assert!(project_energy(&s.stiffening_energy(Stiffening::SecondOrder), &phi).is_err());
    let q9 = Poly::var(Sym::Q(9));
    assert!(project_energy(&q9, &phi)
        .unwrap_err()
        .to_string()
        .contains("q9"));
    let _ = modal::eval_poly(&Poly::int(1), &krb()).unwrap();
}

/// The invariants in the element length evaluated at `l = L/N`
/// (`from_exact_elements`, what reductions use) are the invariants in `L`
/// evaluated at `L` (`from_exact`) to the last bit: both are the exact value
/// rounded once.
#[test]
fn invariants_in_the_element_length_are_the_same_bits() {
    use ffr_codegen::Formalism;
    let bits = |m: &DMatrix<f64>| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for shape in ["beam2", "beam3"] {
        for n in [1, 3, 7] {
            for r in [Reference::Clamped, Reference::Free] {
                for f in [Formalism::Consistent, Formalism::Lumped] {
                    let s = spec(shape, n, r).with_formalism(f);
                    for p in [krb(), steel()] {
                        let a = Invariants::from_exact(&exact(&s), &p).unwrap();
                        let b = Invariants::from_exact_elements(
                            &s.exact_invariants_in_element_length().unwrap(),
                            &p,
                            n,
                        )
                        .unwrap();
                        let what = format!("{shape} {n} {r:?} {f:?}");
                        assert_eq!(a.mass.to_bits(), b.mass.to_bits(), "{what}");
                        assert_eq!(a.s_t0, b.s_t0, "{what}");
                        assert_eq!(a.theta, b.theta, "{what}");
                        assert_eq!(bits(&a.s_bar), bits(&b.s_bar), "{what}");
                        assert_eq!(bits(&a.m_ff), bits(&b.m_ff), "{what}");
                        assert_eq!(bits(&a.k_ff), bits(&b.k_ff), "{what}");
                        for k in 0..3 {
                            for l in 0..3 {
                                assert_eq!(bits(&a.s_kl[k][l]), bits(&b.s_kl[k][l]), "{what}");
                                assert_eq!(a.i_kl[k][l], b.i_kl[k][l], "{what}");
                            }
                        }
                    }
                }
            }
        }
    }
}
