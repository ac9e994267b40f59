//! Shared by the integration tests: run the generator's kernel programs on
//! tapes (`Program::tape()`, the emitted code's exact operation order),
//! assemble element contributions over a body of `N` elements, and the
//! parameter sets and pseudo-random states of the cross-checks.
#![allow(dead_code)]

use ffr_codegen::eom::OutArr;
use ffr_codegen::poly::{Param, Poly, Sym};
use ffr_codegen::program::{Inputs, Program, Tape};
use ffr_codegen::{
    generate_kernels, BodySpec, ExactInvariants, Formalism, FrameModel, KernelModel, KernelOptions,
    KernelSet, Params, Reference, SceneDim, Shape, Stiffening,
};
use ffr_reference as rf;
use nalgebra::{DMatrix, Matrix3};
use num_traits::ToPrimitive;

/// The generator's kernel programs for `shape` with these options.
pub fn kernel_set(
    shape: &str,
    formalism: Formalism,
    stiffening: Stiffening,
    scene_dim: usize,
    free_frame: bool,
) -> KernelSet {
    let options = KernelOptions::new()
        .formalism(formalism)
        .stiffening(stiffening)
        .scene(SceneDim::from_dim(scene_dim).unwrap())
        .frame(FrameModel::from_flags(free_frame, false));
    generate_kernels(&KernelModel::new(
        Shape::resolve(shape, None).unwrap(),
        options,
    ))
    .unwrap()
}

/// A program on a tape with its registers.
pub struct Run {
    tape: Tape,
    slots: Vec<f64>,
}

impl Run {
    pub fn new(p: &Program) -> Self {
        let tape = p.tape();
        let slots = vec![0.0; tape.n_slots()];
        Self { tape, slots }
    }

    /// Run and hand every output `(array, index, value)` to `out`.
    pub fn run(&mut self, inputs: &Inputs, mut out: impl FnMut(OutArr, usize, f64)) {
        self.tape.run(inputs, &mut self.slots);
        for &((arr, i), r) in &self.tape.outputs {
            out(arr, i as usize, self.slots[r as usize]);
        }
    }
}

/// `[params in Param::FIELDS order, l]`, what `Inputs::params` reads.
pub fn param_array(p: &Params, l: f64) -> [f64; 9] {
    let mut a = [0.0; 9];
    a[..8].copy_from_slice(&p.to_array());
    a[8] = l;
    a
}

/// The coefficient array of `set` for `params` and element length `l`,
/// as the coefficient program computes it (not checked: an entry the
/// program does not set is NaN, a product of parameters beyond `f64` is
/// infinite or zero).
pub fn coefficient_values(set: &KernelSet, p: &Params, l: f64) -> Vec<f64> {
    let mut c = vec![f64::NAN; set.coefficients.len()];
    let pa = param_array(p, l);
    Run::new(&set.coefficient_program).run(
        &Inputs {
            params: &pa,
            ..Inputs::default()
        },
        |arr, i, v| {
            assert_eq!(arr, OutArr::Coef);
            c[i] = v;
        },
    );
    c
}

/// The coefficient array of `set` for `params` and element length `l`,
/// every entry set and finite.
pub fn coefficients(set: &KernelSet, p: &Params, l: f64) -> Vec<f64> {
    let c = coefficient_values(set, p, l);
    assert!(
        c.iter().all(|x| x.is_finite()),
        "a coefficient is not set or not finite"
    );
    c
}

/// The `ffr-reference` parameters as the generator's.
pub fn params_of(p: &rf::RefParams) -> Params {
    Params {
        length: p.length,
        rho: p.rho,
        area: p.area(),
        iy: p.iy(),
        iz: p.iz(),
        e: p.e,
        g: p.g,
        j: p.j,
    }
}

/// Four bodies from 1 mm to 100 m.
pub fn param_sets() -> Vec<rf::RefParams> {
    vec![
        // Steel bar, 1 m, 20 × 10 mm.
        rf::RefParams {
            length: 1.0,
            rho: 7850.0,
            wy: 0.02,
            wz: 0.01,
            e: 2.1e11,
            g: 8.1e10,
            j: 1.2e-8,
        },
        // Micro beam: 1 mm long, 10 × 20 µm, silicon-like.
        rf::RefParams {
            length: 1e-3,
            rho: 2330.0,
            wy: 1e-5,
            wz: 2e-5,
            e: 1.69e11,
            g: 7.9e10,
            j: 3e-21,
        },
        // 100 m aluminium boom, 0.5 × 0.3 m.
        rf::RefParams {
            length: 1e2,
            rho: 2700.0,
            wy: 0.5,
            wz: 0.3,
            e: 7e10,
            g: 2.6e10,
            j: 5e-3,
        },
        // Kane–Ryan–Banerjee-like slender beam, 8 m.
        rf::RefParams {
            length: 8.0,
            rho: 2766.67,
            wy: 0.0105,
            wz: 0.00695,
            e: 6.8952e10,
            g: 2.6e10,
            j: 1.6e-9,
        },
    ]
}

pub fn rf_shape(shape: &str) -> rf::Shape {
    match shape {
        "beam2" => rf::Shape::Beam2,
        "beam3" => rf::Shape::Beam3,
        s => panic!("no reference for {s}"),
    }
}

pub fn rf_reference(r: Reference) -> rf::Reference {
    match r {
        Reference::Clamped => rf::Reference::Clamped,
        Reference::Pinned => rf::Reference::Pinned,
        Reference::Free => rf::Reference::Free,
    }
}

pub const REFERENCES: [Reference; 3] = [Reference::Clamped, Reference::Pinned, Reference::Free];

/// A deterministic pseudo-random vector (xorshift), entries in [−s, s].
pub fn pseudo_random(n: usize, seed: u64, s: f64) -> Vec<f64> {
    let mut x = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            s * ((x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
        })
        .collect()
}

/// Pseudo-random elastic coordinates of `body` with translations of order
/// `a·l` and rotations of order `a` (slopes of order `a`).
pub fn state(spec: &BodySpec, l: f64, seed: u64, a: f64) -> Vec<f64> {
    let r = pseudo_random(spec.nf(), seed, 1.0);
    spec.dofs()
        .iter()
        .zip(r)
        .map(|(d, x)| {
            if d.kind.is_translation() {
                a * l * x
            } else {
                a * x
            }
        })
        .collect()
}

/// An exact polynomial in the runtime parameters evaluated in `f64`.
pub fn eval_params(p: &Poly, v: &Params) -> f64 {
    p.terms()
        .map(|(m, c)| {
            m.factors()
                .iter()
                .fold(c.to_f64().unwrap(), |acc, &(s, e)| {
                    let Sym::Param(par) = s else {
                        panic!("{s} in a parameter polynomial")
                    };
                    let x = match par {
                        Param::ElemLength => panic!("l in a body polynomial"),
                        p => v.get(p).unwrap(),
                    };
                    acc * x.powi(e)
                })
        })
        .sum()
}

/// An exact element polynomial (in the parameters, the element length `l`
/// and the offset `x₀`) evaluated in `f64` term by term: its value and the
/// sum of the magnitudes of its terms, the scale of the rounding error of
/// any order of evaluation.
pub fn eval_element(p: &Poly, v: &Params, l: f64, x0: f64) -> (f64, f64) {
    let (mut value, mut scale) = (0.0, 0.0);
    for (m, c) in p.terms() {
        let t = m
            .factors()
            .iter()
            .fold(ffr_codegen::poly::to_f64(c), |acc, &(s, e)| {
                let x = match s {
                    Sym::Param(Param::ElemLength) => l,
                    Sym::Param(par) => v.get(par).unwrap(),
                    Sym::X0 => x0,
                    s => panic!("{s} in an element polynomial of the parameters, l and x0"),
                };
                acc * x.powi(e)
            });
        value += t;
        scale += t.abs();
    }
    (value, scale)
}

/// Dense invariants of a body (the theory's names), from any route.
#[derive(Clone, Debug)]
pub struct Dense {
    pub mass: f64,
    pub s_t0: [f64; 3],
    pub s_bar: DMatrix<f64>,
    pub s_kl: [[DMatrix<f64>; 3]; 3],
    pub i_kl: [[DMatrix<f64>; 3]; 3],
    pub theta: Matrix3<f64>,
    pub m_ff: DMatrix<f64>,
    pub k_ff: DMatrix<f64>,
}

impl Dense {
    pub fn zeros(nf: usize) -> Self {
        Dense {
            mass: 0.0,
            s_t0: [0.0; 3],
            s_bar: DMatrix::zeros(3, nf),
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(nf, nf))),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(nf, 1))),
            theta: Matrix3::zeros(),
            m_ff: DMatrix::zeros(nf, nf),
            k_ff: DMatrix::zeros(nf, nf),
        }
    }

    /// The exact body polynomials (`BodySpec::exact_invariants`) evaluated
    /// at `p` with [`eval_params`].
    pub fn from_exact(exact: &ExactInvariants, p: &Params) -> Self {
        let nf = exact.nf;
        let ev = |q: &Poly| eval_params(q, p);
        let mut g = Dense::zeros(nf);
        g.mass = ev(&exact.mass);
        for k in 0..3 {
            g.s_t0[k] = ev(&exact.s_t0[k]);
            for l in 0..3 {
                g.theta[(k, l)] = ev(&exact.theta[k][l]);
                g.s_kl[k][l] = DMatrix::from_fn(nf, nf, |i, j| ev(exact.s_kl[k][l].get(i, j)));
                g.i_kl[k][l] = DMatrix::from_fn(nf, 1, |i, _| ev(&exact.i_kl[k][l][i]));
            }
        }
        g.s_bar = DMatrix::from_fn(3, nf, |k, i| ev(exact.s_bar.get(k, i)));
        g.m_ff = DMatrix::from_fn(nf, nf, |i, j| ev(exact.m_ff.get(i, j)));
        g.k_ff = DMatrix::from_fn(nf, nf, |i, j| ev(exact.k_ff.get(i, j)));
        g
    }

    /// Every number with its name as `ffr invariants --json` keys it
    /// (`mass`, `St0[k]`, `Sbar[k][a]`, `Skl.xy[a][b]`, `Ikl.xy[a]`,
    /// `theta.xy`, `mff[a][b]`, `Kff[a][b]`), in that order; all three axes.
    pub fn named(&self) -> Vec<(String, f64)> {
        const AXES: [&str; 3] = ["x", "y", "z"];
        let nf = self.m_ff.nrows();
        let mut v = vec![("mass".to_string(), self.mass)];
        for k in 0..3 {
            v.push((format!("St0[{k}]"), self.s_t0[k]));
        }
        for k in 0..3 {
            for a in 0..nf {
                v.push((format!("Sbar[{k}][{a}]"), self.s_bar[(k, a)]));
            }
        }
        for (k, ak) in AXES.iter().enumerate() {
            for (l, al) in AXES.iter().enumerate() {
                let key = format!("{ak}{al}");
                for a in 0..nf {
                    for b in 0..nf {
                        v.push((format!("Skl.{key}[{a}][{b}]"), self.s_kl[k][l][(a, b)]));
                    }
                    v.push((format!("Ikl.{key}[{a}]"), self.i_kl[k][l][(a, 0)]));
                }
                v.push((format!("theta.{key}"), self.theta[(k, l)]));
            }
        }
        for (name, m) in [("mff", &self.m_ff), ("Kff", &self.k_ff)] {
            for a in 0..nf {
                for b in 0..nf {
                    v.push((format!("{name}[{a}][{b}]"), m[(a, b)]));
                }
            }
        }
        v
    }

    /// The first number (in [`Dense::named`] order) that is not finite.
    pub fn first_not_finite(&self) -> Option<(String, f64)> {
        self.named().into_iter().find(|(_, x)| !x.is_finite())
    }

    pub fn from_reference(r: &rf::RefInvariants) -> Self {
        let nf = r.m_ff.nrows();
        Dense {
            mass: r.mass,
            s_t0: [r.s_t0[0], r.s_t0[1], r.s_t0[2]],
            s_bar: DMatrix::from_fn(3, nf, |i, j| r.s_bar[(i, j)]),
            s_kl: r.s_kl.clone(),
            i_kl: std::array::from_fn(|k| {
                std::array::from_fn(|l| DMatrix::from_column_slice(nf, 1, r.i_kl[k][l].as_slice()))
            }),
            theta: r.theta,
            m_ff: r.m_ff.clone(),
            k_ff: r.k_ff.clone(),
        }
    }
}

/// A body of `N` elements evaluated through the kernel programs on tapes,
/// assembled like the runtime does (gather, evaluate, scatter-add).
pub struct TapeBody<'a> {
    pub set: &'a KernelSet,
    pub spec: BodySpec,
    pub params: Params,
    pub l: f64,
    pub coef: Vec<f64>,
    maps: Vec<Vec<Option<usize>>>,
    pub n: usize,
}

/// Assembled outputs of the `mass` kernel.
#[derive(Clone, Debug)]
pub struct MassAsm {
    pub s_t: [f64; 3],
    pub m_ff: DMatrix<f64>,
    /// `∂f_f/∂[ā, α]` (`n_f × 6`).
    pub m_f_frame: DMatrix<f64>,
    /// `∂[f_r; f_θ]/∂q̈_f` (`6 × n_f`).
    pub m_ref_f: DMatrix<f64>,
    /// `∂[f_r; f_θ]/∂[ā, α]` (`6 × 6`).
    pub m_ref_frame: DMatrix<f64>,
}

/// Assembled outputs of the `residual` / `tangent` kernels.
#[derive(Clone, Debug)]
pub struct ForcesAsm {
    pub f_r: [f64; 3],
    pub f_th: [f64; 3],
    pub f_f: Vec<f64>,
    pub k_ff: DMatrix<f64>,
    /// `n_f × 9`.
    pub d_f_frame: DMatrix<f64>,
    /// `6 × n_f`.
    pub k_ref_f: DMatrix<f64>,
    /// `6 × 9`.
    pub d_ref_frame: DMatrix<f64>,
}

impl<'a> TapeBody<'a> {
    pub fn new(set: &'a KernelSet, elements: usize, reference: Reference, params: Params) -> Self {
        let spec = BodySpec::new(set.model().shape.clone(), elements, reference)
            .unwrap()
            .with_formalism(set.model().options.formalism);
        let l = params.elem_length(elements);
        let coef = coefficients(set, &params, l);
        let maps = (0..elements).map(|e| spec.element_map(e)).collect();
        TapeBody {
            set,
            n: set.n(),
            spec,
            params,
            l,
            coef,
            maps,
        }
    }

    pub fn nf(&self) -> usize {
        self.spec.nf()
    }

    pub fn elements(&self) -> usize {
        self.spec.elements
    }

    pub fn x0(&self, e: usize) -> f64 {
        e as f64 * self.l
    }

    pub fn map(&self, e: usize) -> &[Option<usize>] {
        &self.maps[e]
    }

    pub fn gather(&self, e: usize, v: &[f64]) -> Vec<f64> {
        self.maps[e]
            .iter()
            .map(|m| m.map_or(0.0, |i| v[i]))
            .collect()
    }

    fn scatter(&self, e: usize, local: &[f64], global: &mut [f64]) {
        for (a, m) in self.maps[e].iter().enumerate() {
            if let Some(i) = m {
                global[*i] += local[a];
            }
        }
    }

    fn scatter_mat(&self, e: usize, local: &[f64], global: &mut DMatrix<f64>) {
        let n = self.n;
        for (a, ma) in self.maps[e].iter().enumerate() {
            for (b, mb) in self.maps[e].iter().enumerate() {
                if let (Some(i), Some(j)) = (ma, mb) {
                    global[(*i, *j)] += local[a * n + b];
                }
            }
        }
    }

    /// `Σ_e ½ q_eᵀ K_e q_e + U_nl,e`.
    pub fn energy(&self, q_f: &[f64]) -> f64 {
        let mut run = Run::new(&self.set.energy);
        let mut total = 0.0;
        for e in 0..self.elements() {
            let q = self.gather(e, q_f);
            run.run(
                &Inputs {
                    coef: &self.coef,
                    q: &q,
                    ..Inputs::default()
                },
                |arr, _, v| {
                    assert_eq!(arr, OutArr::Energy);
                    total += v;
                },
            );
        }
        total
    }

    /// Assembled `residual_elastic`.
    pub fn residual_elastic(
        &self,
        q_f: &[f64],
        qd_f: &[f64],
        qdd_f: &[f64],
        frame: &[f64; 9],
    ) -> Vec<f64> {
        let mut run = Run::new(&self.set.residual_elastic);
        let mut f = vec![0.0; self.nf()];
        for e in 0..self.elements() {
            let (q, qd, qdd) = (
                self.gather(e, q_f),
                self.gather(e, qd_f),
                self.gather(e, qdd_f),
            );
            let mut fe = vec![0.0; self.n];
            run.run(
                &Inputs {
                    coef: &self.coef,
                    x0: self.x0(e),
                    frame,
                    q: &q,
                    qd: &qd,
                    qdd: &qdd,
                    ..Inputs::default()
                },
                |arr, i, v| {
                    assert_eq!(arr, OutArr::Fe);
                    fe[i] = v;
                },
            );
            self.scatter(e, &fe, &mut f);
        }
        f
    }

    /// Assembled `tangent_elastic`: `(f_f, K)`.
    #[allow(clippy::too_many_arguments)]
    pub fn tangent_elastic(
        &self,
        q_f: &[f64],
        qd_f: &[f64],
        qdd_f: &[f64],
        frame: &[f64; 9],
        bp: f64,
        gp: f64,
    ) -> (Vec<f64>, DMatrix<f64>) {
        let mut run = Run::new(&self.set.tangent_elastic);
        let nf = self.nf();
        let mut f = vec![0.0; nf];
        let mut k = DMatrix::zeros(nf, nf);
        for e in 0..self.elements() {
            let (q, qd, qdd) = (
                self.gather(e, q_f),
                self.gather(e, qd_f),
                self.gather(e, qdd_f),
            );
            let mut fe = vec![0.0; self.n];
            let mut ke = vec![0.0; self.n * self.n];
            run.run(
                &Inputs {
                    coef: &self.coef,
                    x0: self.x0(e),
                    frame,
                    bp,
                    gp,
                    q: &q,
                    qd: &qd,
                    qdd: &qdd,
                    ..Inputs::default()
                },
                |arr, i, v| match arr {
                    OutArr::Fe => fe[i] = v,
                    OutArr::Kee => ke[i] = v,
                    other => panic!("{other:?} in tangent_elastic"),
                },
            );
            self.scatter(e, &fe, &mut f);
            self.scatter_mat(e, &ke, &mut k);
        }
        (f, k)
    }

    /// Assembled `mass`.
    pub fn mass(&self, q_f: &[f64]) -> MassAsm {
        let mut run = Run::new(&self.set.mass);
        let (n, nf) = (self.n, self.nf());
        let mut out = MassAsm {
            s_t: [0.0; 3],
            m_ff: DMatrix::zeros(nf, nf),
            m_f_frame: DMatrix::zeros(nf, 6),
            m_ref_f: DMatrix::zeros(6, nf),
            m_ref_frame: DMatrix::zeros(6, 6),
        };
        for e in 0..self.elements() {
            let q = self.gather(e, q_f);
            let mut mee = vec![0.0; n * n];
            let mut mef = vec![0.0; n * 6];
            let mut mre = vec![0.0; 6 * n];
            run.run(
                &Inputs {
                    coef: &self.coef,
                    x0: self.x0(e),
                    q: &q,
                    ..Inputs::default()
                },
                |arr, i, v| match arr {
                    OutArr::St => out.s_t[i] += v,
                    OutArr::Mee => mee[i] = v,
                    OutArr::MeFrame => mef[i] = v,
                    OutArr::MrefE => mre[i] = v,
                    OutArr::MrefFrame => out.m_ref_frame[(i / 6, i % 6)] += v,
                    other => panic!("{other:?} in mass"),
                },
            );
            self.scatter_mat(e, &mee, &mut out.m_ff);
            for (a, m) in self.maps[e].iter().enumerate() {
                if let Some(i) = m {
                    for k in 0..6 {
                        out.m_f_frame[(*i, k)] += mef[a * 6 + k];
                        out.m_ref_f[(k, *i)] += mre[k * n + a];
                    }
                }
            }
        }
        out
    }

    /// Assembled `tangent` (free frame): residual and all derivatives.
    #[allow(clippy::too_many_arguments)]
    pub fn tangent(
        &self,
        q_f: &[f64],
        qd_f: &[f64],
        qdd_f: &[f64],
        frame: &[f64; 9],
        bp: f64,
        gp: f64,
    ) -> ForcesAsm {
        self.forces(
            self.set.tangent.as_ref().unwrap(),
            q_f,
            qd_f,
            qdd_f,
            frame,
            bp,
            gp,
        )
    }

    /// Assembled `residual` (free frame).
    pub fn residual(
        &self,
        q_f: &[f64],
        qd_f: &[f64],
        qdd_f: &[f64],
        frame: &[f64; 9],
    ) -> ForcesAsm {
        self.forces(
            self.set.residual.as_ref().unwrap(),
            q_f,
            qd_f,
            qdd_f,
            frame,
            0.0,
            0.0,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn forces(
        &self,
        prog: &Program,
        q_f: &[f64],
        qd_f: &[f64],
        qdd_f: &[f64],
        frame: &[f64; 9],
        bp: f64,
        gp: f64,
    ) -> ForcesAsm {
        let mut run = Run::new(prog);
        let (n, nf) = (self.n, self.nf());
        let mut out = ForcesAsm {
            f_r: [0.0; 3],
            f_th: [0.0; 3],
            f_f: vec![0.0; nf],
            k_ff: DMatrix::zeros(nf, nf),
            d_f_frame: DMatrix::zeros(nf, 9),
            k_ref_f: DMatrix::zeros(6, nf),
            d_ref_frame: DMatrix::zeros(6, 9),
        };
        for e in 0..self.elements() {
            let (q, qd, qdd) = (
                self.gather(e, q_f),
                self.gather(e, qd_f),
                self.gather(e, qdd_f),
            );
            let mut fe = vec![0.0; n];
            let mut kee = vec![0.0; n * n];
            let mut def = vec![0.0; n * 9];
            let mut kre = vec![0.0; 6 * n];
            run.run(
                &Inputs {
                    coef: &self.coef,
                    x0: self.x0(e),
                    frame,
                    bp,
                    gp,
                    q: &q,
                    qd: &qd,
                    qdd: &qdd,
                    ..Inputs::default()
                },
                |arr, i, v| match arr {
                    OutArr::Fr => out.f_r[i] += v,
                    OutArr::Fth => out.f_th[i] += v,
                    OutArr::Fe => fe[i] = v,
                    OutArr::Kee => kee[i] = v,
                    OutArr::DeFrame => def[i] = v,
                    OutArr::KrefE => kre[i] = v,
                    OutArr::DrefFrame => out.d_ref_frame[(i / 9, i % 9)] += v,
                    other => panic!("{other:?} in residual/tangent"),
                },
            );
            self.scatter(e, &fe, &mut out.f_f);
            self.scatter_mat(e, &kee, &mut out.k_ff);
            for (a, m) in self.maps[e].iter().enumerate() {
                if let Some(i) = m {
                    for k in 0..9 {
                        out.d_f_frame[(*i, k)] += def[a * 9 + k];
                    }
                    for r in 0..6 {
                        out.k_ref_f[(r, *i)] += kre[r * n + a];
                    }
                }
            }
        }
        out
    }

    /// Body invariants assembled from the `element_invariants` program.
    pub fn invariants(&self) -> Dense {
        let n = self.n;
        let (off, len) = ffr_codegen::eom::invariant_layout(n);
        let mut run = Run::new(&self.set.element_invariants);
        let mut d = Dense::zeros(self.nf());
        for e in 0..self.elements() {
            let mut buf = vec![0.0; len];
            run.run(
                &Inputs {
                    coef: &self.coef,
                    x0: self.x0(e),
                    ..Inputs::default()
                },
                |arr, i, v| {
                    assert_eq!(arr, OutArr::Inv);
                    buf[i] = v;
                },
            );
            d.mass += buf[off[0]];
            for k in 0..3 {
                d.s_t0[k] += buf[off[1] + k];
                for l in 0..3 {
                    d.theta[(k, l)] += buf[off[5] + k * 3 + l];
                }
            }
            let map = &self.maps[e];
            for (a, ma) in map.iter().enumerate() {
                let Some(i) = *ma else { continue };
                for k in 0..3 {
                    d.s_bar[(k, i)] += buf[off[2] + k * n + a];
                    for l in 0..3 {
                        d.i_kl[k][l][(i, 0)] += buf[off[4] + (k * 3 + l) * n + a];
                    }
                }
                for (b, mb) in map.iter().enumerate() {
                    let Some(j) = *mb else { continue };
                    for k in 0..3 {
                        for l in 0..3 {
                            d.s_kl[k][l][(i, j)] += buf[off[3] + ((k * 3 + l) * n + a) * n + b];
                        }
                    }
                    d.m_ff[(i, j)] += buf[off[6] + a * n + b];
                    d.k_ff[(i, j)] += buf[off[7] + a * n + b];
                }
            }
        }
        d
    }
}

/// `‖a − b‖_F ≤ tol·max(‖b‖_F, scale)`, with a message naming `what`.
pub fn check(what: &str, a: &DMatrix<f64>, b: &DMatrix<f64>, scale: f64, tol: f64) {
    assert_eq!(a.shape(), b.shape(), "{what}: shapes differ");
    let err = (a - b).norm();
    let reference = b.norm().max(scale);
    assert!(
        err <= tol * reference,
        "{what}: relative error {:e} > {tol:e} (|a − b| = {err:e}, |b| = {:e}, scale {scale:e})",
        err / reference,
        b.norm()
    );
}

pub fn col(v: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(v.len(), 1, v)
}

pub fn scalar(x: f64) -> DMatrix<f64> {
    DMatrix::from_element(1, 1, x)
}

/// The CPU time of the current thread (Linux), so that a busy machine does
/// not count against a time limit; elsewhere the wall time since the first
/// call.
pub fn thread_cpu_time() -> std::time::Duration {
    use std::time::{Duration, Instant};
    #[cfg(target_os = "linux")]
    {
        #[repr(C)]
        struct Timespec {
            tv_sec: i64,
            tv_nsec: i64,
        }
        extern "C" {
            fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
        }
        const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
        let mut ts = Timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable timespec (64-bit Linux layout).
        if cfg!(target_pointer_width = "64")
            && unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) } == 0
        {
            return Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32);
        }
    }
    static START: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    START.get_or_init(Instant::now).elapsed()
}
