//! The runtime's assembly of compiled kernels (`KernelBody::compiled` of the
//! fixed-mesh bodies built into this crate: gather, kernel, scatter into the
//! banded blocks) against `ffr-reference` (independent quadrature): the
//! invariants, the elastic force, tangent and energy with the frame at rest
//! (stiffening models as generated), the mass blocks. 1e-12 relative per
//! matrix.

use ffr_bench::arm8::Arm8;
use ffr_bench::bar4::Bar4;
use ffr_bench::{params, random};
use ffr_reference as rf;
use ffr_runtime::nalgebra::DMatrix;
use ffr_runtime::spec::{Formalism, Stiffening};
use ffr_runtime::{Body, BodyForces, BodyMass, BodyState, BodyTangent, CompiledBody, KernelBody};

fn check(what: &str, a: &DMatrix<f64>, b: &DMatrix<f64>, scale: f64) {
    let err = (a - b).norm();
    let r = b.norm().max(scale);
    assert!(err <= 1e-12 * r, "{what}: relative error {:e}", err / r);
}

fn reference_body(shape: rf::Shape, n: usize, r: rf::Reference) -> rf::RefBody {
    // params() is a 20 × 15 mm rectangle: wy = 0.02, wz = 0.015.
    let p = params();
    let rp = rf::RefParams {
        length: p.length,
        rho: p.rho,
        wy: 0.02,
        wz: 0.015,
        e: p.e,
        g: p.g,
        j: p.j,
    };
    assert!((rp.area() - p.area).abs() <= 1e-15 * p.area);
    assert!((rp.iz() - p.iz).abs() <= 1e-15 * p.iz && (rp.iy() - p.iy).abs() <= 1e-15 * p.iy);
    rf::RefBody {
        shape,
        elements: n,
        reference: r,
        params: rp,
    }
}

fn check_body<B: CompiledBody + From<ffr_runtime::spec::Params>>(
    name: &str,
    rb: rf::RefBody,
    formalism: Formalism,
    stiffening: Stiffening,
) where
    B::Kernels: ffr_runtime::ElementKernels,
{
    let body = KernelBody::compiled(&B::from(params())).unwrap();
    let nf = B::NF;
    assert_eq!(body.layout().labels, rb.dof_labels(), "{name}: coordinates");
    let r = match formalism {
        Formalism::Consistent => rb.invariants(),
        Formalism::Lumped => rb.lumped_invariants(),
    };
    let g = body.invariants();
    check(&format!("{name}: m_ff"), &g.m_ff, &r.m_ff, 0.0);
    check(&format!("{name}: K_ff"), &g.k_ff, &r.k_ff, 0.0);
    let sb = |m: &ffr_runtime::nalgebra::Matrix3xX<f64>| DMatrix::from_fn(3, nf, |i, j| m[(i, j)]);
    check(&format!("{name}: S̄"), &sb(&g.s_bar), &sb(&r.s_bar), 0.0);
    let m = |x: f64| DMatrix::from_element(1, 1, x);
    check(&format!("{name}: mass"), &m(g.mass), &m(r.mass), 0.0);

    let model = match stiffening {
        Stiffening::SecondOrder => Some(rf::StiffeningModel::SecondOrder),
        Stiffening::FourthOrder => Some(rf::StiffeningModel::FourthOrder),
        Stiffening::Off => None,
    };
    let l = params().length / B::ELEMENTS as f64;
    let mut w = body.work();
    let hb = body.layout().half_bandwidth;
    for seed in 1..4 {
        let q: Vec<f64> = random(nf, seed, 1.0)
            .iter()
            .zip(&body.layout().labels)
            .map(|(x, lab)| {
                if lab.starts_with('u') {
                    0.1 * l * x
                } else {
                    0.1 * x
                }
            })
            .collect();
        let zero = vec![0.0; nf];
        let s = BodyState {
            q_f: &q,
            qd_f: &zero,
            qdd_f: &zero,
            frame: [0.0; 9],
        };
        let (mut f, mut t) = (BodyForces::zeros(nf), BodyTangent::zeros(nf, hb));
        body.tangent(&s, 0.0, 0.0, true, &mut w, &mut f, &mut t);
        let qv = DMatrix::from_column_slice(nf, 1, &q);
        let mut f_ref = &r.k_ff * &qv;
        let mut k_ref = r.k_ff.clone();
        let mut e_ref = 0.5 * qv.dot(&(&r.k_ff * &qv));
        if let Some(model) = model {
            f_ref +=
                DMatrix::from_column_slice(nf, 1, rb.stiffening_force_with(model, &q).as_slice());
            k_ref += rb.stiffening_tangent_with(model, &q);
            e_ref += rb.stiffening_energy_with(model, &q);
        }
        let t_ = format!("{name} seed {seed}");
        check(
            &format!("{t_}: elastic force"),
            &DMatrix::from_column_slice(nf, 1, &f.f_f),
            &f_ref,
            0.0,
        );
        check(
            &format!("{t_}: elastic tangent"),
            &t.k_ff.to_dense(),
            &k_ref,
            0.0,
        );
        check(
            &format!("{t_}: energy"),
            &m(body.elastic_energy(&q, &mut w)),
            &m(e_ref),
            0.0,
        );
        // At rest the reference rows carry no force.
        assert_eq!(
            (f.f_r, f.f_th),
            ([0.0; 3], [0.0; 3]),
            "{t_}: f_r, f_θ at rest"
        );
        let mut mb = BodyMass::zeros(nf, hb);
        body.mass(&q, &mut w, &mut mb);
        check(
            &format!("{t_}: m_ff (mass)"),
            &mb.m_ff.to_dense(),
            &r.m_ff,
            0.0,
        );
        if formalism == Formalism::Consistent {
            let st = rb.s_t(&q);
            check(
                &format!("{t_}: S_t"),
                &DMatrix::from_column_slice(3, 1, &mb.s_t),
                &DMatrix::from_column_slice(3, 1, st.as_slice()),
                0.0,
            );
            let itt = rb.i_theta_theta(&q);
            let g_itt = DMatrix::from_fn(3, 3, |i, j| mb.m_ref_frame[(3 + i) * 6 + 3 + j]);
            check(
                &format!("{t_}: Ī_θθ"),
                &g_itt,
                &DMatrix::from_fn(3, 3, |i, j| itt[(i, j)]),
                0.0,
            );
        }
    }
}

#[test]
fn compiled_bodies_assembled_by_the_runtime_match_the_reference() {
    check_body::<Arm8>(
        "arm8",
        reference_body(rf::Shape::Beam3, 8, rf::Reference::Clamped),
        Formalism::Consistent,
        Stiffening::FourthOrder,
    );
    check_body::<Bar4>(
        "bar4",
        reference_body(rf::Shape::Beam2, 4, rf::Reference::Pinned),
        Formalism::Lumped,
        Stiffening::SecondOrder,
    );
}
