//! Modal bodies in the runtime (`ffr_runtime::ModalBody`, built by
//! `ffr::modal`): with every mode kept the reduced body is the full body in
//! other coordinates — forces, mass blocks, tangent, energy and point shapes
//! equal `Φᵀ (full body at q_f = Φ η)` to round-off; the tangent matches
//! central differences of the forces; the mass blocks are the forces'
//! acceleration-linear part; static modes are mass-orthonormal and the
//! damping is `diag(2 ζ ω)`.

use ffr::kernels::{BeamSpec, FrameModel};
use ffr::modal::{modal_body, ModalSettings};
use ffr::runtime::nalgebra::{DMatrix, DVector};
use ffr::runtime::spec::{Reference, Stiffening};
use ffr::runtime::{Body, BodyForces, BodyMass, BodyState, BodyTangent};
use ffr_cli::benchmarks::spin_up::KRB;

fn beam(shape: &str, elements: usize, reference: Reference) -> BeamSpec {
    let mut b = BeamSpec::new(shape, elements, KRB);
    b.reference = reference;
    b.options.stiffening = Stiffening::FourthOrder;
    b.options.frame = FrameModel::Free;
    b
}

fn wave(n: usize, amp: f64, phase: f64) -> Vec<f64> {
    (0..n)
        .map(|i| amp * ((i as f64 + 1.0) * 0.77 + phase).sin())
        .collect()
}

struct Eval {
    f: BodyForces,
    t: BodyTangent,
    m: BodyMass,
    energy: f64,
}

fn eval(body: &dyn Body, q: &[f64], qd: &[f64], qdd: &[f64], frame: [f64; 9]) -> Eval {
    let lay = body.layout();
    let (nf, hb) = (lay.nf, lay.half_bandwidth);
    let mut w = body.work();
    let mut f = BodyForces::zeros(nf);
    let mut t = BodyTangent::zeros(nf, hb);
    let mut m = BodyMass::zeros(nf, hb);
    let s = BodyState {
        q_f: q,
        qd_f: qd,
        qdd_f: qdd,
        frame,
    };
    body.tangent(&s, 3.0e4, 1.7e2, true, &mut w, &mut f, &mut t);
    body.mass(q, &mut w, &mut m);
    let energy = body.elastic_energy(q, &mut w);
    Eval { f, t, m, energy }
}

fn close(what: &str, a: &[f64], b: &[f64], rel: f64) {
    let scale = b
        .iter()
        .chain(a)
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(1e-300);
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= rel * scale,
            "{what}[{i}]: {x} vs {y} (scale {scale}, rel {:.2e})",
            (x - y).abs() / scale
        );
    }
    assert_eq!(a.len(), b.len(), "{what}: lengths");
}

/// Every mode kept, no static modes: the modal body at `η` is the full body
/// at `q_f = Φ η` seen through `Φ`.
fn all_modes_reproduce_the_full_body(shape: &str, elements: usize, planar_frame: bool) {
    let spec = beam(shape, elements, Reference::Clamped);
    let full = spec.body().unwrap();
    let nf = full.layout().nf;
    let settings = ModalSettings {
        static_modes: false,
        ..ModalSettings::truncation(nf)
    };
    let modal = modal_body(&spec, &settings).unwrap();
    // The stiffening runs through the element scalars (what this test
    // checks against the full body).
    assert!(modal.uses_element_scalars());
    let k = modal.layout().nf;
    assert_eq!(k, nf, "every elastic mode of a clamped body");
    let phi = modal.data().phi.clone();
    let map =
        |x: &[f64]| -> Vec<f64> { (&phi * DVector::from_column_slice(x)).as_slice().to_vec() };
    let back = |x: &[f64]| -> Vec<f64> {
        (phi.transpose() * DVector::from_column_slice(x))
            .as_slice()
            .to_vec()
    };
    // A deformed, moving state: tip deflections of a few cm.
    let eta = wave(k, 0.02, 0.0);
    let etad = wave(k, 0.3, 1.0);
    let etadd = wave(k, 2.0, 2.0);
    let mut frame = [0.3, -0.2, 0.1, 0.5, -0.4, 0.2, 1.5, -0.7, 0.9];
    if planar_frame {
        for i in [2, 3, 4, 6, 7] {
            frame[i] = 0.0;
        }
    }
    let r = eval(&modal, &eta, &etad, &etadd, frame);
    let f = eval(&full, &map(&eta), &map(&etad), &map(&etadd), frame);
    let tol = 1e-10;
    close("f_r", &r.f.f_r, &f.f.f_r, tol);
    close("f_θ", &r.f.f_th, &f.f.f_th, tol);
    close("f_f", &r.f.f_f, &back(&f.f.f_f), tol);
    close("energy", &[r.energy], &[f.energy], tol);
    close("S_t", &r.m.s_t, &f.m.s_t, tol);
    let ptkp = |b: &DMatrix<f64>| (phi.transpose() * b * &phi).as_slice().to_vec();
    close(
        "k_ff",
        r.t.k_ff.to_dense().as_slice(),
        &ptkp(&f.t.k_ff.to_dense()),
        tol,
    );
    close(
        "m_ff",
        r.m.m_ff.to_dense().as_slice(),
        &ptkp(&f.m.m_ff.to_dense()),
        tol,
    );
    // 6 × n_f blocks times Φ; n_f × 9 blocks with Φᵀ.
    let right = |a: &[f64], rows: usize| {
        let a = DMatrix::from_row_slice(rows, nf, a);
        let p = a * &phi;
        (0..rows)
            .flat_map(|i| (0..k).map(move |j| (i, j)))
            .map(|(i, j)| p[(i, j)])
            .collect::<Vec<_>>()
    };
    let left = |a: &[f64], cols: usize| {
        let a = DMatrix::from_row_slice(nf, cols, a);
        let p = phi.transpose() * a;
        (0..k)
            .flat_map(|i| (0..cols).map(move |j| (i, j)))
            .map(|(i, j)| p[(i, j)])
            .collect::<Vec<_>>()
    };
    close("k_ref_f", &r.t.k_ref_f, &right(&f.t.k_ref_f, 6), tol);
    close("m_ref_f", &r.m.m_ref_f, &right(&f.m.m_ref_f, 6), tol);
    close("d_f_frame", &r.t.d_f_frame, &left(&f.t.d_f_frame, 9), tol);
    close("m_f_frame", &r.m.m_f_frame, &left(&f.m.m_f_frame, 6), tol);
    close("d_ref_frame", &r.t.d_ref_frame, &f.t.d_ref_frame, tol);
    close("m_ref_frame", &r.m.m_ref_frame, &f.m.m_ref_frame, tol);
    // Point shapes: u(η) = u₀ + Σ s_m η_m equals the full body's at Φ η.
    let length = KRB.length;
    for x in [0.0, 0.37 * length, length] {
        let ps_r = modal.point_shape(x).unwrap();
        let ps_f = full.point_shape(x).unwrap();
        let q = map(&eta);
        let disp = |ps: &ffr::runtime::PointShape, q: &[f64]| {
            let mut u = ps.u0;
            for (d, s, _) in &ps.entries {
                for a in 0..3 {
                    u[a] += s[a] * q[*d];
                }
            }
            u
        };
        close("point", &disp(&ps_r, &eta), &disp(&ps_f, &q), tol);
    }
}

#[test]
fn all_modes_reproduce_the_full_planar_body() {
    all_modes_reproduce_the_full_body("beam2", 3, true);
}

#[test]
fn all_modes_reproduce_the_full_spatial_body() {
    all_modes_reproduce_the_full_body("beam3", 2, false);
}

/// The tangent (dual numbers) against central differences of the forces,
/// and the mass blocks against the forces' dependence on the accelerations,
/// for a reduced body with static modes and damping.
#[test]
fn tangent_and_mass_blocks_match_differences_of_the_forces() {
    let spec = beam("beam3", 3, Reference::Clamped);
    let settings = ModalSettings {
        damping: vec![0.02],
        ..ModalSettings::truncation(4)
    };
    let body = modal_body(&spec, &settings).unwrap();
    let k = body.layout().nf;
    assert!(k > 4, "static modes were added: {:?}", body.layout().labels);
    let q = wave(k, 0.05, 0.3);
    let qd = wave(k, 0.4, 1.3);
    let qdd = wave(k, 3.0, 2.3);
    let frame = [0.3, -0.2, 0.1, 0.5, -0.4, 0.2, 1.5, -0.7, 0.9];
    let (bp, gp) = (3.0e4, 1.7e2);
    let base = eval(&body, &q, &qd, &qdd, frame);
    let forces = |q: &[f64], qd: &[f64], qdd: &[f64], frame: [f64; 9]| {
        let mut w = body.work();
        let mut f = BodyForces::zeros(k);
        let s = BodyState {
            q_f: q,
            qd_f: qd,
            qdd_f: qdd,
            frame,
        };
        body.forces(&s, true, &mut w, &mut f);
        let mut all = f.f_r.to_vec();
        all.extend(f.f_th);
        all.extend(f.f_f);
        all
    };
    let h = 1e-6;
    for j in 0..k {
        let step = |s: f64| {
            let mut a = q.clone();
            let mut b = qd.clone();
            let mut c = qdd.clone();
            a[j] += s * h;
            b[j] += s * h * gp;
            c[j] += s * h * bp;
            forces(&a, &b, &c, frame)
        };
        let (p, m) = (step(1.0), step(-1.0));
        let fd: Vec<f64> = p.iter().zip(&m).map(|(a, b)| (a - b) / (2.0 * h)).collect();
        let mut an: Vec<f64> = (0..6).map(|r| base.t.k_ref_f[r * k + j]).collect();
        an.extend((0..k).map(|a| base.t.k_ff.get(a, j)));
        close(&format!("tangent column {j}"), &an, &fd, 1e-6);
    }
    // The forces are quadratic in the frame motion: central differences are
    // exact but for round-off, which a larger step keeps small.
    let h = 1e-2;
    for i in 0..9 {
        let step = |s: f64| {
            let mut fr = frame;
            fr[i] += s * h;
            forces(&q, &qd, &qdd, fr)
        };
        let (p, m) = (step(1.0), step(-1.0));
        let fd: Vec<f64> = p.iter().zip(&m).map(|(a, b)| (a - b) / (2.0 * h)).collect();
        let mut an: Vec<f64> = (0..6).map(|r| base.t.d_ref_frame[r * 9 + i]).collect();
        an.extend((0..k).map(|a| base.t.d_f_frame[a * 9 + i]));
        close(&format!("frame column {i}"), &an, &fd, 1e-6);
    }
    // Mass blocks: forces at rest are linear in (η̈, ā, α).
    let zeros = vec![0.0; k];
    let rest = |qdd: &[f64], fr: [f64; 9]| forces(&q, &zeros, qdd, fr);
    let f0 = rest(&zeros, [0.0; 9]);
    for j in 0..k {
        let mut e = zeros.clone();
        e[j] = 1.0;
        let d: Vec<f64> = rest(&e, [0.0; 9])
            .iter()
            .zip(&f0)
            .map(|(a, b)| a - b)
            .collect();
        let mut an: Vec<f64> = (0..6).map(|r| base.m.m_ref_f[r * k + j]).collect();
        an.extend((0..k).map(|a| base.m.m_ff.get(a, j)));
        close(&format!("mass column {j}"), &an, &d, 1e-9);
    }
    for i in 0..6 {
        let mut fr = [0.0; 9];
        fr[i] = 1.0;
        let d: Vec<f64> = rest(&zeros, fr)
            .iter()
            .zip(&f0)
            .map(|(a, b)| a - b)
            .collect();
        let mut an: Vec<f64> = (0..6).map(|r| base.m.m_ref_frame[r * 6 + i]).collect();
        an.extend((0..k).map(|a| base.m.m_f_frame[a * 6 + i]));
        close(&format!("frame mass column {i}"), &an, &d, 1e-9);
    }
    // The static modes are mass-orthonormal to the rest; damping 2ζω on the
    // normal modes only.
    let inv = body.invariants();
    let eye = DMatrix::<f64>::identity(k, k);
    close("ΦᵀMΦ", inv.m_ff.as_slice(), eye.as_slice(), 1e-10);
    let d = body.damping().expect("damping").to_dense();
    for a in 0..k {
        for b in 0..k {
            let want = if a == b && a < 4 {
                2.0 * 0.02 * inv.k_ff[(a, a)].sqrt()
            } else {
                0.0
            };
            assert!(
                (d[(a, b)] - want).abs() <= 1e-12 * want.abs().max(1e-12),
                "D[{a},{b}] = {} vs {want}",
                d[(a, b)]
            );
        }
    }
}

/// The spin-up (8 elements, 4 rad/s, fourth-order stiffening, first 10 s)
/// with the beam reduced to 2, 4 and 8 normal modes plus static modes
/// converges to the full body: the largest difference of the transverse
/// tip deflection shrinks and is below 1e-3 of the peak from 4 modes on;
/// every mode kept gives the full body's history to round-off (ε times the
/// stiffness's condition number).
/// Without the static modes the axial strain cannot follow the bending
/// (no foreshortening) and the fourth-order energy over-stiffens the beam:
/// the peak is far too small, which is why the static modes are the default.
#[test]
fn spin_up_with_modes_converges_to_the_full_body() {
    use ffr_cli::benchmarks::spin_up::{run, SpinUp};
    let base = SpinUp {
        t_end: 10.0,
        ..SpinUp::new(4.0)
    };
    let full = run(&base).unwrap();
    assert!(full.diverged.is_none());
    let peak = full.min_transverse().unwrap().1.abs();
    let diff = |settings: ModalSettings| {
        let r = run(&SpinUp {
            modal: Some(settings),
            ..base.clone()
        })
        .unwrap();
        assert!(r.diverged.is_none(), "{:?}", r.diverged);
        assert_eq!(r.t.len(), full.t.len());
        r.tip_transverse
            .iter()
            .zip(&full.tip_transverse)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max)
            / peak
    };
    let d: Vec<f64> = [2, 4, 8]
        .iter()
        .map(|&k| diff(ModalSettings::truncation(k)))
        .collect();
    eprintln!("relative differences to the full body, 2/4/8 modes: {d:?}");
    assert!(d[0] >= d[1] && d[1] >= d[2] * 0.999, "{d:?}");
    assert!(d[1] < 1e-3 && d[2] < 1e-3, "{d:?}");
    // Every mode: the same equations in other coordinates. The histories
    // then differ by round-off, which the stiffness's spread amplifies: the
    // bound is ε κ with κ = ω_max²/ω_1² of the body (3.4e7 here, so
    // ε κ ≈ 7.6e-9; the Newton tolerance is not the limit: rtol 1e-14
    // instead of 1e-10 changes the difference by under 5 %).
    let every = ModalSettings {
        static_modes: false,
        ..ModalSettings::truncation(24)
    };
    let k_modal = modal_body(&base.beam(), &every).unwrap().invariants().k_ff;
    let kappa = k_modal[(23, 23)] / k_modal[(0, 0)];
    let d_all = diff(every);
    eprintln!("every mode: {d_all:e}, ε κ = {:e}", f64::EPSILON * kappa);
    assert!(d_all < f64::EPSILON * kappa, "every mode kept: {d_all:e}");
    let pure = run(&SpinUp {
        modal: Some(ModalSettings {
            static_modes: false,
            ..ModalSettings::truncation(4)
        }),
        ..base.clone()
    })
    .unwrap();
    let pure_peak = pure.min_transverse().unwrap().1.abs();
    eprintln!("pure truncation peak {pure_peak} vs {peak}");
    assert!(pure_peak < 0.5 * peak, "{pure_peak} vs {peak}");
}

/// Every built-in kernel set with one of `stiffenings`, compiled and on
/// tapes, on `elements` elements, with a label: shapes in their dimensions
/// × frames × formalisms × stiffening models × compiled and tape.
fn kernel_specs(elements: usize, stiffenings: &[Stiffening]) -> Vec<(BeamSpec, String)> {
    use ffr::runtime::spec::Formalism;
    let mut out = Vec::new();
    for (shape, dims) in [("beam2", &[2usize, 3][..]), ("beam3", &[3][..])] {
        for &dim in dims {
            for frame in [FrameModel::Free, FrameModel::PrescribedAtRest] {
                for formalism in [Formalism::Consistent, Formalism::Lumped] {
                    for &stiffening in stiffenings {
                        for tape in [false, true] {
                            let mut b = BeamSpec::new(shape, elements, KRB)
                                .scene_dim(dim)
                                .frame(frame)
                                .formalism(formalism)
                                .stiffening(stiffening);
                            b.force_tape = tape;
                            let what = format!(
                                "{shape} {dim}D {frame:?} {formalism:?} {stiffening:?} tape={tape}"
                            );
                            out.push((b, what));
                        }
                    }
                }
            }
        }
    }
    out
}

/// The element-scalar kernels of a set with stiffening against its other
/// kernels: with `S` the map `elastic_scalars` gives (read off unit
/// vectors), `K_e` the tangent at rest (`∇²U_nl(0) = 0`: the stiffening
/// energies are cubic and quartic), `f_el` = `force_elastic(q)`:
/// `f_el = K_e q + Sᵀ g(S q)` (`scalar_force`), and the tangent at `q`
/// equals `K_e + Sᵀ H(S q) S` (`scalar_tangent`, whose `g` is
/// `scalar_force`'s).
fn check_element_scalars(
    k: &dyn ffr::runtime::ElementKernels,
    c: &[f64],
    q: &[f64],
    f_el: &[f64],
    s: &mut [f64],
    what: &str,
) {
    use ffr::runtime::KernelInput;
    let n = q.len();
    let mut z = vec![0.0; n];
    let nz = k.elastic_scalars(c, q, &mut z, s);
    assert!(nz > 0 && nz <= n, "{what}: {nz} element scalars");
    // S, column by column.
    let mut sm = vec![vec![0.0; n]; nz];
    for a in 0..n {
        let mut e = vec![0.0; n];
        e[a] = 1.0;
        let mut za = vec![0.0; n];
        assert_eq!(k.elastic_scalars(c, &e, &mut za, s), nz);
        for j in 0..nz {
            sm[j][a] = za[j];
        }
    }
    for j in 0..nz {
        let sq: f64 = (0..n).map(|a| sm[j][a] * q[a]).sum();
        assert!(
            (sq - z[j]).abs() <= 1e-14 * (1.0 + sq.abs()),
            "{what}: z[{j}] is not S q"
        );
    }
    let zero = vec![0.0; n];
    let tangent_at = |qq: &[f64], s: &mut [f64]| {
        let x = KernelInput {
            x0: 8.0 / 3.0,
            q: qq,
            qd: &zero,
            qdd: &zero,
            frame: &[0.0; 9],
        };
        let (mut f, mut kt) = (vec![0.0; n], vec![0.0; n * n]);
        k.tangent_elastic(c, &x, 0.0, 0.0, &mut f, &mut kt, s);
        kt
    };
    let k_e = tangent_at(&zero, s);
    let mut g = vec![0.0; n];
    assert!(k.scalar_force(c, &z, &mut g, s), "{what}: scalar_force");
    let scale = f_el.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for a in 0..n {
        let lin: f64 = (0..n).map(|b| k_e[a * n + b] * q[b]).sum();
        let nl: f64 = (0..nz).map(|j| sm[j][a] * g[j]).sum();
        assert!(
            (lin + nl - f_el[a]).abs() <= 1e-12 * scale,
            "{what}: K_e q + Sᵀ g at {a}: {} against force_elastic {}",
            lin + nl,
            f_el[a]
        );
    }
    let (mut g2, mut h) = (vec![0.0; n], vec![0.0; n * n]);
    assert!(
        k.scalar_tangent(c, &z, &mut g2, &mut h, s),
        "{what}: scalar_tangent"
    );
    assert_eq!(g, g2, "{what}: the two kernels' gradients");
    let k_t = tangent_at(q, s);
    let kscale = k_t.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for a in 0..n {
        for b in 0..n {
            let mut v = k_e[a * n + b];
            for i in 0..nz {
                for j in 0..nz {
                    v += sm[i][a] * h[i * n + j] * sm[j][b];
                }
            }
            assert!(
                (v - k_t[a * n + b]).abs() <= 1e-12 * kscale,
                "{what}: K_e + Sᵀ H S at ({a}, {b}): {v} against the tangent {}",
                k_t[a * n + b]
            );
        }
    }
}

/// `force_elastic` (the elastic force alone, generated for the stiffening
/// models; a modal body's stiffening calls it at `q_f = Φ η`) is what
/// `residual_elastic` gives at rest (`q̇ = q̈ = 0`, frame at rest), for every
/// built-in kernel set, compiled and on tapes, element by element and
/// through the body (`Body::elastic_force` against `Body::forces`); the
/// element-scalar kernels agree with both (`check_element_scalars`); models
/// without stiffening report that they have none.
#[test]
fn force_elastic_is_the_residual_at_rest() {
    use ffr::runtime::{ElementKernels, KernelInput};
    let mut checked = 0;
    let all = [
        Stiffening::Off,
        Stiffening::SecondOrder,
        Stiffening::FourthOrder,
    ];
    for (b, what) in kernel_specs(3, &all) {
        let stiffening = b.options.stiffening;
        let k = b.kernels().unwrap();
        let n = k.info().n_local;
        let mut c = vec![0.0; k.info().n_coefficients];
        k.coefficients(&KRB, 8.0 / 3.0, &mut c);
        let mut s = vec![0.0; k.info().scratch];
        let q = wave(n, 0.05, 0.3);
        let z = vec![0.0; n];
        let (mut a, mut r) = (vec![0.0; n], vec![0.0; n]);
        let has = k.force_elastic(&c, &q, &mut a, &mut s);
        assert_eq!(has, stiffening != Stiffening::Off, "{what}");
        if !has {
            assert!(a.iter().all(|x| *x == 0.0), "{what}: f_e touched");
            continue;
        }
        let x = KernelInput {
            x0: 8.0 / 3.0,
            q: &q,
            qd: &z,
            qdd: &z,
            frame: &[0.0; 9],
        };
        k.residual_elastic(&c, &x, &mut r, &mut s);
        let scale = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            assert!(
                (a[i] - r[i]).abs() <= 1e-13 * scale,
                "{what}: f_e[{i}] {} against {}",
                a[i],
                r[i]
            );
        }
        check_element_scalars(&k, &c, &q, &a, &mut s, &what);
        // Through the body.
        let body = b.body().unwrap();
        let nf = body.layout().nf;
        let qf = wave(nf, 0.05, 0.9);
        let zf = vec![0.0; nf];
        let mut w = body.work();
        let mut f = vec![0.0; nf];
        assert!(body.elastic_force(&qf, &mut w, &mut f), "{what}");
        let mut out = BodyForces::zeros(nf);
        let st = BodyState {
            q_f: &qf,
            qd_f: &zf,
            qdd_f: &zf,
            frame: [0.0; 9],
        };
        body.forces(&st, false, &mut w, &mut out);
        let scale = out.f_f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..nf {
            assert!(
                (f[i] - out.f_f[i]).abs() <= 1e-13 * scale,
                "{what}: body f_f[{i}] {} against {}",
                f[i],
                out.f_f[i]
            );
        }
        checked += 1;
    }
    // 3 shapes-in-dimensions × 2 frames × 2 formalisms × 2 stiffening
    // models × compiled and tape.
    assert_eq!(checked, 48);
}

/// `scalar_force_batch` (generated: the program of `scalar_force` in a loop
/// over the elements; on tapes: the trait's default loop) gives the same
/// bits as `scalar_force` element by element, with one coefficient set for
/// all elements and with one per element (`c_stride`); it refuses sizes
/// that disagree. Through the body: `Body::scalar_forces` is
/// `Body::scalar_derivatives` per element, on an equal and a graded mesh.
#[test]
fn scalar_force_batch_is_scalar_force_per_element() {
    use ffr::runtime::{ElementKernels, KernelBody};
    let mut checked = 0;
    for (b, what) in kernel_specs(5, &[Stiffening::SecondOrder, Stiffening::FourthOrder]) {
        let k = b.kernels().unwrap();
        let (n, nc) = (k.info().n_local, k.info().n_coefficients);
        let mut s = vec![0.0; k.info().scratch + 2 * n];
        let mut z = vec![0.0; n];
        let nz = k.elastic_scalars(&vec![0.0; nc], &vec![0.0; n], &mut z, &mut s);
        assert!(nz > 0, "{what}: element scalars");
        let ne = 5;
        // Five element lengths; coefficients per element.
        let mut c_all = vec![0.0; ne * nc];
        for e in 0..ne {
            let l = 1.0 + 0.4 * e as f64;
            k.coefficients(&KRB, l, &mut c_all[e * nc..(e + 1) * nc]);
        }
        let z_all = wave(nz * ne, 0.08, 0.7);
        for stride in [0, nc] {
            let mut g_all = vec![f64::NAN; nz * ne];
            assert!(
                k.scalar_force_batch(&c_all, stride, &z_all, &mut g_all, ne, &mut s),
                "{what}: stride {stride}"
            );
            for e in 0..ne {
                let c = &c_all[e * stride..e * stride + nc];
                let mut zz = vec![0.0; n];
                for j in 0..nz {
                    zz[j] = z_all[j * ne + e];
                }
                let mut g = vec![0.0; n];
                assert!(k.scalar_force(c, &zz, &mut g, &mut s), "{what}");
                for j in 0..nz {
                    assert_eq!(
                        g_all[j * ne + e].to_bits(),
                        g[j].to_bits(),
                        "{what}: stride {stride}, element {e}, scalar {j}"
                    );
                }
            }
        }
        // Sizes that disagree are refused.
        let mut g_all = vec![0.0; nz * ne];
        let short = &z_all[..nz * ne - 1];
        assert!(
            !k.scalar_force_batch(&c_all, 0, short, &mut g_all, ne, &mut s),
            "{what}: a short z_all"
        );
        assert!(
            !k.scalar_force_batch(&c_all, 0, &z_all, &mut g_all[..nz * ne - 1], ne, &mut s),
            "{what}: a short g_all"
        );
        assert!(
            !k.scalar_force_batch(&c_all[..(ne - 1) * nc], nc, &z_all, &mut g_all, ne, &mut s),
            "{what}: too few coefficients"
        );
        assert!(
            !k.scalar_force_batch(&c_all, usize::MAX, &z_all, &mut g_all, ne, &mut s),
            "{what}: a stride past the address space"
        );
        // Through the body, on an equal and a graded mesh.
        let equal = b.body().unwrap();
        let nodes = [0.0, 0.5, 1.5, 3.0, 5.5, 8.0];
        let graded =
            KernelBody::with_nodes(b.kernels().unwrap(), KRB, &nodes, Reference::Clamped).unwrap();
        for body in [&equal as &dyn Body, &graded] {
            let layout = body.scalar_layout().expect("element scalars");
            assert_eq!((layout.elements, layout.scalars), (ne, nz), "{what}");
            let mut w = body.work();
            let mut g_all = vec![f64::NAN; nz * ne];
            assert!(body.scalar_forces(&z_all, &mut w, &mut g_all), "{what}");
            for e in 0..ne {
                let mut zz = vec![0.0; n];
                for j in 0..nz {
                    zz[j] = z_all[j * ne + e];
                }
                let mut g = vec![0.0; n];
                assert!(body.scalar_derivatives(e, &zz, &mut w, &mut g, None));
                for j in 0..nz {
                    assert_eq!(
                        g_all[j * ne + e].to_bits(),
                        g[j].to_bits(),
                        "{what}: body, element {e}, scalar {j}"
                    );
                }
            }
        }
        checked += 1;
    }
    // 3 shapes-in-dimensions × 2 frames × 2 formalisms × 2 stiffening
    // models × compiled and tape.
    assert_eq!(checked, 48);
}

/// A reproducible pseudo-random number in `[-1, 1)` (xorshift64*).
fn uniform(state: &mut u64) -> f64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    let x = state.wrapping_mul(0x2545_f491_4f6c_dd1d);
    (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The generated inertia kernels (`ffr_codegen::modal::generate_modal_kernels`,
/// run from tapes: the operations of the emitted code, in its order)
/// against the run-time equations (`InertiaTerms`, `ModalBody::new`) of the
/// same reduced body: forces, tangent and mass blocks equal to round-off
/// (1e-12 of each block's largest entry) at random states, with and without
/// the reference rows.
fn generated_kernels_match_the_runtime(
    shape: &str,
    stiffening: Stiffening,
    frame: FrameModel,
    scene: Option<ffr::runtime::spec::SceneDim>,
    modes: usize,
) {
    use ffr::modal::modal_body_tape;
    let mut spec = beam(shape, 8, Reference::Clamped);
    spec.options.stiffening = stiffening;
    spec.options.frame = frame;
    spec.options.scene = scene;
    let settings = ModalSettings::truncation(modes);
    let runtime = modal_body(&spec, &settings).unwrap();
    let generated = modal_body_tape(&spec, &settings).unwrap();
    assert!(generated.uses_generated_kernels());
    assert!(!runtime.uses_generated_kernels());
    let lay = runtime.layout();
    let (k, hb) = (lay.nf, lay.half_bandwidth);
    assert_eq!(generated.layout(), lay);
    let planar = lay.scene_dim == 2;
    let mut seed = 0x9e37_79b9_7f4a_7c15u64 ^ (modes as u64) << 7 ^ shape.len() as u64;
    let rnd = |seed: &mut u64, n: usize, amp: f64| -> Vec<f64> {
        (0..n).map(|_| amp * uniform(seed)).collect()
    };
    let tol = 1e-12;
    for _ in 0..4 {
        let q = rnd(&mut seed, k, 0.05);
        let qd = rnd(&mut seed, k, 0.5);
        let qdd = rnd(&mut seed, k, 3.0);
        let mut frame: [f64; 9] = rnd(&mut seed, 9, 2.0).try_into().unwrap();
        if planar {
            for i in [2, 3, 4, 6, 7] {
                frame[i] = 0.0;
            }
        }
        let state = BodyState {
            q_f: &q,
            qd_f: &qd,
            qdd_f: &qdd,
            frame,
        };
        let (bp, gp) = (2.5e4 * (1.0 + uniform(&mut seed)), 1.3e2);
        for frame_rows in [true, false] {
            let run = |body: &dyn Body| {
                let mut w = body.work();
                let mut f = BodyForces::zeros(k);
                let mut f2 = BodyForces::zeros(k);
                let mut t = BodyTangent::zeros(k, hb);
                let mut m = BodyMass::zeros(k, hb);
                body.forces(&state, frame_rows, &mut w, &mut f2);
                body.tangent(&state, bp, gp, frame_rows, &mut w, &mut f, &mut t);
                body.mass(&q, &mut w, &mut m);
                (f, f2, t, m)
            };
            let (fg, fg2, tg, mg) = run(&generated);
            let (fr, fr2, tr, mr) = run(&runtime);
            let what = |s: &str| format!("{shape} {stiffening:?} {frame:?} rows {frame_rows}: {s}");
            close(&what("f_r"), &fg.f_r, &fr.f_r, tol);
            close(&what("f_θ"), &fg.f_th, &fr.f_th, tol);
            close(&what("f_f"), &fg.f_f, &fr.f_f, tol);
            close(&what("forces f_f"), &fg2.f_f, &fr2.f_f, tol);
            close(&what("forces f_r"), &fg2.f_r, &fr2.f_r, tol);
            close(&what("forces f_θ"), &fg2.f_th, &fr2.f_th, tol);
            close(
                &what("k_ff"),
                tg.k_ff.to_dense().as_slice(),
                tr.k_ff.to_dense().as_slice(),
                tol,
            );
            close(&what("d_f_frame"), &tg.d_f_frame, &tr.d_f_frame, tol);
            close(&what("k_ref_f"), &tg.k_ref_f, &tr.k_ref_f, tol);
            close(&what("d_ref_frame"), &tg.d_ref_frame, &tr.d_ref_frame, tol);
            close(&what("S_t"), &mg.s_t, &mr.s_t, tol);
            close(
                &what("m_ff"),
                mg.m_ff.to_dense().as_slice(),
                mr.m_ff.to_dense().as_slice(),
                tol,
            );
            close(&what("m_f_frame"), &mg.m_f_frame, &mr.m_f_frame, tol);
            close(&what("m_ref_f"), &mg.m_ref_f, &mr.m_ref_f, tol);
            close(&what("m_ref_frame"), &mg.m_ref_frame, &mr.m_ref_frame, tol);
            // Not a trivially zero comparison.
            assert!(fr.f_f.iter().any(|x| *x != 0.0));
            assert!(tr.k_ff.to_dense().amax() > 0.0);
            if frame_rows {
                assert!(tr.k_ref_f.iter().any(|x| *x != 0.0));
            }
        }
    }
}

#[test]
fn generated_kernels_planar_linear_free() {
    generated_kernels_match_the_runtime("beam2", Stiffening::Off, FrameModel::Free, None, 4);
}

#[test]
fn generated_kernels_planar_stiffening_free() {
    generated_kernels_match_the_runtime(
        "beam2",
        Stiffening::FourthOrder,
        FrameModel::Free,
        None,
        3,
    );
}

#[test]
fn generated_kernels_planar_stiffening_prescribed() {
    generated_kernels_match_the_runtime(
        "beam2",
        Stiffening::SecondOrder,
        FrameModel::Prescribed,
        None,
        4,
    );
}

#[test]
fn generated_kernels_planar_shape_in_a_spatial_scene() {
    generated_kernels_match_the_runtime(
        "beam2",
        Stiffening::Off,
        FrameModel::Free,
        Some(ffr::runtime::spec::SceneDim::Spatial),
        3,
    );
}

#[test]
fn generated_kernels_spatial_linear_free() {
    generated_kernels_match_the_runtime("beam3", Stiffening::Off, FrameModel::Free, None, 5);
}

#[test]
fn generated_kernels_spatial_stiffening_free() {
    generated_kernels_match_the_runtime(
        "beam3",
        Stiffening::FourthOrder,
        FrameModel::Free,
        None,
        4,
    );
}

#[test]
fn generated_kernels_spatial_linear_prescribed() {
    generated_kernels_match_the_runtime("beam3", Stiffening::Off, FrameModel::Prescribed, None, 4);
}

/// A spin-up with the generated modal kernels (on tapes, `--modes 4
/// --tape`) and with the run-time equations: the same tip history to
/// 1e-9 of the peak deflection (the two differ by the round-off of their
/// operation orders).
#[test]
fn spin_up_with_generated_modal_kernels_matches_the_runtime() {
    use ffr_cli::benchmarks::spin_up::{run, SpinUp};
    let base = SpinUp {
        t_end: 4.0,
        modal: Some(ModalSettings::truncation(4)),
        ..SpinUp::new(4.0)
    };
    let runtime = run(&base).unwrap();
    let generated = run(&SpinUp {
        force_tape: true,
        ..base.clone()
    })
    .unwrap();
    assert!(runtime.diverged.is_none() && generated.diverged.is_none());
    assert_eq!(runtime.t.len(), generated.t.len());
    let peak = runtime.min_transverse().unwrap().1.abs();
    assert!(peak > 1e-3, "peak {peak}");
    let d = runtime
        .tip_transverse
        .iter()
        .zip(&generated.tip_transverse)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    eprintln!("generated vs run-time modal kernels: tip difference {d:e} m, peak {peak} m");
    assert!(d <= 1e-9 * peak, "{d:e} vs peak {peak}");
}
