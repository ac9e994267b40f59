//! The derivative kernels are the derivatives of the residual kernels: on
//! tapes of the generated programs, at random states (coordinates,
//! velocities, accelerations, frame motion, generalized-α factors), every
//! output of `tangent`, `tangent_elastic` and `mass` against central finite
//! differences of `residual` / `residual_elastic`:
//!
//! - `K = ∂f/∂q + γ' ∂f/∂q̇ + β' ∂f/∂q̈` as the derivative along
//!   `(q, q̇, q̈) + t (e_a, γ' e_a, β' e_a)`;
//! - `∂f/∂[ā, α, ω]`;
//! - the mass blocks `∂f/∂q̈`, `∂f/∂[ā, α]` and `S_t` inside them.
//!
//! The residual is a polynomial of degree at most 3 in each direction, so
//! Richardson-extrapolated central differences are exact up to rounding for
//! any step: the steps are large (a tenth of the state's scale, the frame
//! motion's scale) to keep the rounding of the large elastic terms small.
//! beam2 (planar and spatial scene) and beam3, both formalisms, stiffening
//! off and fourth-order, a clamped 2-element body.

mod common;

use common::*;
use ffr_codegen::{Formalism, Reference, Shape, Stiffening};
use nalgebra::DMatrix;

fn derivative(f: impl Fn(f64) -> Vec<f64>, h: f64) -> Vec<f64> {
    let d = |h: f64| -> Vec<f64> {
        let (p, m) = (f(h), f(-h));
        p.iter().zip(&m).map(|(a, b)| (a - b) / (2.0 * h)).collect()
    };
    let (d1, d2) = (d(h), d(h / 2.0));
    d1.iter()
        .zip(&d2)
        .map(|(a, b)| (4.0 * b - a) / 3.0)
        .collect()
}

/// `[f_r; f_θ; f_f]` as one vector.
fn stacked(f: &ForcesAsm) -> Vec<f64> {
    f.f_r.iter().chain(&f.f_th).chain(&f.f_f).copied().collect()
}

/// Finite differences carry rounding of order `ε |f| / h` per column; with
/// a large elastic part (`|K q| ≫` the inertia terms, e.g. the micro beam)
/// that is the limit. Allowed: `1e-8 |exact| + 1e-13 √(Σ_c (|f| / h_c)²)`.
fn check_fd(
    what: &str,
    fd: &DMatrix<f64>,
    exact: &DMatrix<f64>,
    f_norm: f64,
    steps: &[f64],
) -> f64 {
    let noise = 1e-13
        * steps
            .iter()
            .map(|h| (f_norm / h).powi(2))
            .sum::<f64>()
            .sqrt();
    let err = (fd - exact).norm();
    assert!(
        err <= 1e-8 * exact.norm() + noise,
        "{what}: |fd − exact| = {err:e}, |exact| = {:e}, rounding allowance {noise:e}",
        exact.norm()
    );
    err / exact.norm()
}

fn columns(cols: Vec<Vec<f64>>) -> DMatrix<f64> {
    let rows = cols[0].len();
    DMatrix::from_fn(rows, cols.len(), |i, j| cols[j][i])
}

#[test]
fn tangent_kernels_are_the_derivatives_of_the_residual_kernels() {
    let mut worst = [0.0f64; 4];
    for shape in ["beam2", "beam3"] {
        let dim = Shape::resolve(shape, None).unwrap().dimension;
        for f in [Formalism::Consistent, Formalism::Lumped] {
            for model in [Stiffening::Off, Stiffening::FourthOrder] {
                for scene in dim..=3 {
                    let set = kernel_set(shape, f, model, scene, true);
                    for (ip, rp) in param_sets().iter().enumerate() {
                        let body = TapeBody::new(&set, 2, Reference::Clamped, params_of(rp));
                        let nf = body.nf();
                        let seed = ip as u64 * 17 + 1;
                        let len = rp.length;
                        let q = state(&body.spec, body.l, seed, 0.1);
                        let qd = state(&body.spec, body.l, seed + 1, 0.5);
                        let qdd = state(&body.spec, body.l, seed + 2, 3.0);
                        let r = pseudo_random(11, seed + 3, 1.0);
                        let live = |k: usize| scene == 3 || matches!(k, 0 | 1 | 5 | 8);
                        let fscale = |k: usize| if k < 3 { 10.0 * len.min(1.0) } else { 1.0 };
                        let mut frame = [0.0; 9];
                        for k in (0..9).filter(|&k| live(k)) {
                            frame[k] = fscale(k) * r[k];
                        }
                        // β' ~ 1/(β h²), γ' ~ γ/(β h) for h = 1e-3.
                        let (bp, gp) = (4e6 * (1.0 + 0.1 * r[9]), 2e3 * (1.0 + 0.1 * r[10]));
                        let t = format!("{shape} {f} {model} scene {scene} L={len}");

                        let tan = body.tangent(&q, &qd, &qdd, &frame, bp, gp);
                        let res = body.residual(&q, &qd, &qdd, &frame);
                        assert_eq!(
                            stacked(&tan),
                            stacked(&res),
                            "{t}: tangent's residual differs"
                        );

                        let hq = |a: usize| {
                            if body.spec.dofs()[a].kind.is_translation() {
                                0.01 * body.l
                            } else {
                                0.01
                            }
                        };
                        let along = |a: usize, s: f64| {
                            let mut x = (q.clone(), qd.clone(), qdd.clone());
                            x.0[a] += s;
                            x.1[a] += gp * s;
                            x.2[a] += bp * s;
                            x
                        };
                        let res_at = |x: &(Vec<f64>, Vec<f64>, Vec<f64>), fr: &[f64; 9]| {
                            stacked(&body.residual(&x.0, &x.1, &x.2, fr))
                        };
                        // K (all rows) by the generalized-α direction.
                        let kcols: Vec<Vec<f64>> = (0..nf)
                            .map(|a| derivative(|s| res_at(&along(a, s), &frame), hq(a)))
                            .collect();
                        let k_fd = columns(kcols);
                        let mut k = DMatrix::zeros(6 + nf, nf);
                        k.rows_mut(0, 6).copy_from(&tan.k_ref_f);
                        k.rows_mut(6, nf).copy_from(&tan.k_ff);
                        let f_norm = col(&stacked(&res)).norm();
                        let k_steps: Vec<f64> = (0..nf).map(hq).collect();
                        let rel = check_fd(
                            &format!("{t}: [K_ref,f; K_ff]"),
                            &k_fd,
                            &k,
                            f_norm,
                            &k_steps,
                        );
                        worst[ip] = worst[ip].max(rel);
                        // Frame derivatives (zero columns for what a planar scene lacks).
                        let dcols: Vec<Vec<f64>> = (0..9)
                            .map(|kf| {
                                let x = (q.clone(), qd.clone(), qdd.clone());
                                derivative(
                                    |s| {
                                        let mut fr = frame;
                                        fr[kf] += s;
                                        res_at(&x, &fr)
                                    },
                                    fscale(kf),
                                )
                            })
                            .collect();
                        let d_fd = columns(dcols);
                        let mut d = DMatrix::zeros(6 + nf, 9);
                        d.rows_mut(0, 6).copy_from(&tan.d_ref_frame);
                        d.rows_mut(6, nf).copy_from(&tan.d_f_frame);
                        let d_steps: Vec<f64> = (0..9).map(fscale).collect();
                        let rel = check_fd(&format!("{t}: ∂f/∂frame"), &d_fd, &d, f_norm, &d_steps);
                        worst[ip] = worst[ip].max(rel);

                        // tangent_elastic = the f_f rows of tangent, and its K_ff.
                        let (fe, kee) = body.tangent_elastic(&q, &qd, &qdd, &frame, bp, gp);
                        assert_eq!(fe, tan.f_f, "{t}: tangent_elastic's f_f");
                        assert_eq!(kee, tan.k_ff, "{t}: tangent_elastic's K_ff");
                        assert_eq!(
                            body.residual_elastic(&q, &qd, &qdd, &frame),
                            res.f_f,
                            "{t}: residual_elastic"
                        );

                        // Mass blocks: the residual is linear in q̈ and [ā, α].
                        let m = body.mass(&q);
                        let m_step = |a: usize| 300.0 * hq(a);
                        let m_steps: Vec<f64> = (0..nf).map(m_step).collect();
                        let mcols: Vec<Vec<f64>> = (0..nf)
                            .map(|a| {
                                derivative(
                                    |s| {
                                        let mut x = (q.clone(), qd.clone(), qdd.clone());
                                        x.2[a] += s;
                                        res_at(&x, &frame)
                                    },
                                    m_step(a),
                                )
                            })
                            .collect();
                        let m_fd = columns(mcols);
                        worst[ip] = worst[ip].max(check_fd(
                            &format!("{t}: m_ff"),
                            &m_fd.rows(6, nf).into(),
                            &m.m_ff,
                            f_norm,
                            &m_steps,
                        ));
                        worst[ip] = worst[ip].max(check_fd(
                            &format!("{t}: ∂f_ref/∂q̈"),
                            &m_fd.rows(0, 6).into(),
                            &m.m_ref_f,
                            f_norm,
                            &m_steps,
                        ));
                        let d6 = d_fd.columns(0, 6);
                        worst[ip] = worst[ip].max(check_fd(
                            &format!("{t}: ∂f_f/∂[ā, α]"),
                            &d6.rows(6, nf).into(),
                            &m.m_f_frame,
                            f_norm,
                            &d_steps[..6],
                        ));
                        worst[ip] = worst[ip].max(check_fd(
                            &format!("{t}: ∂f_ref/∂[ā, α]"),
                            &d6.rows(0, 6).into(),
                            &m.m_ref_frame,
                            f_norm,
                            &d_steps[..6],
                        ));
                        // … and S_t sits in −S̃_t (rows f_r, columns α).
                        let st = m.s_t;
                        let skew = DMatrix::from_row_slice(
                            3,
                            3,
                            &[0.0, st[2], -st[1], -st[2], 0.0, st[0], st[1], -st[0], 0.0],
                        );
                        let block: DMatrix<f64> = m.m_ref_frame.view((0, 3), (3, 3)).into();
                        let expect = if scene == 2 {
                            DMatrix::from_fn(
                                3,
                                3,
                                |i, j| if i < 2 && j == 2 { skew[(i, j)] } else { 0.0 },
                            )
                        } else {
                            skew
                        };
                        assert_eq!(block, expect, "{t}: S_t and −S̃_t");
                    }
                }
            }
        }
    }
    eprintln!(
        "tangent and mass kernels vs finite differences, worst relative error per parameter set (L = 1, 1e-3, 1e2, 8 m): {:e} {:e} {:e} {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}
