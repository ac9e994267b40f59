//! The compiled generated code computes bit for bit what tapes of the same
//! programs compute: every kernel function of every kernel set built into
//! this crate (beam2 planar and spatial scene, beam3, consistent and lumped,
//! every stiffening model, free and prescribed frame) at random inputs; and
//! the fixed-mesh bodies (`CompiledBody`) assembled by `KernelBody` against
//! the same bodies on tapes.

use ffr_bench::configs::{BODIES, KERNELS};
use ffr_bench::tape::TapeKernels;
use ffr_bench::{compiled, kernel_set, params, random};
use ffr_codegen::builder::BodyConfig;
use ffr_codegen::{generate_kernels, BodySpec};
use ffr_runtime::spec::{Formalism, Params, Reference, Stiffening};
use ffr_runtime::{
    Body, BodyForces, BodyMass, BodyState, BodyTangent, CompiledBody, ElementKernels, KernelBody,
    KernelInfo, KernelInput, MassOut, ResidualOut, TangentOut,
};

/// Bit-for-bit equality of two slices (NaN = NaN with the same bits).
fn same(what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            x.to_bits() == y.to_bits(),
            "{what}[{i}]: compiled {x:e} vs tape {y:e}"
        );
    }
}

/// What the kernel writes differs from what it leaves alone: fill outputs
/// with this before a call, so both must write the same entries.
const UNSET: f64 = 1.2345e300;

fn info_without_scratch(i: &KernelInfo) -> KernelInfo {
    KernelInfo {
        scratch: 0,
        ..i.clone()
    }
}

/// Parameter values around `params()` (each scaled by a random factor).
fn params_variant(seed: u64) -> Params {
    let f = random(8, seed, 0.5);
    let a = params().to_array();
    Params::from_array(std::array::from_fn(|i| a[i] * (1.0 + f[i])))
}

/// Outputs of every kernel function at one set of inputs.
#[derive(Debug, PartialEq)]
struct All {
    mass: Vec<Vec<f64>>,
    residual: Vec<Vec<f64>>,
    tangent: Vec<Vec<f64>>,
    residual_elastic: Vec<f64>,
    tangent_elastic: Vec<Vec<f64>>,
    energy: f64,
    invariants: Vec<f64>,
    point_shape: Vec<Vec<f64>>,
}

struct In {
    x0: f64,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    frame: [f64; 9],
    bp: f64,
    gp: f64,
    xi: f64,
}

fn inputs(n: usize, l: f64, seed: u64) -> In {
    let r = random(14, seed, 1.0);
    let mut frame = [0.0; 9];
    for (k, f) in frame.iter_mut().enumerate() {
        *f = r[k] * if k < 3 { 10.0 } else { 2.0 };
    }
    In {
        x0: (3.0 + r[9]) * l,
        q: random(n, seed + 1, 0.05 * l),
        qd: random(n, seed + 2, 0.5 * l),
        qdd: random(n, seed + 3, 5.0 * l),
        frame,
        bp: 4e6 * (1.0 + 0.1 * r[10]),
        gp: 2e3 * (1.0 + 0.1 * r[11]),
        xi: 0.5 + 0.5 * r[12],
    }
}

fn eval(k: &dyn ElementKernels, c: &[f64], x: &In, scratch: &mut [f64]) -> All {
    let info = k.info();
    let n = info.n_local;
    let (_, inv_len) = ffr_runtime::kernel::invariant_layout(n);
    let input = KernelInput {
        x0: x.x0,
        q: &x.q,
        qd: &x.qd,
        qdd: &x.qdd,
        frame: &x.frame,
    };
    let mut s_t = [UNSET; 3];
    let mut m = [
        vec![UNSET; n * n],
        vec![UNSET; n * 6],
        vec![UNSET; 6 * n],
        vec![UNSET; 36],
    ];
    {
        let [mee, mef, mre, mrf] = &mut m;
        k.mass(
            c,
            x.x0,
            &x.q,
            &mut MassOut {
                s_t: &mut s_t,
                m_ee: mee,
                m_e_frame: mef,
                m_ref_e: mre,
                m_ref_frame: mrf,
            },
            scratch,
        );
    }
    let mut mass = vec![s_t.to_vec()];
    mass.extend(m);
    let (mut residual, mut tangent) = (Vec::new(), Vec::new());
    if info.free_frame() {
        let (mut f_r, mut f_th, mut f_e) = ([UNSET; 3], [UNSET; 3], vec![UNSET; n]);
        k.residual(
            c,
            &input,
            &mut ResidualOut {
                f_r: &mut f_r,
                f_th: &mut f_th,
                f_e: &mut f_e,
            },
            scratch,
        );
        residual = vec![f_r.to_vec(), f_th.to_vec(), f_e];
        let (mut f_r, mut f_th, mut f_e) = ([UNSET; 3], [UNSET; 3], vec![UNSET; n]);
        let mut t = [
            vec![UNSET; n * n],
            vec![UNSET; n * 9],
            vec![UNSET; 6 * n],
            vec![UNSET; 54],
        ];
        {
            let [kee, def, kre, drf] = &mut t;
            k.tangent(
                c,
                &input,
                x.bp,
                x.gp,
                &mut TangentOut {
                    f_r: &mut f_r,
                    f_th: &mut f_th,
                    f_e: &mut f_e,
                    k_ee: kee,
                    d_e_frame: def,
                    k_ref_e: kre,
                    d_ref_frame: drf,
                },
                scratch,
            );
        }
        tangent = vec![f_r.to_vec(), f_th.to_vec(), f_e];
        tangent.extend(t);
    }
    let mut residual_elastic = vec![UNSET; n];
    k.residual_elastic(c, &input, &mut residual_elastic, scratch);
    let (mut fe, mut kee) = (vec![UNSET; n], vec![UNSET; n * n]);
    k.tangent_elastic(c, &input, x.bp, x.gp, &mut fe, &mut kee, scratch);
    let energy = k.energy(c, &x.q, scratch);
    let mut invariants = vec![UNSET; inv_len];
    k.element_invariants(c, x.x0, &mut invariants, scratch);
    let (mut s, mut psi) = (vec![UNSET; 3 * n], vec![UNSET; 3 * n]);
    k.point_shape(c, x.xi, &mut s, &mut psi, scratch);
    All {
        mass,
        residual,
        tangent,
        residual_elastic,
        tangent_elastic: vec![fe, kee],
        energy,
        invariants,
        point_shape: vec![s, psi],
    }
}

fn same_all(what: &str, a: &All, b: &All) {
    let groups = [
        ("mass", &a.mass, &b.mass),
        ("residual", &a.residual, &b.residual),
        ("tangent", &a.tangent, &b.tangent),
        ("tangent_elastic", &a.tangent_elastic, &b.tangent_elastic),
        ("point_shape", &a.point_shape, &b.point_shape),
    ];
    for (name, x, y) in groups {
        assert_eq!(x.len(), y.len(), "{what}: {name}");
        for (i, (u, v)) in x.iter().zip(y.iter()).enumerate() {
            same(&format!("{what}: {name} output {i}"), u, v);
        }
    }
    same(
        &format!("{what}: residual_elastic"),
        &a.residual_elastic,
        &b.residual_elastic,
    );
    same(&format!("{what}: energy"), &[a.energy], &[b.energy]);
    same(
        &format!("{what}: element_invariants"),
        &a.invariants,
        &b.invariants,
    );
}

#[test]
fn every_kernel_function_is_bit_for_bit_the_tape() {
    for &(name, ..) in KERNELS {
        let set = kernel_set(name);
        let tape = TapeKernels::from_set(&set);
        let comp = compiled(name).unwrap();
        assert_eq!(
            info_without_scratch(comp.info()),
            info_without_scratch(tape.info()),
            "{name}: info"
        );
        assert_eq!(
            comp.info().scratch,
            0,
            "{name}: compiled kernels need no scratch"
        );
        let n = comp.info().n_local;
        let mut scratch = vec![0.0; tape.info().scratch];
        let nc = comp.info().n_coefficients;
        for trial in 0..8u64 {
            let p = if trial == 0 {
                params()
            } else {
                params_variant(trial)
            };
            let l = p.length / (1 + trial as usize % 5) as f64;
            let (mut cc, mut ct) = (vec![UNSET; nc], vec![UNSET; nc]);
            comp.coefficients(&p, l, &mut cc);
            tape.coefficients(&p, l, &mut ct);
            same(&format!("{name} trial {trial}: coefficients"), &cc, &ct);
            let x = inputs(n, l, 100 * trial + 7);
            let a = eval(comp.as_ref(), &cc, &x, &mut scratch);
            let b = eval(&tape, &ct, &x, &mut scratch);
            same_all(&format!("{name} trial {trial}"), &a, &b);
            // A few outputs are nonzero (the comparison is not vacuous).
            assert!(a.energy != 0.0 && a.mass[1].iter().any(|v| *v != UNSET && *v != 0.0));
        }
    }
}

fn state_of(nf: usize, l: f64, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>, [f64; 9]) {
    let x = inputs(nf, l, seed);
    (x.q, x.qd, x.qdd, x.frame)
}

fn check_body<B>(name: &str)
where
    B: CompiledBody + From<Params>,
{
    let &(_, shape, n, r, f, s) = BODIES.iter().find(|b| b.0 == name).unwrap();
    let reference: Reference = r.parse().unwrap();
    let config = BodyConfig::new(name, shape, n, reference)
        .formalism(f.parse::<Formalism>().unwrap())
        .stiffening(s.parse::<Stiffening>().unwrap());
    let model = config.kernels.model(std::path::Path::new(".")).unwrap();
    let spec = BodySpec::new(model.shape.clone(), n, reference).unwrap();
    assert_eq!(B::ELEMENTS, n);
    assert_eq!(B::REFERENCE, reference);
    assert_eq!(B::NF, spec.nf());
    assert_eq!(B::DIM, model.shape.dimension);
    let labels: Vec<String> = spec.dofs().iter().map(|d| d.to_string()).collect();
    assert_eq!(
        B::DOFS,
        labels.iter().map(String::as_str).collect::<Vec<_>>()
    );

    let body = B::from(params());
    let cb = KernelBody::compiled(&body).unwrap();
    let tb = KernelBody::new(
        TapeKernels::from_set(&generate_kernels(&model).unwrap()),
        body.params(),
        n,
        reference,
    )
    .unwrap();
    assert_eq!(cb.layout(), tb.layout(), "{name}: layout");
    let nf = B::NF;
    let hb = cb.layout().half_bandwidth;
    let (mut wc, mut wt) = (cb.work(), tb.work());
    let l = params().length / n as f64;
    for trial in 0..4 {
        let (q, qd, qdd, frame) = state_of(nf, l, 11 + trial);
        let st = BodyState {
            q_f: &q,
            qd_f: &qd,
            qdd_f: &qdd,
            frame,
        };
        let t = format!("{name} trial {trial}");
        for frame_rows in [true, false] {
            let (mut fc, mut ft) = (BodyForces::zeros(nf), BodyForces::zeros(nf));
            cb.forces(&st, frame_rows, &mut wc, &mut fc);
            tb.forces(&st, frame_rows, &mut wt, &mut ft);
            assert_eq!(fc, ft, "{t}: forces (frame rows {frame_rows})");
            let (mut tc, mut tt) = (BodyTangent::zeros(nf, hb), BodyTangent::zeros(nf, hb));
            cb.tangent(&st, 4e6, 2e3, frame_rows, &mut wc, &mut fc, &mut tc);
            tb.tangent(&st, 4e6, 2e3, frame_rows, &mut wt, &mut ft, &mut tt);
            assert_eq!(fc, ft, "{t}: tangent's forces");
            assert_eq!(tc, tt, "{t}: tangent (frame rows {frame_rows})");
        }
        let (mut mc, mut mt) = (BodyMass::zeros(nf, hb), BodyMass::zeros(nf, hb));
        cb.mass(&q, &mut wc, &mut mc);
        tb.mass(&q, &mut wt, &mut mt);
        assert_eq!(mc, mt, "{t}: mass");
        let (ec, et) = (
            cb.elastic_energy(&q, &mut wc),
            tb.elastic_energy(&q, &mut wt),
        );
        assert_eq!(ec.to_bits(), et.to_bits(), "{t}: energy");
    }
    assert_eq!(cb.invariants(), tb.invariants(), "{name}: invariants");
    for x in [0.0, 0.37, 1.0] {
        let x = x * params().length;
        assert_eq!(cb.point_shape(x).unwrap(), tb.point_shape(x).unwrap());
    }
}

#[test]
fn fixed_mesh_bodies_are_bit_for_bit_the_tape_bodies() {
    check_body::<ffr_bench::arm8::Arm8>("arm8");
    check_body::<ffr_bench::arm32::Arm32>("arm32");
    check_body::<ffr_bench::bar4::Bar4>("bar4");
}

#[test]
fn prescribed_frame_kernels_have_no_reference_rows() {
    let k = compiled("beam3_prescribed_fourth_order").unwrap();
    assert!(!k.info().free_frame());
    let set = kernel_set("beam3_prescribed_fourth_order");
    assert!(set.residual.is_none() && set.tangent.is_none());
}
