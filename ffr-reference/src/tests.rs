use super::*;

fn params() -> RefParams {
    RefParams {
        length: 2.5,
        rho: 2700.0,
        wy: 0.05,
        wz: 0.03,
        e: 7.0e10,
        g: 2.6e10,
        j: 2.1e-7,
    }
}

fn body(shape: Shape, elements: usize, reference: Reference) -> RefBody {
    RefBody {
        shape,
        elements,
        reference,
        params: params(),
    }
}

fn all_bodies() -> Vec<RefBody> {
    let mut v = Vec::new();
    for shape in [Shape::Beam2, Shape::Beam3] {
        for reference in [Reference::Clamped, Reference::Pinned, Reference::Free] {
            for n in [1, 3] {
                v.push(body(shape, n, reference));
            }
        }
    }
    v
}

/// Deterministic pseudo-random vector in [-scale, scale].
fn pseudo_random(n: usize, seed: u64, scale: f64) -> Vec<f64> {
    let mut x = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            scale * (((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0)
        })
        .collect()
}

fn rel_close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

fn assert_mat_close(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64, what: &str) {
    assert_eq!(a.shape(), b.shape(), "{what}: shape");
    let scale = a.amax().max(b.amax());
    let err = (a - b).amax();
    assert!(
        err <= tol * scale,
        "{what}: err {err:e} scale {scale:e}\n{a}\n{b}"
    );
}

#[test]
fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
    for n in 1..=8 {
        let g = gauss_legendre(n, 0.0, 1.0);
        assert_eq!(g.len(), n);
        for deg in 0..(2 * n) {
            let s: f64 = g.iter().map(|(x, w)| w * x.powi(deg as i32)).sum();
            assert!(
                rel_close(s, 1.0 / (deg as f64 + 1.0), 1e-14),
                "n {n} deg {deg}: {s}"
            );
        }
        // Degree 2n is not integrated exactly.
        let s: f64 = g.iter().map(|(x, w)| w * x.powi(2 * n as i32)).sum();
        assert!(!rel_close(s, 1.0 / (2.0 * n as f64 + 1.0), 1e-14));
    }
}

#[test]
fn mass_static_moment_and_theta() {
    let p = params();
    let (rho, a, big_l) = (p.rho, p.area(), p.length);
    for b in all_bodies() {
        for inv in [b.invariants(), b.lumped_invariants()] {
            assert!(rel_close(inv.mass, rho * a * big_l, 1e-13));
            assert!(rel_close(inv.s_t0.x, rho * a * big_l * big_l / 2.0, 1e-13));
            assert!(inv.s_t0.y.abs() < 1e-15 * inv.s_t0.x);
            assert!(inv.s_t0.z.abs() < 1e-15 * inv.s_t0.x);
        }
        let inv = b.invariants();
        assert!(rel_close(
            inv.theta[(0, 0)],
            rho * a * big_l.powi(3) / 3.0,
            1e-13
        ));
        assert!(rel_close(inv.theta[(1, 1)], rho * p.iz() * big_l, 1e-13));
        match b.shape {
            Shape::Beam2 => assert_eq!(inv.theta[(2, 2)], 0.0),
            Shape::Beam3 => assert!(rel_close(inv.theta[(2, 2)], rho * p.iy() * big_l, 1e-13)),
        }
    }
}

#[test]
fn lumped_mass_and_static_moment_equal_consistent() {
    for b in all_bodies() {
        let (c, l) = (b.invariants(), b.lumped_invariants());
        assert!(rel_close(c.mass, l.mass, 1e-14));
        assert!((c.s_t0 - l.s_t0).amax() <= 1e-14 * c.s_t0.amax());
        assert_eq!(l.k_ff, c.k_ff);
        // S̄ on translations agrees too (∫N1 = ∫N3 = l/2); rotations carry no lumped mass.
        for (i, lab) in b.dof_labels().iter().enumerate() {
            let (cc, lc) = (c.s_bar.column(i), l.s_bar.column(i));
            if lab.starts_with('u') {
                assert!((cc - lc).amax() <= 1e-13 * c.mass, "{lab}");
            } else {
                assert_eq!(lc.amax(), 0.0, "{lab}");
            }
        }
    }
    // Lumped node masses: ρAl/2 at ends, ρAl inside (n = 4).
    let b = body(Shape::Beam3, 4, Reference::Free);
    let inv = b.lumped_invariants();
    let p = params();
    let ml = p.rho * p.area() * p.length / 4.0;
    // S̄_xx diagonal on ux_j is m_j.
    let labels = b.dof_labels();
    for (j, want) in [0.5 * ml, ml, ml, ml, 0.5 * ml].iter().enumerate() {
        let i = labels.iter().position(|s| *s == format!("ux_{j}")).unwrap();
        assert!(rel_close(inv.s_kl[0][0][(i, i)], *want, 1e-14));
        assert!(rel_close(inv.s_bar[(0, i)], *want, 1e-14));
    }
}

#[test]
fn beam2_consistent_mass_matrix() {
    let b = body(Shape::Beam2, 1, Reference::Free);
    let p = params();
    let l = p.length;
    let (l2, ra) = (l * l, p.rho * p.area() * l / 420.0);
    #[rustfmt::skip]
    let m_t = DMatrix::from_row_slice(6, 6, &[
        140.0, 0.0, 0.0, 70.0, 0.0, 0.0,
        0.0, 156.0, 22.0 * l, 0.0, 54.0, -13.0 * l,
        0.0, 22.0 * l, 4.0 * l2, 0.0, 13.0 * l, -3.0 * l2,
        70.0, 0.0, 0.0, 140.0, 0.0, 0.0,
        0.0, 54.0, 13.0 * l, 0.0, 156.0, -22.0 * l,
        0.0, -13.0 * l, -3.0 * l2, 0.0, -22.0 * l, 4.0 * l2,
    ]) * ra;
    #[rustfmt::skip]
    let m_r = DMatrix::from_row_slice(6, 6, &[
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, 36.0, 3.0 * l, 0.0, -36.0, 3.0 * l,
        0.0, 3.0 * l, 4.0 * l2, 0.0, -3.0 * l, -l2,
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.0, -36.0, -3.0 * l, 0.0, 36.0, -3.0 * l,
        0.0, 3.0 * l, -l2, 0.0, -3.0 * l, 4.0 * l2,
    ]) * (p.rho * p.iz() / (30.0 * l));
    let inv = b.invariants();
    assert_mat_close(&inv.m_ff, &(m_t + m_r), 1e-12, "beam2 m_ff");
    // Planar: every z component vanishes exactly.
    assert_eq!(inv.s_kl[2][2].amax(), 0.0);
    assert_eq!(inv.s_bar.row(2).amax(), 0.0);
    assert_eq!(inv.s_t0.z, 0.0);
    for k in 0..3 {
        assert_eq!(inv.i_kl[2][k].amax(), 0.0);
        assert_eq!(inv.i_kl[k][2].amax(), 0.0);
        assert_eq!(inv.theta[(2, k)], 0.0);
    }
}

/// Classic 4×4 EB bending stiffness for `[v1, θ1, v2, θ2]`.
fn kb(ei: f64, l: f64) -> DMatrix<f64> {
    let l2 = l * l;
    #[rustfmt::skip]
    let k = DMatrix::from_row_slice(4, 4, &[
        12.0, 6.0 * l, -12.0, 6.0 * l,
        6.0 * l, 4.0 * l2, -6.0 * l, 2.0 * l2,
        -12.0, -6.0 * l, 12.0, -6.0 * l,
        6.0 * l, 2.0 * l2, -6.0 * l, 4.0 * l2,
    ]);
    k * (ei / l.powi(3))
}

fn place(k: &mut DMatrix<f64>, idx: &[usize], sub: &DMatrix<f64>) {
    for (a, &i) in idx.iter().enumerate() {
        for (b, &j) in idx.iter().enumerate() {
            k[(i, j)] += sub[(a, b)];
        }
    }
}

#[test]
fn stiffness_is_classic_euler_bernoulli() {
    let p = params();
    let l = p.length;
    let ax = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]);

    let mut k2 = DMatrix::zeros(6, 6);
    place(&mut k2, &[0, 3], &(&ax * (p.e * p.area() / l)));
    place(&mut k2, &[1, 2, 4, 5], &kb(p.e * p.iz(), l));
    let b2 = body(Shape::Beam2, 1, Reference::Free);
    assert_mat_close(&b2.invariants().k_ff, &k2, 1e-12, "beam2 K_ff");

    let mut k3 = DMatrix::zeros(12, 12);
    place(&mut k3, &[0, 6], &(&ax * (p.e * p.area() / l)));
    place(&mut k3, &[3, 9], &(&ax * (p.g * p.j / l)));
    place(&mut k3, &[1, 5, 7, 11], &kb(p.e * p.iz(), l));
    // w with θy = −w': flip the rotation signs.
    let t = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, -1.0, 1.0, -1.0]));
    place(&mut k3, &[2, 4, 8, 10], &(&t * kb(p.e * p.iy(), l) * &t));
    let b3 = body(Shape::Beam3, 1, Reference::Free);
    assert_mat_close(&b3.invariants().k_ff, &k3, 1e-12, "beam3 K_ff");
}

fn eigenvalues(k: &DMatrix<f64>) -> Vec<f64> {
    let mut v: Vec<f64> = k
        .clone()
        .symmetric_eigen()
        .eigenvalues
        .iter()
        .copied()
        .collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v
}

#[test]
fn free_element_rigid_modes_and_reference_conditions() {
    for (shape, zeros) in [(Shape::Beam2, 3), (Shape::Beam3, 6)] {
        for n in [1, 3] {
            let k = body(shape, n, Reference::Free).invariants().k_ff;
            let ev = eigenvalues(&k);
            let max = ev.last().unwrap().abs();
            let nzero = ev.iter().filter(|x| x.abs() < 1e-10 * max).count();
            assert_eq!(nzero, zeros, "{shape:?} n={n}: {ev:?}");
            assert!(ev[0] > -1e-10 * max);
        }
        for reference in [Reference::Clamped, Reference::Pinned] {
            for n in [1, 3] {
                let b = body(shape, n, reference);
                let k = b.invariants().k_ff;
                assert_mat_close(&k, &k.transpose(), 1e-15, "K symmetric");
                let ev = eigenvalues(&k);
                assert!(
                    ev[0] > 1e-9 * ev.last().unwrap(),
                    "{shape:?} {reference:?} n={n}: {ev:?}"
                );
                assert!(k.clone().cholesky().is_some());
            }
        }
    }
}

#[test]
fn dof_labels_and_counts() {
    let b = body(Shape::Beam2, 2, Reference::Clamped);
    assert_eq!(
        b.dof_labels(),
        ["ux_1", "uy_1", "rz_1", "ux_2", "uy_2", "rz_2"]
    );
    let b = body(Shape::Beam2, 2, Reference::Pinned);
    assert_eq!(
        b.dof_labels(),
        ["rz_0", "ux_1", "uy_1", "rz_1", "ux_2", "rz_2"]
    );
    let b = body(Shape::Beam3, 1, Reference::Pinned);
    assert_eq!(
        b.dof_labels(),
        ["ry_0", "rz_0", "ux_1", "rx_1", "ry_1", "rz_1"]
    );
    let b = body(Shape::Beam3, 2, Reference::Free);
    assert_eq!(b.nf(), 18);
    assert_eq!(b.dof_labels()[9], "rx_1");
    for b in all_bodies() {
        assert_eq!(b.dof_labels().len(), b.nf());
        let inv = b.invariants();
        assert_eq!(inv.m_ff.shape(), (b.nf(), b.nf()));
        assert_eq!(inv.s_bar.ncols(), b.nf());
    }
}

#[test]
fn shape_derivatives_match_finite_differences() {
    let l = 0.7;
    let h = 1e-6;
    for shape in [Shape::Beam2, Shape::Beam3] {
        for &(xi, eta, zeta) in &[(0.3, 0.02, -0.04), (0.85, -0.05, 0.01), (0.0, 0.0, 0.0)] {
            let sp = shape.elem_s(l, xi + h, eta, zeta);
            let sm = shape.elem_s(l, xi - h, eta, zeta);
            let fd = (sp - sm) / (2.0 * h * l);
            let g = shape.elem_dsx_dx(l, xi, eta, zeta);
            for i in 0..shape.elem_dofs() {
                assert!((fd[(0, i)] - g[i]).abs() < 1e-8, "{shape:?} dSx/dx {i}");
            }
            let (a, b, c) = shape.centerline_grad(l, xi);
            let sp = shape.elem_s(l, xi + h, 0.0, 0.0);
            let sm = shape.elem_s(l, xi - h, 0.0, 0.0);
            let fd = (sp - sm) / (2.0 * h * l);
            for i in 0..shape.elem_dofs() {
                assert!((fd[(0, i)] - a[i]).abs() < 1e-8, "{shape:?} u' {i}");
                assert!((fd[(1, i)] - b[i]).abs() < 1e-8, "{shape:?} v' {i}");
                assert!((fd[(2, i)] - c[i]).abs() < 1e-8, "{shape:?} w' {i}");
            }
        }
    }
}

#[test]
fn state_dependent_integrals_match_invariant_formulas() {
    for (n, b) in all_bodies().into_iter().enumerate() {
        let inv = b.invariants();
        let nf = b.nf();
        let q = DVector::from_vec(pseudo_random(nf, n as u64 + 1, 0.05));
        let qs = q.as_slice();

        let st = inv.s_t0 + &inv.s_bar * &q;
        assert!((b.s_t(qs) - st).amax() <= 1e-13 * st.amax());

        // U_kl = Θ_kl + (Ī_kl + Ī_lk)·q + qᵀ S̄_kl q;  Ī_θθ = tr(U) I − U.
        let u = Matrix3::from_fn(|k, l| {
            inv.theta[(k, l)]
                + (&inv.i_kl[k][l] + &inv.i_kl[l][k]).dot(&q)
                + q.dot(&(&inv.s_kl[k][l] * &q))
        });
        let itt = u.trace() * Matrix3::identity() - u;
        let got = b.i_theta_theta(qs);
        assert!(
            (got - itt).amax() <= 1e-13 * itt.amax(),
            "{b:?}\n{got}\n{itt}"
        );

        let row = |a: usize, c: usize| {
            (&inv.i_kl[a][c] - &inv.i_kl[c][a]).transpose()
                + q.transpose() * (&inv.s_kl[a][c] - &inv.s_kl[c][a])
        };
        let mut itf = Matrix3xX::zeros(nf);
        itf.row_mut(0).copy_from(&row(1, 2));
        itf.row_mut(1).copy_from(&row(2, 0));
        itf.row_mut(2).copy_from(&row(0, 1));
        let got = b.i_theta_f(qs);
        assert!(
            (&got - &itf).amax() <= 1e-12 * itf.amax(),
            "{b:?}\n{got}\n{itf}"
        );

        if b.shape == Shape::Beam2 {
            assert_eq!(b.s_t(qs).z, 0.0);
            assert_eq!(got.row(0).amax(), 0.0);
            assert_eq!(got.row(1).amax(), 0.0);
        }
    }
}

#[test]
fn stiffening_force_and_tangent_match_finite_differences() {
    for (n, b) in all_bodies().into_iter().enumerate() {
        let nf = b.nf();
        let q = pseudo_random(nf, 100 + n as u64, 0.02);
        let f = b.stiffening_force(&q);
        let k = b.stiffening_tangent(&q);
        assert_mat_close(&k, &k.transpose(), 1e-14, "tangent symmetric");
        let h = 1e-6;
        let mut fd_f = DVector::zeros(nf);
        let mut fd_k = DMatrix::zeros(nf, nf);
        for i in 0..nf {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[i] += h;
            qm[i] -= h;
            fd_f[i] = (b.stiffening_energy(&qp) - b.stiffening_energy(&qm)) / (2.0 * h);
            let col = (b.stiffening_force(&qp) - b.stiffening_force(&qm)) / (2.0 * h);
            fd_k.set_column(i, &col);
        }
        let fm = DMatrix::from_column_slice(nf, 1, f.as_slice());
        let fdm = DMatrix::from_column_slice(nf, 1, fd_f.as_slice());
        assert!(f.amax() > 0.0);
        assert_mat_close(&fm, &fdm, 1e-6, "stiffening force");
        assert_mat_close(&k, &fd_k, 1e-6, "stiffening tangent");
    }
}

#[test]
fn stiffening_energy_closed_form_cases() {
    // Pure axial stretch: v' = w' = 0 → U_nl = 0.
    let b = body(Shape::Beam3, 1, Reference::Clamped);
    let labels = b.dof_labels();
    let mut q = vec![0.0; b.nf()];
    q[labels.iter().position(|s| s == "ux_1").unwrap()] = 0.01;
    assert_eq!(b.stiffening_energy(&q), 0.0);
    // Uniform slope and stretch, v = θx, u = εx: U_nl = EA L (½ ε θ² + ⅛ θ⁴).
    let b = body(Shape::Beam2, 2, Reference::Free);
    let p = params();
    let (eps, th) = (0.003, 0.02);
    let labels = b.dof_labels();
    let mut q = vec![0.0; b.nf()];
    for j in 0..=2 {
        let x = j as f64 * p.length / 2.0;
        q[labels.iter().position(|s| *s == format!("ux_{j}")).unwrap()] = eps * x;
        q[labels.iter().position(|s| *s == format!("uy_{j}")).unwrap()] = th * x;
        q[labels.iter().position(|s| *s == format!("rz_{j}")).unwrap()] = th;
    }
    let want = p.e * p.area() * p.length * (0.5 * eps * th * th + 0.125 * th.powi(4));
    assert!(rel_close(b.stiffening_energy(&q), want, 1e-13));
    // Stiffening tangent at q = 0 vanishes.
    let k0 = b.stiffening_tangent(&vec![0.0; b.nf()]);
    assert_eq!(k0.amax(), 0.0);
}
