//! The compiled generated code computes bit for bit what the generator's
//! evaluator (`ffr invariants --json`) reports, and agrees with the
//! theory-sheet formulas applied to its own invariants (`InvariantBody`).

use ffr_bench::{Beam2N4, Beam3N1, Beam3N32, Beam3N8};
use ffr_codegen::{BodySpec, Options, ParamValues, Reference, Shape};
use ffr_runtime::{CompiledBody, FlexBody, InertiaTerms, InvariantBody, Params};
use nalgebra::DMatrix;

fn params() -> Params {
    Params {
        length: 2.5,
        rho: 2700.0,
        area: 3e-4,
        iy: 2.1e-9,
        iz: 4.4e-9,
        e: 7e10,
        g: 2.6e10,
        j: 5.3e-9,
    }
}

fn values(p: &Params) -> ParamValues {
    ParamValues {
        length: p.length,
        rho: p.rho,
        area: p.area,
        iy: p.iy,
        iz: p.iz,
        e: p.e,
        g: p.g,
        j: p.j,
    }
}

fn q_of(n: usize, scale: f64) -> Vec<f64> {
    (0..n)
        .map(|i| scale * ((i as f64 * 0.7311).sin() + 0.1 * i as f64 / n as f64))
        .collect()
}

fn bits(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

fn check<B: CompiledBody + From<Params>>(shape: &str, n: usize, stiffening: bool) {
    let p = params();
    let body = B::from(p);
    let g = ffr_codegen::generate(
        &BodySpec::new(Shape::resolve(shape, None).unwrap(), n, Reference::Clamped).unwrap(),
        Options { stiffening },
    )
    .unwrap();
    assert_eq!(B::NF, g.dofs.len());
    assert_eq!(
        body.dof_labels(),
        g.dofs.iter().map(|d| d.to_string()).collect::<Vec<_>>()
    );
    let inv = body.invariants();
    let ev = g.eval_invariants(&values(&p));
    assert!(bits(inv.mass, ev.mass));
    let nf = B::NF;
    for a in 0..nf {
        for b in 0..nf {
            assert!(bits(inv.m_ff[(a, b)], ev.m_ff[a][b]), "m_ff[{a}][{b}]");
            assert!(bits(inv.k_ff[(a, b)], ev.k_ff[a][b]), "k_ff[{a}][{b}]");
            for k in 0..3 {
                for l in 0..3 {
                    assert!(bits(inv.s_kl[k][l][(a, b)], ev.s_kl[k][l][a][b]));
                }
            }
        }
        for k in 0..3 {
            assert!(bits(inv.s_bar[(k, a)], ev.s_bar[k][a]));
            for l in 0..3 {
                assert!(bits(inv.i_kl[k][l][a], ev.i_kl[k][l][a]));
            }
        }
    }
    for k in 0..3 {
        assert!(bits(inv.s_t0[k], ev.s_t0[k]));
        for l in 0..3 {
            assert!(bits(inv.theta[(k, l)], ev.theta[k][l]));
        }
    }
    // q_f-dependent terms: bit for bit against the evaluator, and to round-off
    // against the theory-sheet formulas on the invariants.
    let q = q_of(nf, 1e-2 * p.length);
    let mut t = InertiaTerms::zeros(nf);
    body.inertia_terms(&q, &mut t);
    let et = g.eval_inertia(&values(&p), &q);
    let mut f = InertiaTerms::zeros(nf);
    InvariantBody::new(inv.clone()).inertia_terms(&q, &mut f);
    for k in 0..3 {
        assert!(bits(t.s_t[k], et.s_t[k]));
        for l in 0..3 {
            assert!(bits(t.i_theta_theta[(k, l)], et.i_theta_theta[k][l]));
        }
        for a in 0..nf {
            assert!(bits(t.i_theta_f[(k, a)], et.i_theta_f[k][a]));
        }
    }
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    assert!((t.s_t - f.s_t).norm() <= 1e-13 * f.s_t.norm());
    assert!((t.i_theta_theta - f.i_theta_theta).norm() <= 1e-12 * f.i_theta_theta.norm());
    assert!((&t.i_theta_f - &f.i_theta_f).norm() <= 1e-12 * f.i_theta_f.norm());
    assert!(rel(t.i_theta_theta[(2, 2)], f.i_theta_theta[(2, 2)]) < 1e-12);
    // Stiffening.
    assert_eq!(body.has_stiffening(), stiffening);
    let mut force = vec![0.0; nf];
    let mut kt = DMatrix::zeros(nf, nf);
    body.stiffening(&q, &mut force, Some(&mut kt));
    let (ef, ek) = g.eval_stiffening(&values(&p), &q);
    for a in 0..nf {
        assert!(bits(force[a], ef[a]), "force[{a}]");
        for b in 0..nf {
            assert!(bits(kt[(a, b)], ek[a][b]), "tangent[{a}][{b}]");
        }
    }
}

#[test]
fn beam3_one_element_bit_for_bit() {
    check::<Beam3N1>("beam3", 1, false);
}

#[test]
fn beam3_eight_elements_bit_for_bit() {
    check::<Beam3N8>("beam3", 8, false);
}

#[test]
fn beam3_thirty_two_elements_bit_for_bit() {
    check::<Beam3N32>("beam3", 32, false);
}

#[test]
fn beam2_with_stiffening_bit_for_bit() {
    check::<Beam2N4>("beam2", 4, true);
}

/// The trait's mass blocks against the theory-sheet table written out here
/// with nalgebra's own cross-product matrix: `m_Rθ = −A S̃_t Ḡ`,
/// `m_Rf = A S̄`, `m_θθ = Ḡᵀ Ī_θθ Ḡ`, `m_θf = Ḡᵀ Ī_θf`, for a rotation
/// given by Euler parameters (`Ḡ = 2[−e, −ẽ + e₀I]`).
#[test]
fn mass_blocks_follow_the_theory_sheet() {
    use nalgebra::{Matrix3, Matrix3xX, UnitQuaternion, Vector3};
    let body = Beam3N8::from(params());
    let inv = body.invariants();
    let q = q_of(Beam3N8::NF, 1e-2);
    let rot = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.7, 1.1));
    let a = *rot.to_rotation_matrix().matrix();
    let (e0, e) = (rot.w, rot.imag());
    let mut g_bar = Matrix3xX::zeros(4);
    g_bar.set_column(0, &(-2.0 * e));
    g_bar
        .columns_mut(1, 3)
        .copy_from(&(2.0 * (Matrix3::identity() * e0 - e.cross_matrix())));
    let b = body.mass_blocks(&inv, &q, &a, &g_bar);
    let mut t = InertiaTerms::zeros(Beam3N8::NF);
    body.inertia_terms(&q, &mut t);
    let rel = |x: f64, scale: f64| x <= 1e-14 * scale;
    assert_eq!(b.m_rr, inv.mass);
    let m_rth = -(a * t.s_t.cross_matrix() * &g_bar);
    assert!(rel((&b.m_r_theta - &m_rth).norm(), m_rth.norm()));
    let m_rf = a * &inv.s_bar;
    assert!(rel((&b.m_rf - &m_rf).norm(), m_rf.norm()));
    let m_thth = g_bar.transpose() * t.i_theta_theta * &g_bar;
    assert!(rel((&b.m_theta_theta - &m_thth).norm(), m_thth.norm()));
    let m_thf = g_bar.transpose() * &t.i_theta_f;
    assert!(rel((&b.m_theta_f - &m_thf).norm(), m_thf.norm()));
}
