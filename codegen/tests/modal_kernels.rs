//! A modal body's generated inertia kernels
//! (`ffr_codegen::modal::generate_modal_kernels`), run from tapes: the
//! tangent equals central differences of the residual (the equations are
//! polynomials of degree ≤ 2 in each input, so the differences are exact up
//! to round-off), the mass blocks are the residual's acceleration-linear
//! part, the linear elastic force is in the kernels exactly when the body
//! has no stiffening; the constants are the model's bits; op counts,
//! the fallback above `MAX_GENERATED_MODES` and determinism.

#![cfg(feature = "modal")]

use ffr_codegen::eom::OutArr;
use ffr_codegen::modal::{
    exact_invariants, generate_modal_kernels, ModalKernelSet, ModalModel, MAX_GENERATED_MODES,
};
use ffr_codegen::poly::to_f64;
use ffr_codegen::program::{Inputs, Program};
use ffr_codegen::{
    BodySpec, KernelModel, KernelOptions, ModalSettings, Params, Reference, SceneDim, Shape,
    Stiffening,
};

fn krb() -> Params {
    Params {
        length: 8.0,
        rho: 2766.67,
        area: 7.2968e-5,
        iy: 8.2189e-9,
        iz: 8.2189e-9,
        e: 6.8952e10,
        g: 2.6e10,
        j: 1.6438e-8,
    }
}

fn spec(shape: &str, elements: usize) -> BodySpec {
    BodySpec::new(
        Shape::resolve(shape, None).unwrap(),
        elements,
        Reference::Clamped,
    )
    .unwrap()
}

fn model(shape: &str, elements: usize, modes: usize, stiffening: Stiffening) -> ModalModel {
    ModalModel::of_body(
        &spec(shape, elements),
        &krb(),
        &ModalSettings {
            static_modes: false,
            ..ModalSettings::truncation(modes)
        },
        stiffening,
    )
    .unwrap()
}

/// The outputs of `p` at the inputs, by array entry.
fn run(p: &Program, x: &Inputs) -> Vec<((OutArr, u32), f64)> {
    let t = p.tape();
    let mut slots = vec![0.0; t.n_slots()];
    t.run(x, &mut slots);
    t.outputs
        .iter()
        .map(|&(o, r)| (o, slots[r as usize]))
        .collect()
}

/// Dense arrays of the outputs of `p` (missing entries are zero).
fn dense(p: &Program, x: &Inputs, arr: OutArr, len: usize) -> Vec<f64> {
    let mut v = vec![0.0; len];
    for ((a, i), y) in run(p, x) {
        if a == arr {
            v[i as usize] = y;
        }
    }
    v
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

struct State {
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    frame: [f64; 9],
}

fn state(k: usize, planar: bool, seed: &mut u64) -> State {
    let mut v = |n: usize, a: f64| (0..n).map(|_| a * lcg(seed)).collect::<Vec<_>>();
    let (q, qd, qdd) = (v(k, 0.05), v(k, 0.5), v(k, 3.0));
    let mut frame: [f64; 9] = v(9, 2.0).try_into().unwrap();
    if planar {
        for i in [2, 3, 4, 6, 7] {
            frame[i] = 0.0;
        }
    }
    State { q, qd, qdd, frame }
}

fn inputs<'a>(s: &'a State, bp: f64, gp: f64) -> Inputs<'a> {
    Inputs {
        q: &s.q,
        qd: &s.qd,
        qdd: &s.qdd,
        frame: &s.frame,
        bp,
        gp,
        ..Inputs::default()
    }
}

/// `[f_r; f_θ; f_e]` of the residual program at `s`.
fn residual(set: &ModalKernelSet, s: &State) -> Vec<f64> {
    let k = set.modes;
    let x = inputs(s, 0.0, 0.0);
    let mut v = dense(&set.residual, &x, OutArr::Fr, 3);
    v.extend(dense(&set.residual, &x, OutArr::Fth, 3));
    v.extend(dense(&set.residual, &x, OutArr::Fe, k));
    v
}

fn assert_close(what: &str, a: &[f64], b: &[f64], rel: f64) {
    assert_eq!(a.len(), b.len(), "{what}");
    let scale = a.iter().chain(b).fold(1e-300f64, |m, x| m.max(x.abs()));
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= rel * scale,
            "{what}[{i}]: {x} vs {y} (scale {scale:e})"
        );
    }
}

/// The tangent's blocks against central differences of the residual, the
/// mass blocks against its differences in the accelerations.
fn tangent_and_mass_match_differences(set: &ModalKernelSet) {
    let k = set.modes;
    let planar = set.scene == SceneDim::Planar;
    let mut seed = 7 + k as u64;
    let (bp, gp) = (2.1e4, 1.7e2);
    for _ in 0..3 {
        let s = state(k, planar, &mut seed);
        let x = inputs(&s, bp, gp);
        let t = &set.tangent;
        // The tangent's residual is the residual.
        let mut r_t = dense(t, &x, OutArr::Fr, 3);
        r_t.extend(dense(t, &x, OutArr::Fth, 3));
        r_t.extend(dense(t, &x, OutArr::Fe, k));
        assert_eq!(r_t, residual(set, &s), "tangent's residual");
        let k_ee = dense(t, &x, OutArr::Kee, k * k);
        let k_ref = dense(t, &x, OutArr::KrefE, 6 * k);
        let d_e = dense(t, &x, OutArr::DeFrame, 9 * k);
        let d_ref = dense(t, &x, OutArr::DrefFrame, 54);
        let (mut fd_kee, mut fd_kref) = (vec![0.0; k * k], vec![0.0; 6 * k]);
        let diff = |set: &ModalKernelSet, f: &dyn Fn(&mut State, f64)| {
            let h = 1e-4;
            let (mut p, mut m) = (clone(&s), clone(&s));
            f(&mut p, h);
            f(&mut m, -h);
            let (rp, rm) = (residual(set, &p), residual(set, &m));
            rp.iter()
                .zip(&rm)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect::<Vec<_>>()
        };
        let mut m_ref = vec![0.0; 6 * k];
        let mut m_ee = vec![0.0; k * k];
        for b in 0..k {
            let dq = diff(set, &|s, h| s.q[b] += h);
            let dqd = diff(set, &|s, h| s.qd[b] += h);
            let dqdd = diff(set, &|s, h| s.qdd[b] += h);
            for r in 0..6 + k {
                let v = dq[r] + gp * dqd[r] + bp * dqdd[r];
                if r < 6 {
                    fd_kref[r * k + b] = v;
                    m_ref[r * k + b] = dqdd[r];
                } else {
                    fd_kee[(r - 6) * k + b] = v;
                    m_ee[(r - 6) * k + b] = dqdd[r];
                }
            }
        }
        assert_close("K_ee", &k_ee, &fd_kee, 1e-7);
        assert_close("K_ref,e", &k_ref, &fd_kref, 1e-7);
        let (mut fd_de, mut fd_dref) = (vec![0.0; 9 * k], vec![0.0; 54]);
        let (mut m_e_frame, mut m_ref_frame) = (vec![0.0; 6 * k], vec![0.0; 36]);
        for c in 0..9 {
            if planar && [2, 3, 4, 6, 7].contains(&c) {
                continue;
            }
            let d = diff(set, &|s, h| s.frame[c] += h);
            for r in 0..6 {
                fd_dref[r * 9 + c] = d[r];
                if c < 6 {
                    m_ref_frame[r * 6 + c] = d[r];
                }
            }
            for a in 0..k {
                fd_de[a * 9 + c] = d[6 + a];
                if c < 6 {
                    m_e_frame[a * 6 + c] = d[6 + a];
                }
            }
        }
        assert_close("∂f_e/∂frame", &d_e, &fd_de, 1e-7);
        assert_close("∂f_ref/∂frame", &d_ref, &fd_dref, 1e-7);
        // The mass blocks: the acceleration-linear part of the residual.
        let mx = Inputs {
            q: &s.q,
            ..Inputs::default()
        };
        let m = &set.mass;
        assert_close("m_ee", &dense(m, &mx, OutArr::Mee, k * k), &m_ee, 1e-7);
        assert_close(
            "m_ref,e",
            &dense(m, &mx, OutArr::MrefE, 6 * k),
            &m_ref,
            1e-7,
        );
        assert_close(
            "m_e,frame",
            &dense(m, &mx, OutArr::MeFrame, 6 * k),
            &m_e_frame,
            1e-7,
        );
        assert_close(
            "m_ref,frame",
            &dense(m, &mx, OutArr::MrefFrame, 36),
            &m_ref_frame,
            1e-7,
        );
        // The elastic-only programs are the residual's and tangent's f_e
        // rows and K_ee.
        assert_eq!(
            dense(&set.residual_elastic, &x, OutArr::Fe, k),
            dense(&set.residual, &x, OutArr::Fe, k)
        );
        assert_eq!(dense(&set.tangent_elastic, &x, OutArr::Kee, k * k), k_ee);
    }
}

fn clone(s: &State) -> State {
    State {
        q: s.q.clone(),
        qd: s.qd.clone(),
        qdd: s.qdd.clone(),
        frame: s.frame,
    }
}

#[test]
fn planar_tangent_and_mass_match_differences_of_the_residual() {
    let m = model("beam2", 6, 4, Stiffening::Off);
    let set = generate_modal_kernels(&m, SceneDim::Planar)
        .unwrap()
        .unwrap();
    assert!(set.linear_elastic);
    tangent_and_mass_match_differences(&set);
}

#[test]
fn spatial_tangent_and_mass_match_differences_of_the_residual() {
    let m = model("beam3", 4, 5, Stiffening::FourthOrder);
    let set = generate_modal_kernels(&m, SceneDim::Spatial)
        .unwrap()
        .unwrap();
    assert!(!set.linear_elastic);
    tangent_and_mass_match_differences(&set);
}

/// At rest (`η̇ = η̈ = 0`, no frame motion) `f_f` is `K̃ η` without
/// stiffening and zero with it (the runtime adds the elastic force).
#[test]
fn linear_elastic_force_only_without_stiffening() {
    for stiffening in [Stiffening::Off, Stiffening::FourthOrder] {
        let m = model("beam2", 6, 4, stiffening);
        let set = generate_modal_kernels(&m, SceneDim::Planar)
            .unwrap()
            .unwrap();
        let k = set.modes;
        let q: Vec<f64> = (0..k).map(|i| 0.01 * (i as f64 + 1.0)).collect();
        let zero = vec![0.0; k];
        let frame = [0.0; 9];
        let x = Inputs {
            q: &q,
            qd: &zero,
            qdd: &zero,
            frame: &frame,
            ..Inputs::default()
        };
        let f = dense(&set.residual_elastic, &x, OutArr::Fe, k);
        let kq: Vec<f64> = (0..k)
            .map(|a| (0..k).map(|b| m.projected.k_ff[(a, b)] * q[b]).sum())
            .collect();
        if stiffening.is_on() {
            assert!(f.iter().all(|v| *v == 0.0), "{f:?}");
        } else {
            assert!(kq.iter().any(|v| v.abs() > 1.0));
            assert_close("K̃ η", &f, &kq, 1e-13);
        }
    }
}

/// Every constant is the model's number, bit for bit; a number that is not
/// finite is an error, not a panic.
#[test]
fn exact_constants_are_the_models_bits() {
    let m = model("beam3", 3, 4, Stiffening::Off);
    let inv = &m.projected;
    let exact = exact_invariants(inv).unwrap();
    let bits = |p: &ffr_codegen::poly::Poly| match p.as_constant() {
        Some(r) => to_f64(&r).to_bits(),
        None => 0.0f64.to_bits(),
    };
    let k = m.len();
    for a in 0..k {
        for b in 0..k {
            assert_eq!(bits(exact.m_ff.get(a, b)), inv.m_ff[(a, b)].to_bits());
            assert_eq!(bits(exact.k_ff.get(a, b)), inv.k_ff[(a, b)].to_bits());
            assert_eq!(
                bits(exact.s_kl[1][2].get(a, b)),
                inv.s_kl[1][2][(a, b)].to_bits()
            );
        }
        assert_eq!(bits(exact.s_bar.get(1, a)), inv.s_bar[(1, a)].to_bits());
        assert_eq!(bits(&exact.i_kl[0][1][a]), inv.i_kl[0][1][a].to_bits());
    }
    assert_eq!(bits(&exact.mass), inv.mass.to_bits());
    assert_eq!(bits(&exact.theta[0][0]), inv.theta[(0, 0)].to_bits());
    for bad in [f64::NAN, f64::INFINITY] {
        let mut broken = m.clone();
        broken.projected.s_kl[0][0][(1, 1)] = bad;
        assert!(exact_invariants(&broken.projected).is_err());
        assert!(generate_modal_kernels(&broken, SceneDim::Spatial).is_err());
    }
}

fn body_file(m: &ModalModel, shape: &str, elements: usize) -> String {
    let sp = spec(shape, elements);
    let set = ffr_codegen::generate_checked(&KernelModel::new(
        sp.shape.clone(),
        KernelOptions::default(),
    ))
    .unwrap();
    let opts = ffr_codegen::EmitOptions {
        type_name: "Beam".into(),
        ..Default::default()
    };
    ffr_codegen::emit::emit_modal_body_file(&set, &sp, &opts, m, &krb()).unwrap()
}

/// The banner lists every kernel's operation count; the same input gives
/// the same programs and the same file, byte for byte.
#[test]
fn op_counts_and_determinism() {
    let m = model("beam2", 8, 4, Stiffening::Off);
    let a = generate_modal_kernels(&m, SceneDim::Planar)
        .unwrap()
        .unwrap();
    let b = generate_modal_kernels(&m.clone(), SceneDim::Planar)
        .unwrap()
        .unwrap();
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
    for (name, p) in a.programs() {
        assert!(p.ops() > 0, "{name}");
    }
    // The tangent does more than the residual, which does more than its
    // elastic rows alone.
    assert!(a.tangent.ops() > a.residual.ops());
    assert!(a.residual.ops() > a.residual_elastic.ops());
    let file = body_file(&m, "beam2", 8);
    assert_eq!(file, body_file(&m, "beam2", 8));
    assert!(file.contains("impl ::ffr::runtime::ModalKernels for BeamModalKernels"));
    assert!(file.contains("ModalBody::with_kernels"));
    for (name, p) in a.programs() {
        let line = format!("//     {name:<20} {}\n", p.ops());
        assert!(file.contains(&line), "banner line `{line}` missing");
        assert!(file.contains(&format!("    // operations: {}\n", p.ops())));
    }
}

/// Above `MAX_GENERATED_MODES` modes: no kernels, the run-time equations,
/// and the banner says so.
#[test]
fn too_many_modes_fall_back_to_the_runtime() {
    let k = MAX_GENERATED_MODES + 1;
    let m = model("beam2", 12, k, Stiffening::Off);
    assert_eq!(m.len(), k);
    assert!(generate_modal_kernels(&m, SceneDim::Planar)
        .unwrap()
        .is_none());
    let file = body_file(&m, "beam2", 12);
    assert!(!file.contains("ModalKernels for"));
    assert!(file.contains(&format!("More than {MAX_GENERATED_MODES} modes")));
    assert!(file.contains("ModalBody::new("));
}
