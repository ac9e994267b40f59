//! Generated expressions against an independent route: Gauss–Legendre
//! quadrature of the hand-coded beam shape functions over the actual
//! rectangular prism (`ffr-reference`, which shares no code with the
//! generator). Every invariant, the `q_f`-dependent terms and the stiffening
//! terms; beam2 and beam3, 1–4 elements, every reference condition, both
//! formalisms, lengths from 1e-3 m to 1e2 m. Agreement: 1e-12 relative per
//! matrix (Frobenius norm).

use ffr_codegen::{BodySpec, Formalism, Generated, Options, ParamValues, Reference, Shape};
use ffr_reference as rf;
use nalgebra::{DMatrix, DVector};

const TOL: f64 = 1e-12;

fn param_sets() -> Vec<rf::RefParams> {
    vec![
        // Steel bar, 1 m, 20 × 10 mm.
        rf::RefParams {
            length: 1.0,
            rho: 7850.0,
            wy: 0.02,
            wz: 0.01,
            e: 2.1e11,
            g: 8.1e10,
            j: 1.2e-8,
        },
        // Micro beam: 1 mm long, 10 × 20 µm, silicon-like.
        rf::RefParams {
            length: 1e-3,
            rho: 2330.0,
            wy: 1e-5,
            wz: 2e-5,
            e: 1.69e11,
            g: 7.9e10,
            j: 3e-21,
        },
        // 100 m aluminium boom, 0.5 × 0.3 m.
        rf::RefParams {
            length: 1e2,
            rho: 2700.0,
            wy: 0.5,
            wz: 0.3,
            e: 7e10,
            g: 2.6e10,
            j: 5e-3,
        },
        // Kane–Ryan–Banerjee-like slender beam, 8 m.
        rf::RefParams {
            length: 8.0,
            rho: 2766.67,
            wy: 0.0105,
            wz: 0.00695,
            e: 6.8952e10,
            g: 2.6e10,
            j: 1.6e-9,
        },
    ]
}

fn values(p: &rf::RefParams) -> ParamValues {
    ParamValues {
        length: p.length,
        rho: p.rho,
        area: p.area(),
        iy: p.iy(),
        iz: p.iz(),
        e: p.e,
        g: p.g,
        j: p.j,
    }
}

fn dm(rows: &[Vec<f64>]) -> DMatrix<f64> {
    let r = rows.len();
    let c = rows.first().map_or(0, Vec::len);
    DMatrix::from_fn(r, c, |i, j| rows[i][j])
}

fn rows3(m: &[[f64; 3]; 3]) -> DMatrix<f64> {
    DMatrix::from_fn(3, 3, |i, j| m[i][j])
}

/// ‖a − b‖ ≤ TOL·‖b‖, or ≤ TOL·scale when `b` is (numerically) zero.
fn check(what: &str, a: &DMatrix<f64>, b: &DMatrix<f64>, scale: f64) {
    assert_eq!(a.shape(), b.shape(), "{what}: shapes differ");
    let err = (a - b).norm();
    let reference = b.norm().max(scale);
    assert!(
        err <= TOL * reference,
        "{what}: relative error {:e} (|generated − quadrature| = {err:e}, |quadrature| = {:e})",
        err / reference,
        b.norm()
    );
}

fn col(v: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(v.len(), 1, v)
}

struct Case {
    shape: rf::Shape,
    elements: usize,
    reference: rf::Reference,
    formalism: Formalism,
    params: rf::RefParams,
}

impl Case {
    fn body(&self) -> rf::RefBody {
        rf::RefBody {
            shape: self.shape,
            elements: self.elements,
            reference: self.reference,
            params: self.params,
        }
    }

    fn tag(&self) -> String {
        format!(
            "{:?} N={} {:?} {:?} L={}",
            self.shape, self.elements, self.reference, self.formalism, self.params.length
        )
    }

    fn generated(&self, stiffening: bool) -> Generated {
        let name = match self.shape {
            rf::Shape::Beam2 => "beam2",
            rf::Shape::Beam3 => "beam3",
        };
        let reference = match self.reference {
            rf::Reference::Clamped => Reference::Clamped,
            rf::Reference::Pinned => Reference::Pinned,
            rf::Reference::Free => Reference::Free,
        };
        let spec = BodySpec::new(
            Shape::resolve(name, None).unwrap(),
            self.elements,
            reference,
        )
        .unwrap()
        .with_formalism(self.formalism);
        ffr_codegen::generate(&spec, Options { stiffening }).unwrap()
    }
}

fn cases() -> Vec<Case> {
    let mut v = Vec::new();
    for shape in [rf::Shape::Beam2, rf::Shape::Beam3] {
        for elements in 1..=4 {
            for reference in [
                rf::Reference::Clamped,
                rf::Reference::Pinned,
                rf::Reference::Free,
            ] {
                for formalism in [Formalism::Consistent, Formalism::Lumped] {
                    for params in param_sets() {
                        v.push(Case {
                            shape,
                            elements,
                            reference,
                            formalism,
                            params,
                        });
                    }
                }
            }
        }
    }
    v
}

/// A deterministic pseudo-random vector (xorshift), entries in [−s, s].
fn pseudo_random(n: usize, seed: u64, s: f64) -> Vec<f64> {
    let mut x = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            s * ((x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
        })
        .collect()
}

#[test]
fn invariants_match_quadrature() {
    for case in cases() {
        let g = case.generated(false);
        let body = case.body();
        let r = match case.formalism {
            Formalism::Consistent => body.invariants(),
            Formalism::Lumped => body.lumped_invariants(),
        };
        let n = g.eval_invariants(&values(&case.params));
        let tag = case.tag();
        assert_eq!(
            n.dofs,
            body.dof_labels(),
            "{tag}: coordinate labels and order"
        );
        let nf = n.dofs.len();
        let one = |x: f64| DMatrix::from_element(1, 1, x);
        check(&format!("{tag} mass"), &one(n.mass), &one(r.mass), 0.0);
        let st0 = DMatrix::from_column_slice(3, 1, r.s_t0.as_slice());
        check(&format!("{tag} S_t0"), &col(&n.s_t0), &st0, 0.0);
        let s_bar = DMatrix::from_column_slice(3, nf, r.s_bar.as_slice());
        check(&format!("{tag} S̄"), &dm(&n.s_bar), &s_bar, 0.0);
        let theta = DMatrix::from_column_slice(3, 3, r.theta.as_slice());
        check(&format!("{tag} Θ"), &rows3(&n.theta), &theta, 0.0);
        let skl_scale = r.m_ff.norm();
        let ikl_scale = (0..9)
            .map(|i| r.i_kl[i / 3][i % 3].norm())
            .fold(0.0, f64::max);
        for k in 0..3 {
            for l in 0..3 {
                let what = format!("{tag} S̄_{k}{l}");
                check(&what, &dm(&n.s_kl[k][l]), &r.s_kl[k][l], skl_scale);
                let ikl = DMatrix::from_column_slice(nf, 1, r.i_kl[k][l].as_slice());
                let what = format!("{tag} Ī_{k}{l}");
                check(&what, &col(&n.i_kl[k][l]), &ikl, ikl_scale);
            }
        }
        check(&format!("{tag} m_ff"), &dm(&n.m_ff), &r.m_ff, 0.0);
        check(&format!("{tag} K_ff"), &dm(&n.k_ff), &r.k_ff, 0.0);
    }
}

#[test]
fn inertia_terms_match_quadrature() {
    for (i, case) in cases().into_iter().enumerate() {
        // The quadrature's q-dependent terms are volume integrals (consistent).
        if case.formalism == Formalism::Lumped {
            continue;
        }
        let g = case.generated(false);
        let body = case.body();
        let nf = body.nf();
        let q = pseudo_random(nf, i as u64 + 1, 0.05 * case.params.length);
        let n = g.eval_inertia(&values(&case.params), &q);
        let tag = case.tag();
        let st = DMatrix::from_column_slice(3, 1, body.s_t(&q).as_slice());
        check(&format!("{tag} S_t"), &col(&n.s_t), &st, 0.0);
        let itt = DMatrix::from_column_slice(3, 3, body.i_theta_theta(&q).as_slice());
        check(&format!("{tag} Ī_θθ"), &rows3(&n.i_theta_theta), &itt, 0.0);
        let itf = DMatrix::from_column_slice(3, nf, body.i_theta_f(&q).as_slice());
        check(&format!("{tag} Ī_θf"), &dm(&n.i_theta_f), &itf, 0.0);
    }
}

#[test]
fn stiffening_matches_quadrature() {
    for (i, case) in cases().into_iter().enumerate() {
        if case.formalism == Formalism::Lumped {
            continue; // the same energy in both formalisms
        }
        let g = case.generated(true);
        let body = case.body();
        let q = pseudo_random(body.nf(), i as u64 + 7, 0.05 * case.params.length);
        let (f, k) = g.eval_stiffening(&values(&case.params), &q);
        let tag = case.tag();
        let fr: DVector<f64> = body.stiffening_force(&q);
        let fr = DMatrix::from_column_slice(fr.len(), 1, fr.as_slice());
        check(&format!("{tag} stiffening force"), &col(&f), &fr, 0.0);
        let kr = body.stiffening_tangent(&q);
        check(&format!("{tag} stiffening tangent"), &dm(&k), &kr, 0.0);
    }
}
