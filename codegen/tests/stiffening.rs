//! Issue 7's verification at the kernel level: the generated stiffening
//! (second- and fourth-order models, beam2 and beam3).
//!
//! - The force is the gradient of the generated energy and the tangent the
//!   gradient of the force, by central finite differences at random states
//!   on tapes of the generated programs (the compiled code's arithmetic).
//!   The energy is a polynomial of degree 4 in `q` and the force of degree 3,
//!   so Richardson-extrapolated central differences (`(4 D(h/2) − D(h))/3`,
//!   error `O(h⁴ f⁽⁵⁾)`) are exact up to rounding: the tolerances are tight.
//! - Exactly, as rational polynomials, against hand-written shape functions:
//!   the fourth-order energy is `½ E A l (ε̄² − ū'²)` plus `½ E I_z ∫ v''² v'² dx`
//!   in the plane and `½ ∫ [E I_z v''·v'g + E I_y w''·w'g] dx` (`g = v'v'' +
//!   w'w''`) in space; beam3 with only in-plane coordinates is beam2, and
//!   with only out-of-plane coordinates it is beam2 with `I_y` for `I_z`; the
//!   second-order model is `E A l (½ ū' s̄ + ⅛ s̄²)` per element.

mod common;

use common::*;
use ffr_codegen::energy::element_energy;
use ffr_codegen::poly::{rat, Monomial, Param, Poly, Sym};
use ffr_codegen::{BodySpec, Formalism, Reference, Shape, Stiffening};
use nalgebra::DMatrix;

const MODELS: [Stiffening; 2] = [Stiffening::SecondOrder, Stiffening::FourthOrder];

/// `d/dt f(t)` at `t = 0` by Richardson-extrapolated central differences.
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

fn with(q: &[f64], a: usize, t: f64) -> Vec<f64> {
    let mut v = q.to_vec();
    v[a] += t;
    v
}

/// `h` for coordinate `a`: a thousandth of the state's scale of that kind.
fn step(body: &TapeBody, a: usize, slope: f64) -> f64 {
    let d = body.spec.dofs()[a];
    1e-3 * slope * if d.kind.is_translation() { body.l } else { 1.0 }
}

/// Force = ∇ energy, tangent = ∇ force (elastic kernels with the frame at
/// rest), for the whole elastic energy and for its nonlinear part alone.
#[test]
fn force_is_the_gradient_of_the_energy_and_tangent_the_gradient_of_the_force() {
    let mut worst = [0.0f64; 4];
    for shape in ["beam2", "beam3"] {
        let off = kernel_set(shape, Formalism::Consistent, Stiffening::Off, 3, false);
        for model in MODELS {
            let set = kernel_set(shape, Formalism::Consistent, model, 3, false);
            for (n, r) in [(1, Reference::Free), (3, Reference::Clamped)] {
                for (ip, rp) in param_sets().iter().enumerate() {
                    let p = params_of(rp);
                    let body = TapeBody::new(&set, n, r, p);
                    let body0 = TapeBody::new(&off, n, r, p);
                    let nf = body.nf();
                    let zero = vec![0.0; nf];
                    let frame = [0.0; 9];
                    for (is, slope) in [0.02, 0.1, 0.4].into_iter().enumerate() {
                        let q = state(&body.spec, body.l, (ip * 5 + is + n) as u64, slope);
                        let t = format!("{shape} {model} N={n} L={} slope {slope}", rp.length);
                        let force =
                            |b: &TapeBody, q: &[f64]| b.residual_elastic(q, &zero, &zero, &frame);
                        let f = force(&body, &q);
                        let f0 = force(&body0, &q);
                        let (_, k) = body.tangent_elastic(&q, &zero, &zero, &frame, 0.0, 0.0);
                        let (_, k0) = body0.tangent_elastic(&q, &zero, &zero, &frame, 0.0, 0.0);
                        let mut g = vec![0.0; nf];
                        let mut g_nl = vec![0.0; nf];
                        let mut kfd = DMatrix::zeros(nf, nf);
                        let mut kfd_nl = DMatrix::zeros(nf, nf);
                        for a in 0..nf {
                            let h = step(&body, a, slope);
                            g[a] = derivative(|s| vec![body.energy(&with(&q, a, s))], h)[0];
                            g_nl[a] = derivative(
                                |s| {
                                    let qq = with(&q, a, s);
                                    vec![body.energy(&qq) - body0.energy(&qq)]
                                },
                                h,
                            )[0];
                            let col_a = derivative(|s| force(&body, &with(&q, a, s)), h);
                            let col_nl = derivative(
                                |s| {
                                    let qq = with(&q, a, s);
                                    let (x, y) = (force(&body, &qq), force(&body0, &qq));
                                    x.iter().zip(&y).map(|(x, y)| x - y).collect()
                                },
                                h,
                            );
                            for i in 0..nf {
                                kfd[(i, a)] = col_a[i];
                                kfd_nl[(i, a)] = col_nl[i];
                            }
                        }
                        let f_nl: Vec<f64> = f.iter().zip(&f0).map(|(a, b)| a - b).collect();
                        let cases = [
                            ("force = ∇ energy", col(&g), col(&f), 1e-9),
                            ("nonlinear force = ∇ U_nl", col(&g_nl), col(&f_nl), 1e-7),
                            ("tangent = ∇ force", kfd, k.clone(), 1e-9),
                            (
                                "nonlinear tangent = ∇ nonlinear force",
                                kfd_nl,
                                &k - &k0,
                                1e-7,
                            ),
                        ];
                        for (i, (what, fd, exact, tol)) in cases.into_iter().enumerate() {
                            let rel = (&fd - &exact).norm() / exact.norm();
                            worst[i] = worst[i].max(rel);
                            check(&format!("{t}: {what}"), &fd, &exact, 0.0, tol);
                        }
                        // The tangent of an energy is symmetric, exactly (each
                        // pair is computed once).
                        assert_eq!(k, k.transpose(), "{t}: tangent not symmetric");
                    }
                }
            }
        }
    }
    eprintln!(
        "finite differences, worst relative error: force {:e}, nonlinear force {:e}, tangent {:e}, nonlinear tangent {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

// ---- exact checks against hand-written shape functions ----

fn p(param: Param) -> Poly {
    Poly::var(Sym::Param(param))
}
fn q(i: u32) -> Poly {
    Poly::var(Sym::Q(i))
}
fn xi() -> Poly {
    Poly::var(Sym::Xi)
}
fn c(n: i64, d: i64) -> Poly {
    Poly::constant(rat(n, d))
}
fn inv_l(e: i32) -> Monomial {
    Monomial::var(Sym::Param(Param::ElemLength), -e)
}
fn d_dx(f: &Poly) -> Poly {
    f.diff(Sym::Xi).mul_monomial(&inv_l(1))
}

/// Hermite cubics `N1..N4(ξ)` (`v = N1 v1 + l N2 θ1 + N3 v2 + l N4 θ2`).
fn hermite() -> [Poly; 4] {
    let (x, x2, x3) = (xi(), xi().pow(2), xi().pow(3));
    [
        c(1, 1)
            .sub(&x2.scale(&rat(3, 1)))
            .add(&x3.scale(&rat(2, 1))),
        x.sub(&x2.scale(&rat(2, 1))).add(&x3),
        x2.scale(&rat(3, 1)).sub(&x3.scale(&rat(2, 1))),
        x3.sub(&x2),
    ]
}

/// Centre-line fields `(u, v, w)` of one element, written by hand:
/// beam2 `[u1 v1 θz1 u2 v2 θz2]`, beam3 `[u1 v1 w1 θx1 θy1 θz1 u2 …]` with
/// `w = N1 w1 − l N2 θy1 + N3 w2 − l N4 θy2` (`θy = −w'`).
fn fields(shape: &str) -> (Poly, Poly, Poly) {
    let [n1, n2, n3, n4] = hermite();
    let l = p(Param::ElemLength);
    let lin = |a: u32, b: u32| c(1, 1).sub(&xi()).mul(&q(a)).add(&xi().mul(&q(b)));
    let cubic = |v1: u32, t1: u32, v2: u32, t2: u32, sign: i64| {
        n1.mul(&q(v1))
            .add(&l.mul(&n2).mul(&q(t1)).scale(&rat(sign, 1)))
            .add(&n3.mul(&q(v2)))
            .add(&l.mul(&n4).mul(&q(t2)).scale(&rat(sign, 1)))
    };
    match shape {
        "beam2" => (lin(0, 3), cubic(1, 2, 4, 5, 1), Poly::zero()),
        "beam3" => (lin(0, 6), cubic(1, 5, 7, 11, 1), cubic(2, 4, 8, 10, -1)),
        s => panic!("{s}"),
    }
}

/// `(ū', s̄)` of the hand-written fields.
fn means(shape: &str) -> (Poly, Poly) {
    let (u, v, w) = fields(shape);
    let (u1, v1, w1) = (d_dx(&u), d_dx(&v), d_dx(&w));
    (
        u1.integrate_xi(),
        v1.mul(&v1).add(&w1.mul(&w1)).integrate_xi(),
    )
}

fn ea_l() -> Poly {
    p(Param::E).mul(&p(Param::Area)).mul(&p(Param::ElemLength))
}

/// `½ E A l (ε̄² − ū'²)`, `ε̄ = ū' + ½ ū'² + ½ s̄`.
fn fourth_order_axial(shape: &str) -> Poly {
    let (du, s) = means(shape);
    let eps = du
        .add(&du.mul(&du).scale(&rat(1, 2)))
        .add(&s.scale(&rat(1, 2)));
    ea_l()
        .mul(&eps.mul(&eps).sub(&du.mul(&du)))
        .scale(&rat(1, 2))
}

/// `½ ∫₀ˡ [E I_z v''·v'g + E I_y w''·w'g] dx`, `g = v'v'' + w'w''`.
fn fourth_order_bending(shape: &str) -> Poly {
    let (_, v, w) = fields(shape);
    let (v1, w1) = (d_dx(&v), d_dx(&w));
    let (v2, w2) = (d_dx(&v1), d_dx(&w1));
    let g = v1.mul(&v2).add(&w1.mul(&w2));
    let eiz = p(Param::E).mul(&p(Param::Iz));
    let eiy = p(Param::E).mul(&p(Param::Iy));
    eiz.mul(&v2)
        .mul(&v1)
        .mul(&g)
        .add(&eiy.mul(&w2).mul(&w1).mul(&g))
        .integrate_xi()
        .mul(&p(Param::ElemLength))
        .scale(&rat(1, 2))
}

fn generated(shape: &str, model: Stiffening) -> Poly {
    element_energy(&Shape::resolve(shape, None).unwrap(), model)
        .unwrap()
        .in_coordinates()
}

#[test]
fn fourth_order_energy_is_the_documented_formula_exactly() {
    for shape in ["beam2", "beam3"] {
        let expect = fourth_order_axial(shape).add(&fourth_order_bending(shape));
        assert_eq!(generated(shape, Stiffening::FourthOrder), expect, "{shape}");
    }
}

#[test]
fn fourth_order_planar_bending_is_half_ei_integral_of_v2_squared_v1_squared() {
    // ½ E I_z ∫₀ˡ v''² v'² dx with the hand-written beam2 field.
    let (_, v, _) = fields("beam2");
    let (v1, v2) = (d_dx(&v), d_dx(&d_dx(&v)));
    let bend = p(Param::E)
        .mul(&p(Param::Iz))
        .mul(&v2.mul(&v2).mul(&v1).mul(&v1))
        .integrate_xi()
        .mul(&p(Param::ElemLength))
        .scale(&rat(1, 2));
    let g = generated("beam2", Stiffening::FourthOrder);
    assert_eq!(g.sub(&fourth_order_axial("beam2")), bend);
    // The same for beam3 with w = 0 (w1, θy1, w2, θy2 and the twists set to zero).
    let g3 = generated("beam3", Stiffening::FourthOrder).rename(|s| match s {
        Sym::Q(2 | 3 | 4 | 8 | 9 | 10) => None,
        s => Some(s),
    });
    let axial3 = fourth_order_axial("beam3").rename(|s| match s {
        Sym::Q(2 | 3 | 4 | 8 | 9 | 10) => None,
        s => Some(s),
    });
    let to_beam3 = |s: Sym| match s {
        Sym::Q(i) => Some(Sym::Q([0, 1, 5, 6, 7, 11][i as usize])),
        s => Some(s),
    };
    assert_eq!(g3.sub(&axial3), bend.rename(to_beam3));
}

/// beam3 restricted to the x–y plane is beam2; restricted to the x–z plane
/// it is beam2 with `I_y` for `I_z` and `θy = −w'` (both models).
#[test]
fn beam3_in_a_plane_is_beam2() {
    for model in MODELS {
        let b2 = generated("beam2", model);
        let b3 = generated("beam3", model);
        // x–y: beam3 [u1 v1 · · · θz1 u2 v2 · · · θz2] ← beam2 [u1 v1 θz1 u2 v2 θz2].
        let in_plane = b3.rename(|s| match s {
            Sym::Q(2 | 3 | 4 | 8 | 9 | 10) => None,
            s => Some(s),
        });
        let b2_as_3 = b2.rename(|s| match s {
            Sym::Q(i) => Some(Sym::Q([0, 1, 5, 6, 7, 11][i as usize])),
            s => Some(s),
        });
        assert_eq!(in_plane, b2_as_3, "{model}: x–y plane");
        // x–z: beam3 [u1 · w1 · θy1 · u2 · w2 · θy2 ·] with θy = −θz of beam2.
        let out_of_plane = b3.rename(|s| match s {
            Sym::Q(1 | 3 | 5 | 7 | 9 | 11) => None,
            s => Some(s),
        });
        let b2_xz = b2
            .rename(|s| match s {
                Sym::Q(i) => Some(Sym::Q([0, 2, 104, 6, 8, 110][i as usize])),
                Sym::Param(Param::Iz) => Some(Sym::Param(Param::Iy)),
                s => Some(s),
            })
            .substitute(Sym::Q(104), &q(4).scale(&rat(-1, 1)))
            .substitute(Sym::Q(110), &q(10).scale(&rat(-1, 1)));
        assert_eq!(out_of_plane, b2_xz, "{model}: x–z plane");
    }
}

#[test]
fn second_order_is_ea_l_times_half_du_sbar_plus_eighth_sbar_squared() {
    for shape in ["beam2", "beam3"] {
        let (du, s) = means(shape);
        let expect = ea_l().mul(
            &du.mul(&s)
                .scale(&rat(1, 2))
                .add(&s.mul(&s).scale(&rat(1, 8))),
        );
        assert_eq!(generated(shape, Stiffening::SecondOrder), expect, "{shape}");
    }
}

/// The same on the tapes: beam3's kernels with only in-plane coordinates
/// give beam2's energy, force and tangent (to rounding: the programs differ),
/// and nothing out of plane.
#[test]
fn beam3_kernels_in_plane_equal_beam2_kernels() {
    let in_plane = [0usize, 1, 5, 6, 7, 11];
    for model in [
        Stiffening::Off,
        Stiffening::SecondOrder,
        Stiffening::FourthOrder,
    ] {
        let s2 = kernel_set("beam2", Formalism::Consistent, model, 3, false);
        let s3 = kernel_set("beam3", Formalism::Consistent, model, 3, false);
        for (ip, rp) in param_sets().iter().enumerate() {
            let p = params_of(rp);
            let b2 = TapeBody::new(&s2, 1, Reference::Free, p);
            let b3 = TapeBody::new(&s3, 1, Reference::Free, p);
            let q2 = state(&b2.spec, b2.l, ip as u64 + 1, 0.3);
            let mut q3 = vec![0.0; 12];
            for (a, &i) in in_plane.iter().enumerate() {
                q3[i] = q2[a];
            }
            let t = format!("{model} L={}", rp.length);
            let (e2, e3) = (b2.energy(&q2), b3.energy(&q3));
            assert!(
                (e2 - e3).abs() <= 1e-14 * e2.abs(),
                "{t}: energy {e2} vs {e3}"
            );
            let (z2, z3) = (vec![0.0; 6], vec![0.0; 12]);
            let (f2, k2) = b2.tangent_elastic(&q2, &z2, &z2, &[0.0; 9], 0.0, 0.0);
            let (f3, k3) = b3.tangent_elastic(&q3, &z3, &z3, &[0.0; 9], 0.0, 0.0);
            let f3_in = DMatrix::from_fn(6, 1, |a, _| f3[in_plane[a]]);
            check(&format!("{t}: force"), &f3_in, &col(&f2), 0.0, 1e-14);
            let k3_in = DMatrix::from_fn(6, 6, |a, b| k3[(in_plane[a], in_plane[b])]);
            check(&format!("{t}: tangent"), &k3_in, &k2, 0.0, 1e-14);
            for i in (0..12).filter(|i| !in_plane.contains(i)) {
                assert_eq!(f3[i], 0.0, "{t}: out-of-plane force {i}");
            }
        }
    }
}

/// `BodySpec::stiffening_energy` (the exact body polynomial) is the sum of
/// the element energies the kernels compute, and the reference's.
#[test]
fn body_stiffening_energy_is_the_sum_over_elements() {
    for shape in ["beam2", "beam3"] {
        for model in MODELS {
            let set = kernel_set(shape, Formalism::Consistent, model, 3, false);
            let off = kernel_set(shape, Formalism::Consistent, Stiffening::Off, 3, false);
            let rp = param_sets()[3];
            let pv = params_of(&rp);
            let spec =
                BodySpec::new(Shape::resolve(shape, None).unwrap(), 3, Reference::Pinned).unwrap();
            let body = TapeBody::new(&set, 3, Reference::Pinned, pv);
            let body0 = TapeBody::new(&off, 3, Reference::Pinned, pv);
            let qv = state(&body.spec, body.l, 9, 0.2);
            let exact = spec.stiffening_energy(model);
            let value: f64 = exact
                .terms()
                .map(|(m, c)| {
                    use num_traits::ToPrimitive;
                    m.factors()
                        .iter()
                        .fold(c.to_f64().unwrap(), |acc, &(s, e)| {
                            acc * match s {
                                Sym::Q(i) => qv[i as usize],
                                Sym::Param(par) => pv.get(par).unwrap(),
                                s => panic!("{s}"),
                            }
                            .powi(e)
                        })
                })
                .sum();
            let kernels = body.energy(&qv) - body0.energy(&qv);
            let reference = ref_body(shape, &rp).stiffening_energy_with(
                match model {
                    Stiffening::SecondOrder => ffr_reference::StiffeningModel::SecondOrder,
                    _ => ffr_reference::StiffeningModel::FourthOrder,
                },
                &qv,
            );
            assert!(
                (value - reference).abs() <= 1e-12 * reference.abs(),
                "{shape} {model}: exact {value} vs reference {reference}"
            );
            assert!(
                (kernels - reference).abs() <= 1e-10 * reference.abs(),
                "{shape} {model}: kernels {kernels} vs reference {reference}"
            );
        }
    }
}

fn ref_body(shape: &str, rp: &ffr_reference::RefParams) -> ffr_reference::RefBody {
    ffr_reference::RefBody {
        shape: rf_shape(shape),
        elements: 3,
        reference: ffr_reference::Reference::Pinned,
        params: *rp,
    }
}
