//! The equations of motion of one element (or one modal body) in body-frame
//! form, as exact polynomials over the kernel inputs, and the derivatives the
//! Newton matrix needs (theory: "Mass matrix", "Quadratic velocity vector",
//! "Geometric stiffening").
//!
//! With the frame motion in body axes, `ā = Aᵀ(R̈ − g)`, `α = ω̄̇`, `ω = ω̄`,
//! an element with coordinates `q` contributes
//!
//! - `f_r = m ā − S̃_t α + S̄ q̈ + ω̃² S_t + 2 ω̃ S̄ q̇`
//! - `f_θ = S̃_t ā + Ī_θθ α + Ī_θf q̈ + ω̃ Ī_θθ ω + 2 (tr P · ω − Pᵀ ω)`
//! - `f_e = S̄ᵀ ā + Ī_θfᵀ α + m_ff q̈ + h_e + K q + ∂U_nl/∂q`,
//!   `h_e = Σ_kl [ (ω̃²)_kl (Ī_lk + S̄_kl q) + 2 ω̃_kl S̄_kl q̇ ]`
//!
//! with `S_t = S_t0 + S̄ q`, `U_kl = Θ_kl + (Ī_kl + Ī_lk) q + qᵀ S̄_kl q`,
//! `Ī_θθ = tr(U) I − U`, `Ī_θf` rows `Ī_ab − Ī_ba + qᵀ(S̄_ab − S̄_ba)` for
//! `(a, b)` cyclic, `P_kl = Ī_kl q̇ + qᵀ S̄_kl q̇`. The runtime forms
//! `r_R = A f_r`, `r_θ = Ḡᵀ f_θ`, `r_f = f_f − Q` after assembling the
//! elements; gravity enters through `ā`.

// Tensor code over coordinate and axis indices (`k`, `l`, `a`, `b` as in
// the theory): index loops read closer to the formulas than iterators.
#![allow(clippy::needless_range_loop)]

use crate::body::{element_invariants_with, rows3, ExactInvariants};
use crate::dag::{linear, Dag};
use crate::energy::{element_energy_with, ElementEnergy};
use crate::error::Error;
use crate::poly::{rat, Param, Poly, Sym};
use crate::shape::Shape;
use ffr_spec::{KernelOptions, SceneDim, SectionModel};

/// What a set of element kernels is generated for: a shape and the
/// options ([`KernelOptions`]; planar kernels have frame motion in the x–y
/// plane, `ā_z = α_x = α_y = ω_x = ω_y = 0`; without a free frame only the
/// elastic equations are generated; at rest, no `ā` terms).
#[derive(Clone, Debug)]
pub struct KernelModel {
    /// The element shape.
    pub shape: Shape,
    /// The options (scene `None`: the shape's dimension).
    pub options: KernelOptions,
    /// Uniform section (in the body parameters) or varying (in per-element
    /// moments of the section properties); default uniform.
    pub sections: SectionModel,
}

impl KernelModel {
    /// `shape` with `options`, uniform section.
    pub fn new(shape: Shape, options: KernelOptions) -> Self {
        Self {
            shape,
            options,
            sections: SectionModel::Uniform,
        }
    }

    /// The same model with this section model.
    pub fn with_sections(mut self, sections: SectionModel) -> Self {
        self.sections = sections;
        self
    }

    /// The scene, resolved against the shape's dimension.
    pub fn scene(&self) -> SceneDim {
        self.options.scene_or(self.shape.dimension)
    }

    /// 2 (planar scene) or 3.
    pub fn scene_dim(&self) -> usize {
        self.scene().dim()
    }

    /// The options with the scene resolved (what `KernelInfo` reports).
    pub fn resolved_options(&self) -> KernelOptions {
        self.options.resolved(self.shape.dimension)
    }
}

/// An output array of a kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum OutArr {
    /// `f_r` (3).
    Fr,
    /// `f_θ` (3).
    Fth,
    /// `f_e` (n).
    Fe,
    /// `β' ∂f_e/∂q̈ + γ' ∂f_e/∂q̇ + ∂f_e/∂q` (n × n, row-major).
    Kee,
    /// `∂f_e/∂(ā, α, ω)` (n × 9).
    DeFrame,
    /// `β' ∂f_ref/∂q̈ + γ' ∂f_ref/∂q̇ + ∂f_ref/∂q`, rows `f_r, f_θ` (6 × n).
    KrefE,
    /// `∂f_ref/∂(ā, α, ω)` (6 × 9).
    DrefFrame,
    /// `S_t` (3).
    St,
    /// `∂f_e/∂q̈ = m_ff` (n × n).
    Mee,
    /// `∂f_e/∂(ā, α)` (n × 6).
    MeFrame,
    /// `∂f_ref/∂q̈` (6 × n).
    MrefE,
    /// `∂f_ref/∂(ā, α)` (6 × 6).
    MrefFrame,
    /// Elastic energy `½ qᵀ K q + U_nl` (1).
    Energy,
    /// Element invariants, flat (see [`invariant_layout`]).
    Inv,
    /// `S(ξ)` on the centre line (3 × n).
    S,
    /// Section rotation `ψ(ξ) = ½ ∇ × u` on the centre line (3 × n).
    Psi,
    /// Parameter-only coefficients (the coefficient program).
    Coef,
    /// The element scalars `z` of the stiffening energy (at most n).
    Z,
    /// `∂U_nl/∂z` (at most n).
    Gz,
    /// `∂²U_nl/∂z²` (row-major with stride n).
    Hz,
}

/// One output: an array entry and its polynomial.
pub type Outputs = Vec<((OutArr, u32), Poly)>;

pub use ffr_spec::invariant_layout;

/// All kernel polynomials of a model, sharing one DAG of intermediates.
#[derive(Clone, Debug)]
pub struct KernelPolys {
    /// The model.
    pub model: KernelModel,
    /// Element coordinates `n`.
    pub n: usize,
    /// Shared intermediates.
    pub dag: Dag,
    /// The exact element invariants (in the parameters, `l`, `x₀`).
    pub invariants: ExactInvariants,
    /// The element's stiffening energy, if any.
    pub energy_form: Option<ElementEnergy>,
    /// `mass(q)`: `S_t` and the acceleration-linear blocks.
    pub mass: Outputs,
    /// `residual(q, q̇, q̈, frame)` with reference rows (free frame only).
    pub residual: Option<Outputs>,
    /// `tangent(…)`: residual and derivatives (free frame only).
    pub tangent: Option<Outputs>,
    /// `residual_elastic`: `f_e` only.
    pub residual_elastic: Outputs,
    /// `tangent_elastic`: `f_e` and `K_ee`.
    pub tangent_elastic: Outputs,
    /// `force_elastic`: `K_e q + ∇U_nl` alone (stiffening models only).
    pub force_elastic: Option<Outputs>,
    /// `elastic_scalars`: `z = S q`, the energy's element scalars
    /// (stiffening models only).
    pub elastic_scalars: Option<Outputs>,
    /// `scalar_force`: `∂U_nl/∂z` with the scalars as inputs (`Sym::Q(j)`
    /// stands for `z_j`).
    pub scalar_force: Option<Outputs>,
    /// `scalar_tangent`: `∂U_nl/∂z` and `∂²U_nl/∂z²`.
    pub scalar_tangent: Option<Outputs>,
    /// `energy(q)`.
    pub energy: Outputs,
    /// `element_invariants(x₀)`.
    pub element_invariants: Outputs,
    /// `point_shape(ξ)`.
    pub point_shape: Outputs,
}

fn frame(k: usize) -> Poly {
    Poly::var(Sym::Frame(k as u8))
}

fn q(a: usize) -> Sym {
    Sym::Q(a as u32)
}
fn qd(a: usize) -> Sym {
    Sym::Qd(a as u32)
}
fn qdd(a: usize) -> Sym {
    Sym::Qdd(a as u32)
}

fn cross(a: &[Poly; 3], b: &[Poly; 3]) -> [Poly; 3] {
    [
        a[1].mul(&b[2]).sub(&a[2].mul(&b[1])),
        a[2].mul(&b[0]).sub(&a[0].mul(&b[2])),
        a[0].mul(&b[1]).sub(&a[1].mul(&b[0])),
    ]
}

fn mat_vec(m: &[[Poly; 3]; 3], v: &[Poly; 3]) -> [Poly; 3] {
    std::array::from_fn(|i| {
        let mut s = Poly::zero();
        for j in 0..3 {
            s.add_assign(&m[i][j].mul(&v[j]));
        }
        s
    })
}

/// `qᵀ M x` for a polynomial matrix and two coordinate families.
fn bilinear(
    m: &crate::body::PolyMatrix,
    x: impl Fn(usize) -> Sym,
    y: impl Fn(usize) -> Sym,
) -> Poly {
    let mut s = Poly::zero();
    for a in 0..m.rows {
        for b in 0..m.cols {
            let c = m.get(a, b);
            if !c.is_zero() {
                s.add_assign(&c.mul(&Poly::var(x(a))).mul(&Poly::var(y(b))));
            }
        }
    }
    s
}

impl KernelModel {
    /// Build every kernel's polynomials.
    pub fn polys(&self) -> Result<KernelPolys, Error> {
        let inv = element_invariants_with(&self.shape, self.options.formalism, self.sections)?;
        let energy_form = element_energy_with(&self.shape, self.options.stiffening, self.sections)?;
        let n = inv.nf;
        let mut dag = Dag::new();
        let inputs = FrameInputs {
            planar: self.scene() == SceneDim::Planar,
            zero_acceleration: self.options.frame.zero_frame_acceleration(),
            free: self.options.frame.is_free(),
        };
        let Equations {
            mass,
            residual,
            tangent,
            residual_elastic,
            tangent_elastic,
            force_elastic,
            energy,
        } = equations(&inv, energy_form.as_ref(), inputs, &mut dag);
        let push = |out: &mut Outputs, arr: OutArr, idx: usize, p: Poly| {
            if !p.is_zero() {
                out.push(((arr, idx as u32), p));
            }
        };

        // The stiffening energy in its element scalars, with the scalars as
        // the inputs (`Sym::Q(j)` stands for `z_j`): a modal body maps
        // `η` to each element's scalars once (`z = S Φ_e η`) and needs only
        // the energy's derivatives in them.
        let (elastic_scalars, scalar_force, scalar_tangent) = match &energy_form {
            Some(ef) if ef.scalars.len() <= n => {
                let nz = ef.scalars.len();
                let mut map = Outputs::new();
                for (j, form) in ef.scalars.iter().enumerate() {
                    push(&mut map, OutArr::Z, j, linear(form, q));
                }
                let mut zs: Vec<Sym> = (0..nz).map(q).collect();
                let rename = |p: &Poly, zs: &[Sym]| {
                    p.rename(|s| match s {
                        Sym::Z(j) => Some(zs[j as usize]),
                        other => Some(other),
                    })
                };
                for (name, def) in &ef.derived {
                    let d = rename(def, &zs);
                    let b = dag.bind_always(&format!("{name}_of_z"), d);
                    zs.push(match b.terms().next().map(|(m, _)| m.factors()) {
                        Some([(s, 1)]) => *s,
                        _ => unreachable!("bind_always returns a symbol"),
                    });
                }
                let e = rename(&ef.energy, &zs);
                let e = dag.bind_always("u_nl_of_z", e);
                let grad: Vec<Poly> = (0..nz).map(|j| dag.derivative(&e, q(j))).collect();
                let mut force = Outputs::new();
                for (j, g) in grad.iter().enumerate() {
                    push(&mut force, OutArr::Gz, j, g.clone());
                }
                let mut tan = force.clone();
                for a in 0..nz {
                    for b in a..nz {
                        let h = dag.derivative(&grad[a], q(b));
                        let h = dag.bind(&format!("h_z_{a}_{b}"), h);
                        push(&mut tan, OutArr::Hz, a * n + b, h.clone());
                        if a != b {
                            push(&mut tan, OutArr::Hz, b * n + a, h);
                        }
                    }
                }
                (Some(map), Some(force), Some(tan))
            }
            _ => (None, None, None),
        };

        let element_invariants = invariant_outputs(&inv);
        let point_shape = point_shape_outputs(&self.shape);
        Ok(KernelPolys {
            model: self.clone(),
            n,
            dag,
            invariants: inv,
            energy_form,
            mass,
            residual,
            tangent,
            residual_elastic,
            tangent_elastic,
            force_elastic,
            elastic_scalars,
            scalar_force,
            scalar_tangent,
            energy,
            element_invariants,
            point_shape,
        })
    }
}

/// Which frame inputs the equations have and which rows they keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameInputs {
    /// Planar scene: frame motion in the x–y plane (`ā_z = α_x = α_y =
    /// ω_x = ω_y = 0`).
    pub planar: bool,
    /// `ā ≡ 0` (frame origin fixed, no gravity).
    pub zero_acceleration: bool,
    /// Whether the reference rows (`residual`, `tangent`) are formed.
    pub free: bool,
}

/// The equations of motion of one set of invariants (see the module
/// documentation) as kernel outputs: what [`equations`] returns.
#[derive(Clone, Debug)]
pub struct Equations {
    /// `mass(q)`: `S_t` and the acceleration-linear blocks.
    pub mass: Outputs,
    /// `residual(q, q̇, q̈, frame)` with the reference rows (free frame only).
    pub residual: Option<Outputs>,
    /// `tangent(…)`: the residual and its derivatives (free frame only).
    pub tangent: Option<Outputs>,
    /// `f_e` only.
    pub residual_elastic: Outputs,
    /// `f_e` and `K_ee`.
    pub tangent_elastic: Outputs,
    /// `K q + ∇U_nl` alone (with a stiffening energy only).
    pub force_elastic: Option<Outputs>,
    /// Elastic energy `½ qᵀ K q + U_nl`.
    pub energy: Outputs,
}

/// The equations of motion in body axes of the invariants `inv` over its
/// `n = inv.nf` coordinates (`Sym::Q`, `Sym::Qd`, `Sym::Qdd`) and the frame
/// inputs `inputs`, with the elastic force `K q` (`inv.k_ff`; a zero matrix
/// leaves it out) and, if given, the gradient of the stiffening energy
/// `energy_form` (its element scalars bound in `dag`). The invariants may be
/// polynomials in the parameters (an element's) or numbers (a modal body's,
/// `crate::modal::exact_invariants`): one path for both.
pub fn equations(
    inv: &ExactInvariants,
    energy_form: Option<&ElementEnergy>,
    inputs: FrameInputs,
    dag: &mut Dag,
) -> Equations {
    let n = inv.nf;
    // Frame inputs (zero where a planar scene has none).
    let planar = inputs.planar;
    let zero_a = inputs.zero_acceleration;
    let live = |k: usize| !((planar && matches!(k, 2 | 3 | 4 | 6 | 7)) || (zero_a && k < 3));
    let f = |k: usize| if live(k) { frame(k) } else { Poly::zero() };
    let a_bar = [f(0), f(1), f(2)];
    let alpha = [f(3), f(4), f(5)];
    let w = [f(6), f(7), f(8)];
    // ω̃ and ω̃² = ω ωᵀ − |ω|² I.
    let zero = Poly::zero();
    let w1: [[Poly; 3]; 3] = [
        [zero.clone(), w[2].scale(&rat(-1, 1)), w[1].clone()],
        [w[2].clone(), zero.clone(), w[0].scale(&rat(-1, 1))],
        [w[1].scale(&rat(-1, 1)), w[0].clone(), zero.clone()],
    ];
    let wsq = w[0].mul(&w[0]).add(&w[1].mul(&w[1])).add(&w[2].mul(&w[2]));
    let w2: [[Poly; 3]; 3] = std::array::from_fn(|k| {
        std::array::from_fn(|l| {
            let mut v = w[k].mul(&w[l]);
            if k == l {
                v = v.sub(&wsq);
            }
            v
        })
    });

    // Intermediates of q.
    let s_t: [Poly; 3] = std::array::from_fn(|k| {
        let p = inv.s_t0[k].add(&linear(
            &(0..n)
                .map(|a| inv.s_bar.get(k, a).clone())
                .collect::<Vec<_>>(),
            q,
        ));
        dag.bind(&format!("s_t_{}", AXES[k]), p)
    });
    let mut u: [[Poly; 3]; 3] = Default::default();
    for k in 0..3 {
        for l in k..3 {
            let lin: Vec<Poly> = (0..n)
                .map(|a| inv.i_kl[k][l][a].add(&inv.i_kl[l][k][a]))
                .collect();
            let p = inv.theta[k][l]
                .add(&linear(&lin, q))
                .add(&bilinear(&inv.s_kl[k][l], q, q));
            let z = dag.bind(&format!("u_{}{}", AXES[k], AXES[l]), p);
            u[k][l] = z.clone();
            u[l][k] = z;
        }
    }
    let tr = u[0][0].add(&u[1][1]).add(&u[2][2]);
    let i_tt: [[Poly; 3]; 3] = std::array::from_fn(|k| {
        std::array::from_fn(|l| {
            let m = u[k][l].scale(&rat(-1, 1));
            if k == l {
                m.add(&tr)
            } else {
                m
            }
        })
    });
    // Ī_θf rows r = 0, 1, 2 from (a, b) = (y, z), (z, x), (x, y).
    let cyc = [(1, 2), (2, 0), (0, 1)];
    let i_tf: Vec<[Poly; 3]> = (0..n)
        .map(|a| {
            std::array::from_fn(|r| {
                let (ka, kb) = cyc[r];
                let mut p = inv.i_kl[ka][kb][a].sub(&inv.i_kl[kb][ka][a]);
                for c in 0..n {
                    let s = inv.s_kl[ka][kb].get(c, a).sub(inv.s_kl[kb][ka].get(c, a));
                    if !s.is_zero() {
                        p.add_assign(&s.mul(&Poly::var(q(c))));
                    }
                }
                dag.bind(&format!("i_tf_{}_{a}", AXES[r]), p)
            })
        })
        .collect();
    // S̄ q̇, S̄ q̈ and P_kl = Ī_kl q̇ + qᵀ S̄_kl q̇.
    let row = |k: usize| {
        (0..n)
            .map(|a| inv.s_bar.get(k, a).clone())
            .collect::<Vec<_>>()
    };
    let sbar_qd: [Poly; 3] = std::array::from_fn(|k| linear(&row(k), qd));
    let sbar_qdd: [Poly; 3] = std::array::from_fn(|k| linear(&row(k), qdd));
    let p_kl: [[Poly; 3]; 3] = std::array::from_fn(|k| {
        std::array::from_fn(|l| {
            let p = linear(&inv.i_kl[k][l], qd).add(&bilinear(&inv.s_kl[k][l], q, qd));
            dag.bind(&format!("p_{}{}", AXES[k], AXES[l]), p)
        })
    });

    // f_r = m ā − S_t × α + S̄ q̈ + ω̃² S_t + 2 ω̃ S̄ q̇.
    let st_x_alpha = cross(&s_t, &alpha);
    let w2_st = mat_vec(&w2, &s_t);
    let w1_sqd = mat_vec(&w1, &sbar_qd);
    let f_r: [Poly; 3] = std::array::from_fn(|k| {
        inv.mass
            .mul(&a_bar[k])
            .sub(&st_x_alpha[k])
            .add(&sbar_qdd[k])
            .add(&w2_st[k])
            .add(&w1_sqd[k].scale(&rat(2, 1)))
    });
    // f_θ = S_t × ā + Ī_θθ α + Ī_θf q̈ + ω × (Ī_θθ ω) + 2 (tr P ω − Pᵀ ω).
    let st_x_a = cross(&s_t, &a_bar);
    let i_alpha = mat_vec(&i_tt, &alpha);
    let i_w = mat_vec(&i_tt, &w);
    let gyro = cross(&w, &i_w);
    let tr_p = p_kl[0][0].add(&p_kl[1][1]).add(&p_kl[2][2]);
    let p_t: [[Poly; 3]; 3] = std::array::from_fn(|k| std::array::from_fn(|l| p_kl[l][k].clone()));
    let pt_w = mat_vec(&p_t, &w);
    let f_th: [Poly; 3] = std::array::from_fn(|k| {
        let mut itf_qdd = Poly::zero();
        for (a, row) in i_tf.iter().enumerate() {
            itf_qdd.add_assign(&row[k].mul(&Poly::var(qdd(a))));
        }
        st_x_a[k]
            .add(&i_alpha[k])
            .add(&itf_qdd)
            .add(&gyro[k])
            .add(&w[k].mul(&tr_p).sub(&pt_w[k]).scale(&rat(2, 1)))
    });
    // f_e.
    let energy_grad = energy_form.map(|ef| {
        // Element scalars, then derived scalars, then the energy: the
        // chain rule runs through them (Sym::Z ids of the form → DAG).
        let mut zs: Vec<Poly> = ef
            .scalars
            .iter()
            .zip(&ef.names)
            .map(|(form, name)| dag.bind_always(name, linear(form, q)))
            .collect();
        // Energy-local Z(j) → the DAG's symbols, all at once.
        let subst = |p: &Poly, zs: &[Poly]| {
            let ids: Vec<Sym> = zs
                .iter()
                .map(|z| match z.terms().next().map(|(m, _)| m.factors()) {
                    Some([(s, 1)]) => *s,
                    _ => unreachable!("bind_always returns a symbol"),
                })
                .collect();
            p.rename(|s| match s {
                Sym::Z(j) => Some(ids[j as usize]),
                other => Some(other),
            })
        };
        for (name, def) in &ef.derived {
            let d = subst(def, &zs);
            zs.push(dag.bind_always(name, d));
        }
        let e = subst(&ef.energy, &zs);
        dag.bind_always("u_nl", e)
    });
    let mut f_e = Vec::with_capacity(n);
    let mut elastic = Vec::with_capacity(n);
    let mut inertial = Vec::with_capacity(n);
    for a in 0..n {
        let mut p = Poly::zero();
        for k in 0..3 {
            p.add_assign(&inv.s_bar.get(k, a).mul(&a_bar[k]));
            p.add_assign(&i_tf[a][k].mul(&alpha[k]));
        }
        for b in 0..n {
            p.add_assign(&inv.m_ff.get(a, b).mul(&Poly::var(qdd(b))));
        }
        for k in 0..3 {
            for l in 0..3 {
                if !w2[k][l].is_zero() {
                    let mut v = inv.i_kl[l][k][a].clone();
                    for b in 0..n {
                        v.add_assign(&inv.s_kl[k][l].get(a, b).mul(&Poly::var(q(b))));
                    }
                    p.add_assign(&w2[k][l].mul(&v));
                }
                if !w1[k][l].is_zero() {
                    let mut v = Poly::zero();
                    for b in 0..n {
                        v.add_assign(&inv.s_kl[k][l].get(a, b).mul(&Poly::var(qd(b))));
                    }
                    p.add_assign(&w1[k][l].mul(&v).scale(&rat(2, 1)));
                }
            }
        }
        let mut el = Poly::zero();
        for b in 0..n {
            el.add_assign(&inv.k_ff.get(a, b).mul(&Poly::var(q(b))));
        }
        if let Some(e) = &energy_grad {
            el.add_assign(&dag.derivative(e, q(a)));
        }
        inertial.push(p.clone());
        p.add_assign(&el);
        f_e.push(p);
        elastic.push(el);
    }

    // Elastic energy ½ qᵀ K q + U_nl.
    let mut energy_poly = bilinear(&inv.k_ff, q, q).scale(&rat(1, 2));
    if let Some(e) = &energy_grad {
        energy_poly.add_assign(e);
    }
    let energy = vec![((OutArr::Energy, 0), energy_poly)];

    // Derivatives.
    let frame_syms: Vec<(usize, Sym)> = (0..9)
        .filter(|&k| live(k))
        .map(|k| (k, Sym::Frame(k as u8)))
        .collect();
    let combined = |dag: &mut Dag, fp: &Poly, b: usize| -> Poly {
        let dq = dag.derivative(fp, q(b));
        let dqd = dag.derivative(fp, qd(b));
        let dqdd = dag.derivative(fp, qdd(b));
        dq.add(&dqd.mul(&Poly::var(Sym::Gp)))
            .add(&dqdd.mul(&Poly::var(Sym::Bp)))
    };
    let push = |out: &mut Outputs, arr: OutArr, idx: usize, p: Poly| {
        if !p.is_zero() {
            out.push(((arr, idx as u32), p));
        }
    };
    let refs: Vec<&Poly> = f_r.iter().chain(f_th.iter()).collect();

    // Mass kernel: acceleration-linear blocks and S_t.
    let mut mass = Outputs::new();
    for k in 0..3 {
        push(&mut mass, OutArr::St, k, s_t[k].clone());
    }
    for a in 0..n {
        for b in 0..n {
            push(
                &mut mass,
                OutArr::Mee,
                a * n + b,
                inv.m_ff.get(a, b).clone(),
            );
        }
        for k in 0..6 {
            if live(k) {
                let d = dag.derivative(&f_e[a], Sym::Frame(k as u8));
                push(&mut mass, OutArr::MeFrame, a * 6 + k, d);
            }
        }
    }
    for (r, fp) in refs.iter().enumerate() {
        for b in 0..n {
            let d = dag.derivative(fp, qdd(b));
            push(&mut mass, OutArr::MrefE, r * n + b, d);
        }
        for k in 0..6 {
            if live(k) {
                let d = dag.derivative(fp, Sym::Frame(k as u8));
                push(&mut mass, OutArr::MrefFrame, r * 6 + k, d);
            }
        }
    }

    // Residual and tangent kernels.
    let mut residual_elastic = Outputs::new();
    for (a, p) in f_e.iter().enumerate() {
        push(&mut residual_elastic, OutArr::Fe, a, p.clone());
    }
    let force_elastic = energy_grad.is_some().then(|| {
        let mut out = Outputs::new();
        for (a, p) in elastic.iter().enumerate() {
            push(&mut out, OutArr::Fe, a, p.clone());
        }
        out
    });
    let mut tangent_elastic = residual_elastic.clone();
    // K_ee = (inertial part, by the chain rule) + the elastic Hessian,
    // symmetric: each pair computed once and named.
    let mut hess = vec![vec![Poly::zero(); n]; n];
    for a in 0..n {
        for b in a..n {
            let h = dag.derivative(&elastic[a], q(b));
            let h = dag.bind(&format!("k_t_{a}_{b}"), h);
            hess[b][a] = h.clone();
            hess[a][b] = h;
        }
    }
    let mut k_ee = Vec::new();
    for a in 0..n {
        for b in 0..n {
            let t = combined(dag, &inertial[a], b).add(&hess[a][b]);
            k_ee.push(((OutArr::Kee, (a * n + b) as u32), t));
        }
    }
    tangent_elastic.extend(k_ee.iter().filter(|(_, p)| !p.is_zero()).cloned());

    let (residual, tangent) = if inputs.free {
        let mut res = Outputs::new();
        for k in 0..3 {
            push(&mut res, OutArr::Fr, k, f_r[k].clone());
            push(&mut res, OutArr::Fth, k, f_th[k].clone());
        }
        res.extend(residual_elastic.iter().cloned());
        let mut tan = res.clone();
        tan.extend(k_ee.iter().filter(|(_, p)| !p.is_zero()).cloned());
        for a in 0..n {
            for &(k, s) in &frame_syms {
                let d = dag.derivative(&f_e[a], s);
                push(&mut tan, OutArr::DeFrame, a * 9 + k, d);
            }
        }
        for (r, fp) in refs.iter().enumerate() {
            for b in 0..n {
                let t = combined(dag, fp, b);
                push(&mut tan, OutArr::KrefE, r * n + b, t);
            }
            for &(k, s) in &frame_syms {
                let d = dag.derivative(fp, s);
                push(&mut tan, OutArr::DrefFrame, r * 9 + k, d);
            }
        }
        (Some(res), Some(tan))
    } else {
        (None, None)
    };
    Equations {
        mass,
        residual,
        tangent,
        residual_elastic,
        tangent_elastic,
        force_elastic,
        energy,
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

fn invariant_outputs(inv: &ExactInvariants) -> Outputs {
    let n = inv.nf;
    let (off, _) = invariant_layout(n);
    let mut out = Outputs::new();
    let mut put = |i: usize, p: &Poly| {
        if !p.is_zero() {
            out.push(((OutArr::Inv, i as u32), p.clone()));
        }
    };
    put(off[0], &inv.mass);
    for k in 0..3 {
        put(off[1] + k, &inv.s_t0[k]);
        for a in 0..n {
            put(off[2] + k * n + a, inv.s_bar.get(k, a));
        }
        for l in 0..3 {
            for a in 0..n {
                for b in 0..n {
                    put(
                        off[3] + ((k * 3 + l) * n + a) * n + b,
                        inv.s_kl[k][l].get(a, b),
                    );
                }
                put(off[4] + (k * 3 + l) * n + a, &inv.i_kl[k][l][a]);
            }
            put(off[5] + k * 3 + l, &inv.theta[k][l]);
        }
    }
    for a in 0..n {
        for b in 0..n {
            put(off[6] + a * n + b, inv.m_ff.get(a, b));
            put(off[7] + a * n + b, inv.k_ff.get(a, b));
        }
    }
    out
}

/// `S(ξ)` and `ψ(ξ) = ½ ∇ × u` on the centre line, as polynomials in `ξ`
/// (`∂/∂x = (1/l) ∂/∂ξ`, `∂/∂y = (1/l) ∂/∂η`, `∂/∂z = (1/l) ∂/∂ζ`).
fn point_shape_outputs(shape: &Shape) -> Outputs {
    let rows = rows3(shape);
    let n = shape.n_elem();
    let inv_l = crate::poly::Monomial::var(Sym::Param(Param::ElemLength), -1);
    let centre = |f: &Poly| {
        f.substitute(Sym::Eta, &Poly::zero())
            .substitute(Sym::Zeta, &Poly::zero())
    };
    let d = |f: &Poly, s: Sym| f.diff(s).mul_monomial(&inv_l);
    let mut out = Outputs::new();
    for a in 0..n {
        for k in 0..3 {
            let s = centre(&rows[k][a]);
            if !s.is_zero() {
                out.push(((OutArr::S, (k * n + a) as u32), s));
            }
        }
        let (sx, sy, sz) = (&rows[0][a], &rows[1][a], &rows[2][a]);
        let psi = [
            d(sz, Sym::Eta).sub(&d(sy, Sym::Zeta)),
            d(sx, Sym::Zeta).sub(&d(sz, Sym::Xi)),
            d(sy, Sym::Xi).sub(&d(sx, Sym::Eta)),
        ];
        for (k, p) in psi.iter().enumerate() {
            let p = centre(p).scale(&rat(1, 2));
            if !p.is_zero() {
                out.push(((OutArr::Psi, (k * n + a) as u32), p));
            }
        }
    }
    out
}
