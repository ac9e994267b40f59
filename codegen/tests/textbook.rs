//! Textbook checks, exact: the generator's invariants as rational
//! polynomials compared with the classic closed forms (theory sheet,
//! "Checks any correct implementation passes").

use ffr_codegen::body::{ExactInvariants, PolyMatrix};
use ffr_codegen::poly::{rat, Monomial, Param, Poly, Rational, Sym};
use ffr_codegen::{BodySpec, Formalism, Reference, Shape};
use num_traits::Zero;

fn body(shape: &str, n: usize, r: Reference) -> ExactInvariants {
    BodySpec::new(Shape::resolve(shape, None).unwrap(), n, r)
        .unwrap()
        .exact_invariants()
        .unwrap()
}

/// `c · Π params^e` as a polynomial.
fn mono(c: Rational, factors: &[(Param, i32)]) -> Poly {
    let m = factors.iter().fold(Monomial::one(), |m, &(p, e)| {
        m.mul(&Monomial::var(Sym::Param(p), e))
    });
    Poly::term(c, m)
}

use Param::{Area, Iy, Iz, Length as L, Rho, E, G, J};

#[test]
fn total_mass_static_moment_and_theta_xx() {
    for shape in ["beam2", "beam3"] {
        for n in 1..=5 {
            for r in [Reference::Clamped, Reference::Pinned, Reference::Free] {
                for f in [Formalism::Consistent, Formalism::Lumped] {
                    let inv = BodySpec::new(Shape::resolve(shape, None).unwrap(), n, r)
                        .unwrap()
                        .with_formalism(f)
                        .exact_invariants()
                        .unwrap();
                    assert_eq!(inv.mass, mono(rat(1, 1), &[(L, 1), (Rho, 1), (Area, 1)]));
                    assert_eq!(inv.s_t0[0], mono(rat(1, 2), &[(L, 2), (Rho, 1), (Area, 1)]));
                    assert!(inv.s_t0[1].is_zero() && inv.s_t0[2].is_zero());
                    if f == Formalism::Consistent {
                        // Θ_xx = ρAL³/3, Θ_yy = ρ I_z L, Θ_zz = ρ I_y L (spatial).
                        assert_eq!(
                            inv.theta[0][0],
                            mono(rat(1, 3), &[(L, 3), (Rho, 1), (Area, 1)])
                        );
                        assert_eq!(
                            inv.theta[1][1],
                            mono(rat(1, 1), &[(L, 1), (Rho, 1), (Iz, 1)])
                        );
                        let zz = if shape == "beam3" {
                            mono(rat(1, 1), &[(L, 1), (Rho, 1), (Iy, 1)])
                        } else {
                            Poly::zero()
                        };
                        assert_eq!(inv.theta[2][2], zz);
                    } else {
                        // Nodal masses: the trapezoidal rule of ∫ρAx² dx, plus
                        // each element end's HRZ spread along the axis,
                        // 2N · (ρA l/2) l²/39 = ρA L³/(39 N²).
                        let trapezoid = (0..=n as i64)
                            .map(|j| {
                                let w = if j == 0 || j == n as i64 {
                                    rat(1, 2)
                                } else {
                                    rat(1, 1)
                                };
                                w * rat(j * j, (n * n * n) as i64)
                            })
                            .fold(Rational::zero(), |a, b| a + b);
                        let expect = trapezoid + rat(1, 39 * (n * n) as i64);
                        assert_eq!(
                            inv.theta[0][0],
                            mono(expect, &[(L, 3), (Rho, 1), (Area, 1)])
                        );
                    }
                }
            }
        }
    }
}

/// The free one-element planar m_ff: `ρAl/420 · M + ρI_z/(30l) · R`.
#[test]
fn planar_element_mass_is_classic_consistent_plus_rotary() {
    let inv = body("beam2", 1, Reference::Free);
    let m: [[(i64, i32); 6]; 6] = [
        [(140, 0), (0, 0), (0, 0), (70, 0), (0, 0), (0, 0)],
        [(0, 0), (156, 0), (22, 1), (0, 0), (54, 0), (-13, 1)],
        [(0, 0), (22, 1), (4, 2), (0, 0), (13, 1), (-3, 2)],
        [(70, 0), (0, 0), (0, 0), (140, 0), (0, 0), (0, 0)],
        [(0, 0), (54, 0), (13, 1), (0, 0), (156, 0), (-22, 1)],
        [(0, 0), (-13, 1), (-3, 2), (0, 0), (-22, 1), (4, 2)],
    ];
    let r: [[(i64, i32); 6]; 6] = [
        [(0, 0); 6],
        [(0, 0), (36, 0), (3, 1), (0, 0), (-36, 0), (3, 1)],
        [(0, 0), (3, 1), (4, 2), (0, 0), (-3, 1), (-1, 2)],
        [(0, 0); 6],
        [(0, 0), (-36, 0), (-3, 1), (0, 0), (36, 0), (-3, 1)],
        [(0, 0), (3, 1), (-1, 2), (0, 0), (-3, 1), (4, 2)],
    ];
    for i in 0..6 {
        for j in 0..6 {
            let (cm, pm) = m[i][j];
            let (cr, pr) = r[i][j];
            let expect = mono(rat(cm, 420), &[(L, 1 + pm), (Rho, 1), (Area, 1)])
                .add(&mono(rat(cr, 30), &[(L, pr - 1), (Rho, 1), (Iz, 1)]));
            assert_eq!(inv.m_ff.get(i, j), &expect, "m_ff[{i}][{j}]");
        }
    }
}

/// The one-element stiffness: `EA/l` axial, `EI/l³ [12 6l −12 6l; …]`
/// bending (`I_z` in x–y, `I_y` in x–z with `θ_y = −w'`), `GJ/l` torsion.
#[test]
fn element_stiffness_is_classic_euler_bernoulli() {
    let bending = |i: usize, j: usize| -> (i64, i32) {
        const B: [[(i64, i32); 4]; 4] = [
            [(12, 0), (6, 1), (-12, 0), (6, 1)],
            [(6, 1), (4, 2), (-6, 1), (2, 2)],
            [(-12, 0), (-6, 1), (12, 0), (-6, 1)],
            [(6, 1), (2, 2), (-6, 1), (4, 2)],
        ];
        B[i][j]
    };
    let ei = |c: i64, p: i32, iz: Param| mono(rat(c, 1), &[(L, p - 3), (iz, 1), (E, 1)]);
    // beam2: [u1 v1 θ1 u2 v2 θ2]
    let k = body("beam2", 1, Reference::Free).k_ff;
    let axial = [0usize, 3];
    let bend = [1usize, 2, 4, 5];
    for (a, &i) in axial.iter().enumerate() {
        for (b, &j) in axial.iter().enumerate() {
            let s = if a == b { 1 } else { -1 };
            assert_eq!(k.get(i, j), &mono(rat(s, 1), &[(L, -1), (Area, 1), (E, 1)]));
        }
    }
    for (a, &i) in bend.iter().enumerate() {
        for (b, &j) in bend.iter().enumerate() {
            let (c, p) = bending(a, b);
            assert_eq!(k.get(i, j), &ei(c, p, Iz), "beam2 K[{i}][{j}]");
        }
        for &j in &axial {
            assert!(k.get(i, j).is_zero());
        }
    }
    // beam3: [u1 v1 w1 θx1 θy1 θz1 u2 v2 w2 θx2 θy2 θz2]
    let k = body("beam3", 1, Reference::Free).k_ff;
    let v = [1usize, 5, 7, 11];
    let w = [2usize, 4, 8, 10];
    for a in 0..4 {
        for b in 0..4 {
            let (c, p) = bending(a, b);
            assert_eq!(k.get(v[a], v[b]), &ei(c, p, Iz), "beam3 K v-block");
            // θ_y = −w': the rotation rows/columns change sign.
            let s = if (a % 2 == 1) ^ (b % 2 == 1) { -1 } else { 1 };
            assert_eq!(k.get(w[a], w[b]), &ei(s * c, p, Iy), "beam3 K w-block");
            assert!(k.get(v[a], w[b]).is_zero());
        }
    }
    for (i, j, s) in [(3, 3, 1), (3, 9, -1), (9, 9, 1)] {
        assert_eq!(k.get(i, j), &mono(rat(s, 1), &[(L, -1), (G, 1), (J, 1)]));
    }
}

/// Exact rank of a polynomial matrix at rational parameter values.
fn rank_at(m: &PolyMatrix, values: &[(Param, Rational)]) -> usize {
    let value = |p: Param| values.iter().find(|(q, _)| *q == p).unwrap().1.clone();
    let eval = |p: &Poly| -> Rational {
        p.terms()
            .map(|(mono, c)| {
                mono.factors().iter().fold(c.clone(), |acc, &(s, e)| {
                    let Sym::Param(par) = s else {
                        panic!("non-parameter symbol {s}")
                    };
                    let v = value(par);
                    let v = if e < 0 { v.recip() } else { v };
                    acc * num_traits::pow(v, e.unsigned_abs() as usize)
                })
            })
            .fold(Rational::zero(), |a, b| a + b)
    };
    let mut a: Vec<Vec<Rational>> = (0..m.rows)
        .map(|i| (0..m.cols).map(|j| eval(m.get(i, j))).collect())
        .collect();
    let mut rank = 0;
    // Gaussian elimination: rows `r`, `rank` and columns read together.
    #[allow(clippy::needless_range_loop)]
    for c in 0..m.cols {
        let Some(p) = (rank..m.rows).find(|&r| !a[r][c].is_zero()) else {
            continue;
        };
        a.swap(rank, p);
        for r in 0..m.rows {
            if r != rank && !a[r][c].is_zero() {
                let f = a[r][c].clone() / a[rank][c].clone();
                for cc in c..m.cols {
                    let d = a[rank][cc].clone() * f.clone();
                    a[r][cc] -= d;
                }
            }
        }
        rank += 1;
    }
    rank
}

fn values() -> Vec<(Param, Rational)> {
    vec![
        (L, rat(3, 2)),
        (Rho, rat(7850, 1)),
        (Area, rat(1, 100)),
        (Iy, rat(1, 30000)),
        (Iz, rat(1, 70000)),
        (E, rat(210_000_000_000, 1)),
        (G, rat(81_000_000_000, 1)),
        (J, rat(1, 20000)),
    ]
}

#[test]
fn free_element_stiffness_has_exactly_the_rigid_body_modes() {
    // K_ff is symmetric positive semi-definite; its nullity is the number of
    // zero eigenvalues: 6 rigid-body modes in space, 3 in the plane.
    for n in 1..=3 {
        let k = body("beam3", n, Reference::Free).k_ff;
        assert_eq!(
            k.rows - rank_at(&k, &values()),
            6,
            "beam3 free, {n} elements"
        );
        let k = body("beam2", n, Reference::Free).k_ff;
        assert_eq!(
            k.rows - rank_at(&k, &values()),
            3,
            "beam2 free, {n} elements"
        );
    }
}

#[test]
fn clamped_and_pinned_stiffness_is_regular() {
    for n in 1..=4 {
        for r in [Reference::Clamped, Reference::Pinned] {
            for shape in ["beam2", "beam3"] {
                let k = body(shape, n, r).k_ff;
                assert_eq!(
                    rank_at(&k, &values()),
                    k.rows,
                    "{shape} {r} {n}: singular K_ff"
                );
            }
        }
    }
}

#[test]
fn m_ff_is_the_sum_of_the_diagonal_s_kl_and_s_lk_is_the_transpose() {
    let inv = body("beam3", 3, Reference::Pinned);
    for i in 0..inv.nf {
        for j in 0..inv.nf {
            let sum = inv.s_kl[0][0]
                .get(i, j)
                .add(inv.s_kl[1][1].get(i, j))
                .add(inv.s_kl[2][2].get(i, j));
            assert_eq!(inv.m_ff.get(i, j), &sum);
            for k in 0..3 {
                for l in 0..3 {
                    assert_eq!(inv.s_kl[k][l].get(i, j), inv.s_kl[l][k].get(j, i));
                }
            }
        }
    }
}

/// The element invariants the kernels are generated from, in `l` and the
/// element offset `x₀`: `m = ρAl`, `S_t0,x = ρAl (x₀ + l/2)`,
/// `Θ_xx = ρA ∫ x² dx = ρAl (x₀² + x₀ l + l²/3)` (consistent) and
/// `½ρAl (x₀² + (x₀ + l)²) + 2 ρAl·l²/78` (lumped: half the mass at each
/// end, each spread along the axis by the HRZ rotational inertia
/// `D_p = m_p l²/39`).
#[test]
fn element_invariants_in_l_and_x0() {
    use ffr_codegen::body::element_invariants;
    let l = Poly::var(Sym::Param(Param::ElemLength));
    let x0 = Poly::var(Sym::X0);
    let rho_a = Poly::var(Sym::Param(Rho)).mul(&Poly::var(Sym::Param(Area)));
    let m = rho_a.mul(&l);
    for shape in ["beam2", "beam3"] {
        let s = Shape::resolve(shape, None).unwrap();
        for f in [Formalism::Consistent, Formalism::Lumped] {
            let inv = element_invariants(&s, f).unwrap();
            assert_eq!(inv.mass, m, "{shape} {f}");
            assert_eq!(
                inv.s_t0[0],
                m.mul(&x0.add(&l.scale(&rat(1, 2)))),
                "{shape} {f}"
            );
            let theta = match f {
                Formalism::Consistent => x0
                    .mul(&x0)
                    .add(&x0.mul(&l))
                    .add(&l.mul(&l).scale(&rat(1, 3))),
                Formalism::Lumped => x0
                    .mul(&x0)
                    .add(&x0.add(&l).pow(2))
                    .scale(&rat(1, 2))
                    .add(&l.mul(&l).scale(&rat(1, 39))),
            };
            assert_eq!(inv.theta[0][0], m.mul(&theta), "{shape} {f}");
            // The element K does not depend on where the element is.
            for i in 0..inv.nf {
                for j in 0..inv.nf {
                    assert!(!inv.k_ff.get(i, j).contains(Sym::X0));
                    assert!(!inv.m_ff.get(i, j).contains(Sym::X0));
                }
            }
        }
    }
}
