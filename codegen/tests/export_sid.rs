//! SID export read back by a reader written for this test (a block tree of
//! `name … end name` and `key = value` lines, Taylor blocks rebuilt from
//! `m0(i,j)` / `m1(i,j,l)` entries); no code shared with the writer.
//!
//! Compared with the body's invariants computed directly: mass, `mdCM`,
//! `J`, `Ct`, `Cr`, `Me`, `Ke` against the exact invariants projected
//! (and the first-order terms against central differences of the theory
//! sheet's `q_f`-dependent terms `S_t`, `Ī_θθ`, `Ī_θf` of the full body);
//! `Gr`, `Ge`, `Oe` against the velocity terms of the theory sheet
//! (`2∫ũ ω̃ u̇ dm`, `2 Σ ω̃_kl S̄_kl q̇`, `Σ (ω̃²)_kl (Ī_lkᵀ + S̄_kl q)`);
//! the node frames against the mode shapes.

#![cfg(feature = "modal")]

use ffr_codegen::export::{sid, ExportBody};
use ffr_codegen::modal::{reduce, Invariants, ModalBasis, Reduction};
use ffr_codegen::{BodySpec, Params, Reference, Shape};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

#[derive(Debug)]
enum Item {
    Block {
        name: String,
        id: Option<String>,
        items: Vec<Item>,
    },
    Set(String, String),
}

fn parse(text: &str) -> Vec<Item> {
    let mut stack: Vec<(String, Option<String>, Vec<Item>)> = vec![("".into(), None, Vec::new())];
    let mut started = false;
    for raw in text.lines() {
        let line = raw.trim();
        if !started {
            // Free text before `part`.
            started = line == "part";
            if !started {
                continue;
            }
        }
        if line.is_empty() {
            continue;
        }
        if let Some(name) = line.strip_prefix("end ") {
            let (n, id, items) = stack.pop().unwrap();
            assert_eq!(n, name.trim(), "`end {name}` closes `{n}`");
            stack
                .last_mut()
                .unwrap()
                .2
                .push(Item::Block { name: n, id, items });
        } else if let Some(rest) = line.strip_prefix("new ") {
            let (name, id) = match rest.split_once('=') {
                Some((a, b)) => (a.trim().to_string(), Some(b.trim().to_string())),
                None => (rest.trim().to_string(), None),
            };
            stack.push((name, id, Vec::new()));
        } else if let Some((k, v)) = line.split_once('=') {
            stack
                .last_mut()
                .unwrap()
                .2
                .push(Item::Set(k.trim().to_string(), v.trim().to_string()));
        } else {
            stack.push((line.to_string(), None, Vec::new()));
        }
    }
    assert_eq!(stack.len(), 1, "unclosed blocks");
    stack.pop().unwrap().2
}

fn block<'a>(items: &'a [Item], name: &str) -> &'a [Item] {
    items
        .iter()
        .find_map(|i| match i {
            Item::Block { name: n, items, .. } if n == name => Some(items.as_slice()),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no block `{name}`"))
}

fn get<'a>(items: &'a [Item], key: &str) -> &'a str {
    items
        .iter()
        .find_map(|i| match i {
            Item::Set(k, v) if k == key => Some(v.as_str()),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no `{key}`"))
}

/// A Taylor block: m0 (nrow × ncol) and m1[l] (nrow × ncol).
struct Taylor {
    order: usize,
    nq: usize,
    structure: usize,
    m0: DMatrix<f64>,
    m1: Vec<DMatrix<f64>>,
}

fn indices(key: &str, prefix: &str) -> Option<Vec<usize>> {
    let inner = key
        .strip_prefix(prefix)?
        .strip_prefix('(')?
        .strip_suffix(')')?;
    Some(
        inner
            .split(',')
            .map(|s| s.trim().parse().unwrap())
            .collect(),
    )
}

fn taylor(items: &[Item], name: &str) -> Taylor {
    let b = block(items, name);
    let int = |k: &str| -> usize { get(b, k).parse().unwrap() };
    let (order, nrow, ncol, nq, structure) = (
        int("order"),
        int("nrow"),
        int("ncol"),
        int("nq"),
        int("structure"),
    );
    assert_eq!(int("nqn"), 0);
    let mut m0 = DMatrix::zeros(nrow, ncol);
    let mut m1 = vec![DMatrix::zeros(nrow, ncol); if order == 1 { nq } else { 0 }];
    let mut seen0 = 0;
    for it in b {
        let Item::Set(k, v) = it else { continue };
        let x: f64 = match v.parse() {
            Ok(x) => x,
            Err(_) => continue,
        };
        if let Some(ix) = indices(k, "m0") {
            assert_eq!(ix.len(), 2);
            m0[(ix[0] - 1, ix[1] - 1)] = x;
            if structure == 2 {
                assert!(
                    ix[1] <= ix[0],
                    "{name}: symmetric block writes the lower triangle"
                );
                m0[(ix[1] - 1, ix[0] - 1)] = x;
            }
            seen0 += 1;
        } else if let Some(ix) = indices(k, "m1") {
            assert_eq!(ix.len(), 3);
            m1[ix[2] - 1][(ix[0] - 1, ix[1] - 1)] = x;
        }
    }
    let expect = match structure {
        0 => 0,
        2 => nrow * (nrow + 1) / 2,
        3 => nrow * ncol,
        s => panic!("structure {s}"),
    };
    assert_eq!(seen0, expect, "{name}: m0 entries");
    Taylor {
        order,
        nq,
        structure,
        m0,
        m1,
    }
}

fn params() -> Params {
    Params {
        length: 2.5,
        rho: 7850.0,
        area: 3e-4,
        iy: 2.2e-9,
        iz: 9.1e-9,
        e: 2.1e11,
        g: 8.1e10,
        j: 6.3e-9,
    }
}

fn setup(
    shape: &str,
    n: usize,
    r: Reference,
    red: Reduction,
) -> (BodySpec, Invariants, ModalBasis) {
    let s = BodySpec::new(Shape::resolve(shape, None).unwrap(), n, r).unwrap();
    let full = Invariants::from_exact(&s.exact_invariants().unwrap(), &params()).unwrap();
    let b = reduce(&s, &params(), &full, &red).unwrap();
    (s, full, b)
}

fn close(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64, what: &str) {
    close_to(a, b, tol, 0.0, what)
}

/// `|a − b| ≤ tol · max(|a|, |b|, floor)` (Frobenius).
fn close_to(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64, floor: f64, what: &str) {
    let scale = a.norm().max(b.norm()).max(floor);
    let d = (a - b).norm();
    assert!(
        d <= tol * scale || scale == 0.0,
        "{what}: |Δ| = {d:e}, scale {scale:e}"
    );
}

fn m3(m: &Matrix3<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(3, 3, |i, j| m[(i, j)])
}

/// Theory sheet: U_kl(q) = Θ_kl + (Ī_kl + Ī_lk) q + qᵀ S̄_kl q, Ī_θθ = tr U I − U.
fn i_theta_theta(f: &Invariants, q: &DVector<f64>) -> Matrix3<f64> {
    let u = Matrix3::from_fn(|k, l| {
        f.theta[(k, l)] + (&f.i_kl[k][l] + &f.i_kl[l][k]).dot(q) + q.dot(&(&f.s_kl[k][l] * q))
    });
    Matrix3::identity() * u.trace() - u
}

/// Theory sheet: Ī_θf(q) rows Ī_yz − Ī_zy + qᵀ(S̄_yz − S̄_zy), … (3 × n_f).
fn i_theta_f(f: &Invariants, q: &DVector<f64>) -> DMatrix<f64> {
    let n = f.m_ff.nrows();
    let mut out = DMatrix::zeros(3, n);
    for (a, (k, l)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
        let row = &f.i_kl[k][l] - &f.i_kl[l][k] + (&f.s_kl[k][l] - &f.s_kl[l][k]).transpose() * q;
        out.row_mut(a).copy_from(&row.transpose());
    }
    out
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

#[test]
fn sid_reads_back() {
    let cases = [
        (
            "beam3",
            8,
            Reference::Clamped,
            Reduction::Modal { modes: 6 },
        ),
        (
            "beam2",
            12,
            Reference::Clamped,
            Reduction::Modal { modes: 4 },
        ),
        (
            "beam3",
            5,
            Reference::Clamped,
            Reduction::CraigBampton {
                boundary_nodes: vec![5],
                modes: 3,
            },
        ),
        ("beam3", 6, Reference::Free, Reduction::Modal { modes: 4 }),
    ];
    for (shape, n, r, red) in cases {
        let (s, full, b) = setup(shape, n, r, red);
        let what = format!("{shape} {n} {r}");
        let body = ExportBody::new(&s, &params(), &full, &b).unwrap();
        let text = sid(&body);
        let tree = parse(&text);
        let modal = block(block(&tree, "part"), "modal");
        let k = b.len();
        let phi = &b.phi;
        let nf = full.m_ff.nrows();
        // refmod
        let refmod = block(modal, "refmod");
        let mass: f64 = get(refmod, "mass").parse().unwrap();
        assert_eq!(mass, full.mass);
        assert_eq!(get(refmod, "nelastq"), k.to_string());
        let names: Vec<&str> = refmod
            .iter()
            .filter_map(|i| match i {
                Item::Set(k, v) if k.starts_with("ielastq") => Some(v.as_str()),
                _ => None,
            })
            .collect();
        assert_eq!(names.len(), k);
        for (nm, label) in names.iter().zip(&b.labels) {
            assert!(nm.starts_with(label.as_str()), "{nm} vs {label}");
        }
        // mdCM: S_t = S_t0 + S̄ q.
        let md = taylor(modal, "mdCM");
        assert_eq!((md.order, md.nq, md.structure), (1, k, 3));
        close(
            &md.m0,
            &DMatrix::from_column_slice(3, 1, full.s_t0.as_slice()),
            0.0,
            "mdCM m0",
        );
        // Scales for entries that may vanish (free-free modes are
        // M-orthogonal to rigid motions, so ∫Φ dm = ∫c × Φ dm = 0): by
        // Cauchy–Schwarz |∫Φ dm| ≤ √(m ‖Me‖), |∫cΦ dm| ≤ √(tr Θ ‖Me‖).
        let me_scale = (phi.transpose() * &full.m_ff * phi).norm();
        let f1 = (full.mass * me_scale).sqrt();
        let f2 = (full.theta.trace() * me_scale).sqrt();
        let sphi = &full.s_bar * phi;
        for j in 0..k {
            close_to(
                &md.m1[j],
                &sphi.columns(j, 1).into_owned(),
                1e-14,
                f1,
                "mdCM m1",
            );
        }
        // J: Ī_θθ(0) and its first derivative along each mode (central
        // difference of the quadratic Ī_θθ(q): exact up to round-off).
        let jt = taylor(modal, "J");
        assert_eq!((jt.order, jt.structure), (1, 2));
        let zero = DVector::zeros(nf);
        close(
            &jt.m0,
            &m3(&i_theta_theta(&full, &zero)),
            1e-15,
            &format!("{what} J m0"),
        );
        let eps = 1e-3;
        for j in 0..k {
            let d = phi.column(j) * eps;
            let fd = (i_theta_theta(&full, &d) - i_theta_theta(&full, &-&d)) / (2.0 * eps);
            close_to(&jt.m1[j], &m3(&fd), 1e-9, f2, &format!("{what} J m1 {j}"));
        }
        // Ct = (S̄Φ)ᵀ, order 0.
        let ct = taylor(modal, "Ct");
        assert_eq!(ct.order, 0);
        close_to(&ct.m0, &sphi.transpose(), 1e-14, f1, "Ct");
        // Cr = (Ī_θf(q) Φ)ᵀ: value and derivative along each mode.
        let cr = taylor(modal, "Cr");
        assert_eq!(cr.order, 1);
        close_to(
            &cr.m0,
            &(i_theta_f(&full, &zero) * phi).transpose(),
            1e-14,
            f2,
            &format!("{what} Cr m0"),
        );
        for i in 0..k {
            let d = phi.column(i) * eps;
            let fd = (i_theta_f(&full, &d) - i_theta_f(&full, &-&d)) * phi / (2.0 * eps);
            // Units of a modal mass: compare against the modal mass scale
            // (the entries vanish for a planar body's bending modes).
            close_to(
                &cr.m1[i],
                &fd.transpose(),
                1e-9,
                me_scale,
                &format!("{what} Cr m1 {i}"),
            );
        }
        // Me, Ke.
        let me = taylor(modal, "Me");
        assert_eq!((me.order, me.structure), (0, 2));
        close(&me.m0, &(phi.transpose() * &full.m_ff * phi), 1e-14, "Me");
        let ke = taylor(modal, "Ke");
        close(&ke.m0, &(phi.transpose() * &full.k_ff * phi), 1e-13, "Ke");
        for (name, st) in [("ksigma", 0), ("De", 0)] {
            let t = taylor(modal, name);
            assert_eq!((t.order, t.structure), (0, st));
        }
        // Velocity terms at random η, η̇, ω.
        let gr = taylor(modal, "Gr");
        let ge = taylor(modal, "Ge");
        let oe = taylor(modal, "Oe");
        assert_eq!((gr.order, ge.order, oe.order), (1, 0, 1));
        let mut seed = 11u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for _ in 0..3 {
            let eta = DVector::from_fn(k, |_, _| 0.1 * rnd());
            let etad = DVector::from_fn(k, |_, _| rnd());
            let w = Vector3::new(rnd(), rnd(), rnd());
            let q = phi * &eta;
            let qd = phi * &etad;
            // Gr: Σ_j Gr_j(η) ω η̇_j = 2∫ ũ ω̃ u̇ dm = 2 (tr W ω − Wᵀ ω),
            // W_kl = Ī_kl q̇ + qᵀ S̄_kl q̇.
            let wm = Matrix3::from_fn(|k2, l| {
                full.i_kl[k2][l].dot(&qd) + q.dot(&(&full.s_kl[k2][l] * &qd))
            });
            let expect = (w * wm.trace() - wm.transpose() * w) * 2.0;
            let mut got = Vector3::zeros();
            for j in 0..k {
                let mut g = gr.m0.view((0, 3 * j), (3, 3)).into_owned();
                for i in 0..k {
                    g += gr.m1[i].view((0, 3 * j), (3, 3)) * eta[i];
                }
                got += Vector3::from_column_slice(
                    (g * DVector::from_column_slice(w.as_slice())).as_slice(),
                ) * etad[j];
            }
            let floor = (f2 + me_scale * eta.norm()) * w.norm() * etad.norm();
            assert!(
                (got - expect).norm() <= 1e-12 * expect.norm().max(floor),
                "{what} Gr: {got} vs {expect}"
            );
            // Ge: Σ_j Ge_j ω η̇_j = Φᵀ 2 Σ_kl ω̃_kl S̄_kl q̇.
            let wt = skew(&w);
            let mut expect = DVector::zeros(nf);
            for k2 in 0..3 {
                for l in 0..3 {
                    expect += &full.s_kl[k2][l] * &qd * (2.0 * wt[(k2, l)]);
                }
            }
            let expect = phi.transpose() * expect;
            let mut got = DVector::zeros(k);
            for j in 0..k {
                got += ge.m0.columns(3 * j, 3) * DVector::from_column_slice(w.as_slice()) * etad[j];
            }
            let floor = me_scale * w.norm() * etad.norm();
            assert!(
                (&got - &expect).norm() <= 1e-12 * expect.norm().max(floor),
                "{what} Ge"
            );
            // Oe: Oe(η) ω̂ = Φᵀ Σ_kl (ω̃²)_kl (Ī_lkᵀ + S̄_kl q), ω̂ = (ωx², ωy², ωz², ωxωy, ωyωz, ωxωz).
            let w2 = wt * wt;
            let mut expect = DVector::zeros(nf);
            for k2 in 0..3 {
                for l in 0..3 {
                    expect += (&full.i_kl[l][k2] + &full.s_kl[k2][l] * &q) * w2[(k2, l)];
                }
            }
            let expect = phi.transpose() * expect;
            let hat = DVector::from_vec(vec![
                w[0] * w[0],
                w[1] * w[1],
                w[2] * w[2],
                w[0] * w[1],
                w[1] * w[2],
                w[0] * w[2],
            ]);
            let mut o = oe.m0.clone();
            for i in 0..k {
                o += &oe.m1[i] * eta[i];
            }
            let got = o * hat;
            let floor = (f2 + me_scale * eta.norm()) * w.norm_squared();
            assert!(
                (&got - &expect).norm() <= 1e-12 * expect.norm().max(floor),
                "{what} Oe"
            );
        }
        // Frames: one per body node, origin/phi/psi/AP from the mode shapes.
        let frame = block(modal, "frame");
        let nodes: Vec<(&str, &[Item])> = frame
            .iter()
            .filter_map(|i| match i {
                Item::Block { name, id, items } if name == "node" => {
                    Some((id.as_deref().unwrap(), items.as_slice()))
                }
                _ => None,
            })
            .collect();
        assert_eq!(nodes.len(), n + 1);
        let dofs = s.dofs();
        let kinds = ["ux", "uy", "uz", "rx", "ry", "rz"];
        for (node, (id, items)) in nodes.iter().enumerate() {
            assert_eq!(*id, node.to_string());
            assert_eq!(get(items, "rframe"), "body ref");
            let shape = |c: usize| -> DVector<f64> {
                DVector::from_fn(k, |j, _| {
                    dofs.iter()
                        .position(|d| d.node == node && d.kind.to_string() == kinds[c])
                        .map_or(0.0, |i| phi[(i, j)])
                })
            };
            let tr = DMatrix::from_fn(3, k, |a, j| shape(a)[j]);
            let rot = DMatrix::from_fn(3, k, |a, j| shape(3 + a)[j]);
            let origin = taylor(items, "origin");
            let x = node as f64 / n as f64 * params().length;
            assert!((origin.m0[(0, 0)] - x).abs() <= 2.0 * f64::EPSILON * x);
            for j in 0..k {
                assert_eq!(origin.m1[j], tr.columns(j, 1));
            }
            assert_eq!(taylor(items, "phi").m0, tr);
            assert_eq!(taylor(items, "psi").m0, rot);
            let ap = taylor(items, "AP");
            assert_eq!(ap.m0, DMatrix::identity(3, 3));
            for j in 0..k {
                let v = Vector3::new(rot[(0, j)], rot[(1, j)], rot[(2, j)]);
                assert_eq!(ap.m1[j], m3(&skew(&v)));
            }
        }
    }
}
