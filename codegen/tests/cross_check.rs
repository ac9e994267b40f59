//! The generator against an independent route: `ffr-reference`, Gauss–Legendre
//! quadrature of hand-coded beam shape functions over the actual rectangular
//! prism (it shares no code with the generator). The generated programs are
//! run on tapes (`Program::tape()`: the compiled code's operations in the
//! same order) and assembled over the elements of a body like the runtime
//! does.
//!
//! - (a) body invariants, from the exact polynomials
//!   (`BodySpec::exact_invariants`) and from the `element_invariants`
//!   program assembled over the elements;
//! - (b) the elastic part of the element kernels (`residual_elastic`,
//!   `tangent_elastic`, `energy` with the frame at rest) against `K_ff` and
//!   the reference's stiffening energy, force and tangent, both models;
//! - (c) the `mass` kernel against the reference's `S_t(q)`, `Ī_θθ(q)`,
//!   `Ī_θf(q)`, `m_ff`, `S̄`;
//! - `point_shape` against the reference's shape matrix;
//! - (d) the whole `residual` kernel (`f_r`, `f_θ`, `f_f`) against
//!   d'Alembert's principle evaluated by quadrature: the body-frame
//!   acceleration of every quadrature point, `ā + α × u + ω × (ω × u) +
//!   2 ω × u̇ + ü`, integrated with `ρ dV` (and `u ×`, `Sᵀ`).
//!
//! beam2 and beam3, 1–4 elements, every reference condition, both
//! formalisms, lengths from 1e-3 m to 1e2 m. Agreement: 1e-12 relative per
//! matrix (Frobenius norm) unless a test says otherwise.

mod common;

use common::*;
use ffr_codegen::{BodySpec, Formalism, KernelSet, Reference, Shape, Stiffening};
use ffr_reference as rf;
use nalgebra::{DMatrix, Matrix3, Vector3};

const TOL: f64 = 1e-12;
const SHAPES: [&str; 2] = ["beam2", "beam3"];
const FORMALISMS: [Formalism; 2] = [Formalism::Consistent, Formalism::Lumped];

fn ref_body(shape: &str, elements: usize, r: Reference, p: &rf::RefParams) -> rf::RefBody {
    rf::RefBody {
        shape: rf_shape(shape),
        elements,
        reference: rf_reference(r),
        params: *p,
    }
}

fn tag(shape: &str, n: usize, r: Reference, f: Formalism, p: &rf::RefParams) -> String {
    format!("{shape} N={n} {r} {f} L={}", p.length)
}

/// Every invariant, 1e-12 relative per matrix; `S̄_kl` and `Ī_kl` (some are
/// zero) relative to the largest of their family.
fn compare_invariants(tag: &str, g: &Dense, r: &rf::RefInvariants) {
    let r = Dense::from_reference(r);
    check(
        &format!("{tag} mass"),
        &scalar(g.mass),
        &scalar(r.mass),
        0.0,
        TOL,
    );
    check(
        &format!("{tag} S_t0"),
        &col(&g.s_t0),
        &col(&r.s_t0),
        0.0,
        TOL,
    );
    check(&format!("{tag} S̄"), &g.s_bar, &r.s_bar, 0.0, TOL);
    let th = |m: &Matrix3<f64>| DMatrix::from_fn(3, 3, |i, j| m[(i, j)]);
    check(&format!("{tag} Θ"), &th(&g.theta), &th(&r.theta), 0.0, TOL);
    let skl_scale = r.m_ff.norm();
    let ikl_scale = (0..9)
        .map(|i| r.i_kl[i / 3][i % 3].norm())
        .fold(0.0, f64::max);
    for k in 0..3 {
        for l in 0..3 {
            let what = format!("{tag} S̄_{k}{l}");
            check(&what, &g.s_kl[k][l], &r.s_kl[k][l], skl_scale, TOL);
            let what = format!("{tag} Ī_{k}{l}");
            check(&what, &g.i_kl[k][l], &r.i_kl[k][l], ikl_scale, TOL);
        }
    }
    check(&format!("{tag} m_ff"), &g.m_ff, &r.m_ff, 0.0, TOL);
    check(&format!("{tag} K_ff"), &g.k_ff, &r.k_ff, 0.0, TOL);
}

fn reference_invariants(b: &rf::RefBody, f: Formalism) -> rf::RefInvariants {
    match f {
        Formalism::Consistent => b.invariants(),
        Formalism::Lumped => b.lumped_invariants(),
    }
}

/// (a) The exact body polynomials evaluated at the parameter values.
#[test]
fn exact_invariants_match_quadrature() {
    for shape in SHAPES {
        for n in 1..=4 {
            for r in REFERENCES {
                for f in FORMALISMS {
                    let spec = BodySpec::new(Shape::resolve(shape, None).unwrap(), n, r)
                        .unwrap()
                        .with_formalism(f);
                    let exact = spec.exact_invariants().unwrap();
                    for rp in param_sets() {
                        let p = params_of(&rp);
                        let body = ref_body(shape, n, r, &rp);
                        let t = tag(shape, n, r, f, &rp);
                        let labels: Vec<String> =
                            spec.dofs().iter().map(|d| d.to_string()).collect();
                        assert_eq!(labels, body.dof_labels(), "{t}: coordinate labels");
                        compare_invariants(
                            &format!("exact {t}"),
                            &Dense::from_exact(&exact, &p),
                            &reference_invariants(&body, f),
                        );
                    }
                }
            }
        }
    }
}

/// (a) The `element_invariants` program on tapes, assembled over the elements.
#[test]
fn element_invariant_program_matches_quadrature() {
    for shape in SHAPES {
        for f in FORMALISMS {
            let set = kernel_set(shape, f, Stiffening::Off, 3, false);
            for n in 1..=4 {
                for r in REFERENCES {
                    for rp in param_sets() {
                        let body = TapeBody::new(&set, n, r, params_of(&rp));
                        let reference = ref_body(shape, n, r, &rp);
                        compare_invariants(
                            &format!("program {}", tag(shape, n, r, f, &rp)),
                            &body.invariants(),
                            &reference_invariants(&reference, f),
                        );
                    }
                }
            }
        }
    }
}

fn rf_model(s: Stiffening) -> Option<rf::StiffeningModel> {
    match s {
        Stiffening::Off => None,
        Stiffening::SecondOrder => Some(rf::StiffeningModel::SecondOrder),
        Stiffening::FourthOrder => Some(rf::StiffeningModel::FourthOrder),
    }
}

/// (b) `residual_elastic`, `tangent_elastic` (`β' = γ' = 0`) and `energy`
/// with the frame at rest and no velocities or accelerations are the
/// elastic force `K q + ∂U_nl/∂q`, its tangent `K + ∂²U_nl/∂q²` and the
/// energy `½ qᵀ K q + U_nl`. Totals to 1e-12; the nonlinear part alone (the
/// difference to the stiffening-off kernels) to 1e-10 of itself, over states
/// whose slopes are of order 0.05 and 0.2.
#[test]
fn elastic_kernels_match_quadrature() {
    let mut worst_nl: f64 = 0.0;
    for shape in SHAPES {
        let off = kernel_set(shape, Formalism::Consistent, Stiffening::Off, 3, true);
        for model in [
            Stiffening::Off,
            Stiffening::SecondOrder,
            Stiffening::FourthOrder,
        ] {
            // The elastic part does not depend on the scene, the formalism or
            // the reference rows: vary them to see that it does not.
            let mut sets: Vec<(String, KernelSet)> = Vec::new();
            for (f, scene, free) in [
                (Formalism::Consistent, 3, true),
                (Formalism::Lumped, 3, false),
                (Formalism::Consistent, 2, true),
            ] {
                if scene < Shape::resolve(shape, None).unwrap().dimension {
                    continue;
                }
                sets.push((
                    format!("{f} scene {scene} free {free}"),
                    kernel_set(shape, f, model, scene, free),
                ));
            }
            for (what, set) in &sets {
                for n in 1..=4 {
                    for r in REFERENCES {
                        for (ip, rp) in param_sets().iter().enumerate() {
                            let p = params_of(rp);
                            let body = TapeBody::new(set, n, r, p);
                            let body_off = TapeBody::new(&off, n, r, p);
                            let reference = ref_body(shape, n, r, rp);
                            let k_ref = reference.invariants().k_ff;
                            let nf = body.nf();
                            let zero = vec![0.0; nf];
                            let frame = [0.0; 9];
                            for (is, a) in [0.05, 0.2].into_iter().enumerate() {
                                let seed = (ip * 10 + is) as u64 + 31 * n as u64;
                                let q = state(&body.spec, body.l, seed, a);
                                let t = format!(
                                    "{shape} {model} ({what}) N={n} {r} L={} slope {a}",
                                    rp.length
                                );
                                let qv = col(&q);
                                let kq = &k_ref * &qv;
                                let (f_nl, k_nl, u_nl) = match rf_model(model) {
                                    Some(m) => (
                                        col(reference.stiffening_force_with(m, &q).as_slice()),
                                        reference.stiffening_tangent_with(m, &q),
                                        reference.stiffening_energy_with(m, &q),
                                    ),
                                    None => (DMatrix::zeros(nf, 1), DMatrix::zeros(nf, nf), 0.0),
                                };
                                let u_lin = 0.5 * qv.dot(&kq);

                                let f = col(&body.residual_elastic(&q, &zero, &zero, &frame));
                                check(&format!("{t}: force"), &f, &(&kq + &f_nl), 0.0, TOL);
                                let (f2, k) =
                                    body.tangent_elastic(&q, &zero, &zero, &frame, 0.0, 0.0);
                                assert_eq!(
                                    col(&f2),
                                    f,
                                    "{t}: tangent_elastic's force differs from residual_elastic's"
                                );
                                check(&format!("{t}: tangent"), &k, &(&k_ref + &k_nl), 0.0, TOL);
                                let e = body.energy(&q);
                                check(
                                    &format!("{t}: energy"),
                                    &scalar(e),
                                    &scalar(u_lin + u_nl),
                                    0.0,
                                    TOL,
                                );

                                if model.is_on() {
                                    // The nonlinear part on its own.
                                    let f0 =
                                        col(&body_off.residual_elastic(&q, &zero, &zero, &frame));
                                    let (_, k0) = body_off
                                        .tangent_elastic(&q, &zero, &zero, &frame, 0.0, 0.0);
                                    let e0 = body_off.energy(&q);
                                    for (name, g, r) in [
                                        ("force", &f - &f0, f_nl.clone()),
                                        ("tangent", &k - &k0, k_nl.clone()),
                                        ("energy", scalar(e - e0), scalar(u_nl)),
                                    ] {
                                        let rel = (&g - &r).norm() / r.norm();
                                        worst_nl = worst_nl.max(rel);
                                        check(
                                            &format!("{t}: nonlinear {name}"),
                                            &g,
                                            &r,
                                            0.0,
                                            1e-10,
                                        );
                                    }
                                    // … and it matters in these states.
                                    assert!(
                                        f_nl.norm() > 1e-4 * kq.norm(),
                                        "{t}: the test state hardly stiffens ({:e} vs {:e})",
                                        f_nl.norm(),
                                        kq.norm()
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    eprintln!("elastic kernels: worst relative error of the nonlinear part alone {worst_nl:e}");
}

/// The reference's `q`-dependent inertia terms: quadrature for a consistent
/// body; for a lumped one the theory's formulas applied to the reference's
/// lumped invariants (its point masses).
struct RefInertia {
    s_t: Vector3<f64>,
    i_tt: Matrix3<f64>,
    i_tf: DMatrix<f64>,
}

fn reference_inertia(b: &rf::RefBody, f: Formalism, q: &[f64]) -> RefInertia {
    match f {
        Formalism::Consistent => {
            let itf = b.i_theta_f(q);
            RefInertia {
                s_t: b.s_t(q),
                i_tt: b.i_theta_theta(q),
                i_tf: DMatrix::from_fn(3, q.len(), |i, j| itf[(i, j)]),
            }
        }
        Formalism::Lumped => {
            let inv = Dense::from_reference(&b.lumped_invariants());
            let qv = col(q);
            let s_t = Vector3::from_fn(|k, _| inv.s_t0[k] + (inv.s_bar.row(k) * &qv)[(0, 0)]);
            let u = Matrix3::from_fn(|k, l| {
                inv.theta[(k, l)]
                    + inv.i_kl[k][l].dot(&qv)
                    + inv.i_kl[l][k].dot(&qv)
                    + (qv.transpose() * &inv.s_kl[k][l] * &qv)[(0, 0)]
            });
            let i_tt = Matrix3::identity() * u.trace() - u;
            let cyc = [(1, 2), (2, 0), (0, 1)];
            let mut i_tf = DMatrix::zeros(3, q.len());
            for (r, &(a, b)) in cyc.iter().enumerate() {
                let row = (&inv.i_kl[a][b] - &inv.i_kl[b][a]).transpose()
                    + qv.transpose() * (&inv.s_kl[a][b] - &inv.s_kl[b][a]);
                i_tf.set_row(r, &row.row(0));
            }
            RefInertia { s_t, i_tt, i_tf }
        }
    }
}

/// Indices of the frame inputs `[ā, α]` / reference rows `[f_r, f_θ]` a
/// scene has: all six in space; `ā_x, ā_y, α_z` (rows `f_rx, f_ry, f_θz`) in
/// the plane.
fn live6(scene: usize) -> Vec<usize> {
    if scene == 2 {
        vec![0, 1, 5]
    } else {
        (0..6).collect()
    }
}

/// `m` with the rows and columns outside `rows`/`cols` set to zero.
fn masked(m: &DMatrix<f64>, rows: Option<&[usize]>, cols: Option<&[usize]>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| {
        let ok = rows.is_none_or(|r| r.contains(&i)) && cols.is_none_or(|c| c.contains(&j));
        if ok {
            m[(i, j)]
        } else {
            0.0
        }
    })
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

/// (c) The `mass` kernel: `S_t(q)`, `m_ff`, `∂f_f/∂[ā, α] = [S̄ᵀ, Ī_θfᵀ]`,
/// `∂[f_r; f_θ]/∂q̈ = [S̄; Ī_θf]` and `∂[f_r; f_θ]/∂[ā, α] = [m I, −S̃_t;
/// S̃_t, Ī_θθ]` against the reference (the entries a planar scene has).
#[test]
fn mass_kernel_matches_quadrature() {
    for shape in SHAPES {
        let dim = Shape::resolve(shape, None).unwrap().dimension;
        for f in FORMALISMS {
            for scene in dim..=3 {
                let set = kernel_set(shape, f, Stiffening::FourthOrder, scene, true);
                let live = live6(scene);
                for n in 1..=4 {
                    for r in REFERENCES {
                        for (ip, rp) in param_sets().iter().enumerate() {
                            let body = TapeBody::new(&set, n, r, params_of(rp));
                            let reference = ref_body(shape, n, r, rp);
                            let inv = Dense::from_reference(&reference_invariants(&reference, f));
                            let nf = body.nf();
                            let t = format!("{} scene {scene}", tag(shape, n, r, f, rp));
                            for (is, a) in [0.0, 0.05].into_iter().enumerate() {
                                let q = state(&body.spec, body.l, (ip * 7 + is) as u64 + 3, a);
                                let g = body.mass(&q);
                                let ri = reference_inertia(&reference, f, &q);
                                let t = format!("{t} slope {a}");
                                // S_t: x, y in the plane (S_t,z is zero for a planar shape).
                                check(
                                    &format!("{t}: S_t"),
                                    &col(&g.s_t),
                                    &col(ri.s_t.as_slice()),
                                    0.0,
                                    TOL,
                                );
                                check(&format!("{t}: m_ff"), &g.m_ff, &inv.m_ff, 0.0, TOL);
                                // [S̄; Ī_θf] (6 × n_f), live rows.
                                let mut ref_f = DMatrix::zeros(6, nf);
                                ref_f.rows_mut(0, 3).copy_from(&inv.s_bar);
                                ref_f.rows_mut(3, 3).copy_from(&ri.i_tf);
                                let ref_f = masked(&ref_f, Some(&live), None);
                                check(
                                    &format!("{t}: S̄ rows"),
                                    &g.m_ref_f.rows(0, 3).into(),
                                    &ref_f.rows(0, 3).into(),
                                    0.0,
                                    TOL,
                                );
                                check(
                                    &format!("{t}: Ī_θf"),
                                    &g.m_ref_f.rows(3, 3).into(),
                                    &ref_f.rows(3, 3).into(),
                                    inv.s_bar.norm() * rp.length,
                                    TOL,
                                );
                                check(
                                    &format!("{t}: ∂f_f/∂[ā, α]"),
                                    &g.m_f_frame,
                                    &ref_f.transpose(),
                                    0.0,
                                    TOL,
                                );
                                // [m I, −S̃_t; S̃_t, Ī_θθ].
                                let mut rf6 = DMatrix::zeros(6, 6);
                                let st = skew(&ri.s_t);
                                for i in 0..3 {
                                    rf6[(i, i)] = inv.mass;
                                    for j in 0..3 {
                                        rf6[(i, 3 + j)] = -st[(i, j)];
                                        rf6[(3 + i, j)] = st[(i, j)];
                                        rf6[(3 + i, 3 + j)] = ri.i_tt[(i, j)];
                                    }
                                }
                                let rf6 = masked(&rf6, Some(&live), Some(&live));
                                check(
                                    &format!("{t}: m I"),
                                    &g.m_ref_frame.view((0, 0), (3, 3)).into(),
                                    &rf6.view((0, 0), (3, 3)).into(),
                                    0.0,
                                    TOL,
                                );
                                check(
                                    &format!("{t}: S̃_t blocks"),
                                    &g.m_ref_frame.view((0, 3), (3, 3)).into(),
                                    &rf6.view((0, 3), (3, 3)).into(),
                                    ri.s_t.norm(),
                                    TOL,
                                );
                                check(
                                    &format!("{t}: S̃_t blocks"),
                                    &g.m_ref_frame.view((3, 0), (3, 3)).into(),
                                    &rf6.view((3, 0), (3, 3)).into(),
                                    ri.s_t.norm(),
                                    TOL,
                                );
                                check(
                                    &format!("{t}: Ī_θθ"),
                                    &g.m_ref_frame.view((3, 3), (3, 3)).into(),
                                    &rf6.view((3, 3), (3, 3)).into(),
                                    0.0,
                                    TOL,
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Points of a body with their weights `ρ dV` and the element they belong
/// to: Gauss–Legendre over the prism (consistent), or for each element end
/// (lumped) a rigid body of half the element's mass with the second moments
/// `diag(m l²/39, ρ I_z l/2, ρ I_y l/2)` (HRZ bending rotational inertia and
/// the sections' rotary inertia), as points of weight `m/6` at `±a` along
/// the axes and the rest of the mass at the node; a point `d_x` along the
/// axis from the node moves with the axis' slope, `N + d_x (0, v', w')`.
struct Points {
    /// (element, ξ, η·l, ζ·l, ρ dV, d_x)
    pts: Vec<(usize, f64, f64, f64, f64, f64)>,
}

fn points(b: &rf::RefBody, f: Formalism) -> Points {
    let p = &b.params;
    let l = p.length / b.elements as f64;
    let mut pts = Vec::new();
    for e in 0..b.elements {
        match f {
            Formalism::Consistent => {
                for &(xi, wx) in &rf::gauss_legendre(4, 0.0, 1.0) {
                    for &(y, wy) in &rf::gauss_legendre(2, -0.5 * p.wy, 0.5 * p.wy) {
                        for &(z, wz) in &rf::gauss_legendre(2, -0.5 * p.wz, 0.5 * p.wz) {
                            pts.push((e, xi, y, z, p.rho * l * wx * wy * wz, 0.0));
                        }
                    }
                }
            }
            Formalism::Lumped => {
                let m = 0.5 * p.rho * p.area() * l;
                let mut axes = vec![
                    (l / 13f64.sqrt(), 0.0, 0.0),
                    (0.0, (3.0 * p.iz() / p.area()).sqrt(), 0.0),
                ];
                if b.shape == rf::Shape::Beam3 {
                    axes.push((0.0, 0.0, (3.0 * p.iy() / p.area()).sqrt()));
                }
                for xi in [0.0, 1.0] {
                    let mut rest = m;
                    for &(dx, y, z) in &axes {
                        pts.push((e, xi, y, z, m / 6.0, dx));
                        pts.push((e, xi, -y, -z, m / 6.0, -dx));
                        rest -= m / 3.0;
                    }
                    pts.push((e, xi, 0.0, 0.0, rest, 0.0));
                }
            }
        }
    }
    Points { pts }
}

/// Element → `q_f` maps from the reference's own labels (`kind_node`).
fn ref_maps(b: &rf::RefBody) -> Vec<Vec<Option<usize>>> {
    let labels = b.dof_labels();
    let kinds = b.shape.kinds();
    (0..b.elements)
        .map(|e| {
            (0..2)
                .flat_map(|node| kinds.iter().map(move |k| format!("{k}_{}", e + node)))
                .map(|lab| labels.iter().position(|x| *x == lab))
                .collect()
        })
        .collect()
}

/// `[f_r, f_θ, f_f]` by d'Alembert's principle: with the body-frame
/// acceleration of a point `a_p = ā + α × u + ω × (ω × u) + 2 ω × u̇ + ü`,
/// `f_r = ∫ρ a_p dV`, `f_θ = ∫ρ u × a_p dV`, `f_f = ∫ρ Sᵀ a_p dV + K q`.
fn dalembert(
    b: &rf::RefBody,
    f: Formalism,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    frame: &[f64; 9],
) -> (Vector3<f64>, Vector3<f64>, DMatrix<f64>) {
    let nf = q.len();
    let l = b.params.length / b.elements as f64;
    let maps = ref_maps(b);
    let abar = Vector3::new(frame[0], frame[1], frame[2]);
    let alpha = Vector3::new(frame[3], frame[4], frame[5]);
    let w = Vector3::new(frame[6], frame[7], frame[8]);
    let mut f_r = Vector3::zeros();
    let mut f_th = Vector3::zeros();
    let mut f_f = DMatrix::zeros(nf, 1);
    for (e, xi, y, z, wgt, dx) in points(b, f).pts {
        let map = &maps[e];
        let eta = y / l;
        let zeta = z / l;
        let mut s = b.shape.elem_s(l, xi, eta, zeta);
        if dx != 0.0 {
            let (_, vp, wp) = b.shape.centerline_grad(l, xi);
            for c in 0..s.ncols() {
                s[(1, c)] += dx * vp[c];
                s[(2, c)] += dx * wp[c];
            }
        }
        let g = |v: &[f64]| {
            nalgebra::DVector::from_iterator(map.len(), map.iter().map(|m| m.map_or(0.0, |i| v[i])))
        };
        let (qe, qde, qdde) = (g(q), g(qd), g(qdd));
        let u0 = Vector3::new(
            e as f64 * l + xi * l + dx,
            y,
            if b.shape == rf::Shape::Beam3 { z } else { 0.0 },
        );
        let u = u0 + &s * &qe;
        let ud: Vector3<f64> = &s * &qde;
        let udd: Vector3<f64> = &s * &qdde;
        let a = abar + alpha.cross(&u) + w.cross(&w.cross(&u)) + 2.0 * w.cross(&ud) + udd;
        f_r += wgt * a;
        f_th += wgt * u.cross(&a);
        let local = s.transpose() * (wgt * a);
        for (k, m) in map.iter().enumerate() {
            if let Some(i) = m {
                f_f[(*i, 0)] += local[k];
            }
        }
    }
    let k = b.invariants().k_ff;
    f_f += &k * col(q);
    (f_r, f_th, f_f)
}

/// (d) The whole `residual` kernel against d'Alembert's principle by
/// quadrature (random coordinates, velocities, accelerations and frame
/// motion; stiffening off, so that only the inertia and `K q` remain). The
/// quadrature is exact for these integrands, so the tolerance is 1e-12 of
/// the largest term's scale.
#[test]
fn residual_kernel_matches_dalembert() {
    let mut worst: f64 = 0.0;
    for shape in SHAPES {
        let dim = Shape::resolve(shape, None).unwrap().dimension;
        for f in FORMALISMS {
            for scene in dim..=3 {
                let set = kernel_set(shape, f, Stiffening::Off, scene, true);
                for n in 1..=3 {
                    for r in REFERENCES {
                        for (ip, rp) in param_sets().iter().enumerate() {
                            let body = TapeBody::new(&set, n, r, params_of(rp));
                            let reference = ref_body(shape, n, r, rp);
                            let seed = (ip * 13 + n) as u64;
                            let len = rp.length;
                            let q = state(&body.spec, body.l, seed, 0.05);
                            let qd = state(&body.spec, body.l, seed + 100, 0.3);
                            let qdd = state(&body.spec, body.l, seed + 200, 2.0);
                            let fr = pseudo_random(9, seed + 300, 1.0);
                            // ā of order 10 m/s² (scaled with the body for the micro beam),
                            // α and ω of order 1/s² and 1/s.
                            let mut frame = [0.0; 9];
                            for k in 0..9 {
                                let s = if k < 3 { 10.0 * len.min(1.0) } else { 1.0 };
                                let live = scene == 3 || matches!(k, 0 | 1 | 5 | 8);
                                frame[k] = if live { s * fr[k] } else { 0.0 };
                            }
                            let g = body.residual(&q, &qd, &qdd, &frame);
                            let (rr, rth, rff) = dalembert(&reference, f, &q, &qd, &qdd, &frame);
                            let t = format!("{} scene {scene}", tag(shape, n, r, f, rp));
                            // Scale: the inertia force of the whole body, m·|ā| + m L (|α| + |ω|²).
                            let m = rp.rho * rp.area() * len;
                            let scale = m * (10.0 * len.min(1.0) + len * 3.0);
                            let rows: Vec<usize> = if scene == 2 {
                                vec![0, 1]
                            } else {
                                vec![0, 1, 2]
                            };
                            for &k in &rows {
                                let e = (g.f_r[k] - rr[k]).abs() / scale;
                                worst = worst.max(e);
                                assert!(
                                    e <= TOL,
                                    "{t}: f_r[{k}] {} vs {} (rel {e:e})",
                                    g.f_r[k],
                                    rr[k]
                                );
                            }
                            let th_rows: Vec<usize> =
                                if scene == 2 { vec![2] } else { vec![0, 1, 2] };
                            for &k in &th_rows {
                                let e = (g.f_th[k] - rth[k]).abs() / (scale * len);
                                worst = worst.max(e);
                                assert!(
                                    e <= TOL,
                                    "{t}: f_θ[{k}] {} vs {} (rel {e:e})",
                                    g.f_th[k],
                                    rth[k]
                                );
                            }
                            if scene == 2 {
                                assert_eq!(g.f_r[2], 0.0);
                                assert_eq!((g.f_th[0], g.f_th[1]), (0.0, 0.0));
                            }
                            let kq = (reference.invariants().k_ff * col(&q)).norm();
                            let fscale = rff.norm().max(kq);
                            let e = (col(&g.f_f) - &rff).norm() / fscale;
                            worst = worst.max(e);
                            assert!(e <= TOL, "{t}: f_f relative error {e:e}");
                        }
                    }
                }
            }
        }
    }
    eprintln!("residual vs d'Alembert: worst relative error {worst:e}");
}

/// A test of the test: the quadrature of d'Alembert's principle reproduces
/// the reference's own `S_t`, `Ī_θθ` for a pure rotation about a random axis
/// (`f_θ = ω × Ī_θθ ω` at `α = 0`).
#[test]
fn dalembert_quadrature_agrees_with_the_reference_inertia() {
    let rp = param_sets()[0];
    let b = ref_body("beam3", 2, Reference::Clamped, &rp);
    let nf = b.nf();
    let q = pseudo_random(nf, 5, 0.01);
    let zero = vec![0.0; nf];
    let w = Vector3::new(0.3, -0.7, 1.1);
    let mut frame = [0.0; 9];
    frame[6..9].copy_from_slice(w.as_slice());
    let (f_r, f_th, _) = dalembert(&b, Formalism::Consistent, &q, &zero, &zero, &frame);
    let itt = b.i_theta_theta(&q);
    let st = b.s_t(&q);
    assert!((f_th - w.cross(&(itt * w))).norm() <= 1e-13 * f_th.norm());
    assert!((f_r - w.cross(&w.cross(&st))).norm() <= 1e-13 * f_r.norm());
}

/// The `point_shape` program: `S(ξ)` on the centre line and the section
/// rotation `ψ = ½ ∇ × u` against the reference's shape matrix (`∂/∂y`,
/// `∂/∂z` by differences of `S`, linear in `η`, `ζ`; `∂/∂x` of the centre
/// line from its `centerline_grad`).
#[test]
fn point_shape_matches_the_reference_shape() {
    use ffr_codegen::eom::OutArr;
    use ffr_codegen::program::Inputs;
    for shape in SHAPES {
        let set = kernel_set(shape, Formalism::Consistent, Stiffening::Off, 3, false);
        let n = set.n();
        let rs = rf_shape(shape);
        for rp in param_sets() {
            let l = rp.length / 3.0;
            let c = coefficients(&set, &params_of(&rp), l);
            let mut run = Run::new(&set.point_shape);
            for xi in [0.0, 0.23, 0.5, 0.81, 1.0] {
                let (mut s, mut psi) = (DMatrix::zeros(3, n), DMatrix::zeros(3, n));
                run.run(
                    &Inputs {
                        coef: &c,
                        xi,
                        ..Inputs::default()
                    },
                    |arr, i, v| match arr {
                        OutArr::S => s[(i / n, i % n)] = v,
                        OutArr::Psi => psi[(i / n, i % n)] = v,
                        other => panic!("{other:?}"),
                    },
                );
                let s0 = rs.elem_s(l, xi, 0.0, 0.0);
                let s_ref = DMatrix::from_fn(3, n, |k, a| s0[(k, a)]);
                // ∂S/∂y = (S(η = 1) − S(η = −1)) / (2 l), likewise z.
                let d = |eta: f64, zeta: f64| {
                    let (p, m) = (rs.elem_s(l, xi, eta, zeta), rs.elem_s(l, xi, -eta, -zeta));
                    DMatrix::from_fn(3, n, |k, a| (p[(k, a)] - m[(k, a)]) / (2.0 * l))
                };
                let (dy, dz) = (d(1.0, 0.0), d(0.0, 1.0));
                let (_, bx, cx) = rs.centerline_grad(l, xi);
                let psi_ref = DMatrix::from_fn(3, n, |k, a| match k {
                    0 => 0.5 * (dy[(2, a)] - dz[(1, a)]),
                    1 => 0.5 * (dz[(0, a)] - cx[a]),
                    _ => 0.5 * (bx[a] - dy[(0, a)]),
                });
                let t = format!("{shape} L={} ξ={xi}", rp.length);
                check(&format!("{t}: S"), &s, &s_ref, 0.0, TOL);
                check(&format!("{t}: ψ"), &psi, &psi_ref, 0.0, 1e-11);
            }
        }
    }
}
