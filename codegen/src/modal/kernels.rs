//! Modal bodies as generated code: the projected equations of motion of a
//! reduced body (`docs/theory.md` §13, "Modal bodies as generated code") as
//! straight-line programs, the same path as an element's kernels
//! ([`crate::eom::equations`]) with the projected invariants as exact
//! constants.
//!
//! The invariants `m`, `S_t0`, `S̄Φ`, `Φᵀ S̄_kl Φ`, `Ī_kl Φ`, `Θ_kl`,
//! `Φᵀ m_ff Φ`, `Φᵀ K_ff Φ` are the model's `f64` numbers, each converted to
//! the rational it is (every finite `f64` is one), so the programs fold and
//! cancel exactly what the numbers give and their literals are the correctly
//! rounded sums of the numbers. The linear elastic force `K̃ η` is part of
//! the programs only for a body without geometric stiffening; with it the
//! runtime adds the elastic force through the full body's element scalars,
//! as for a modal body without generated kernels.

use super::{Invariants, ModalModel};
use crate::body::{ExactInvariants, PolyMatrix};
use crate::dag::Dag;
use crate::eom::{equations, FrameInputs};
use crate::error::Error;
use crate::poly::{Poly, Rational};
use crate::program::{Expr, Program, ProgramBuilder};
use ffr_spec::SceneDim;

/// Above this many modes a generated modal body keeps the run-time
/// equations (`ffr_runtime`'s `InertiaTerms`): the unrolled kernels grow as
/// `k³` (25 spatial modes: about 25 000 operations in the tangent, 1.5 MB
/// of code, half a minute of release compile).
pub const MAX_GENERATED_MODES: usize = 32;

/// The programs of a modal body's inertia equations (see the module
/// documentation), over `k` modal coordinates (`q[i]` is `η_i`).
#[derive(Clone, Debug)]
pub struct ModalKernelSet {
    /// Number of modes `k`.
    pub modes: usize,
    /// The scene the programs were generated for (planar: frame motion in
    /// the x–y plane).
    pub scene: SceneDim,
    /// Whether the programs include the linear elastic force `K̃ η` (a body
    /// without geometric stiffening).
    pub linear_elastic: bool,
    /// `mass(η)`: `S_t` and the acceleration-linear blocks.
    pub mass: Program,
    /// `residual(η, η̇, η̈, frame)`: `f_r`, `f_θ`, `f_f`.
    pub residual: Program,
    /// `tangent(…)`: the residual and its derivatives.
    pub tangent: Program,
    /// `residual_elastic(…)`: `f_f` only.
    pub residual_elastic: Program,
    /// `tangent_elastic(…)`: `f_f` and `K_ff`.
    pub tangent_elastic: Program,
}

impl ModalKernelSet {
    /// The programs by kernel name, in emission order.
    pub fn programs(&self) -> [(&'static str, &Program); 5] {
        [
            ("mass", &self.mass),
            ("residual", &self.residual),
            ("tangent", &self.tangent),
            ("residual_elastic", &self.residual_elastic),
            ("tangent_elastic", &self.tangent_elastic),
        ]
    }
}

/// `x` as the exact rational it is; an error naming `name` if it is not a
/// finite number.
fn exact(name: &str, x: f64) -> Result<Poly, Error> {
    if x == 0.0 {
        return Ok(Poly::zero());
    }
    Rational::from_float(x)
        .filter(|_| x.is_finite())
        .map(Poly::constant)
        .ok_or_else(|| {
            Error::Body(format!(
                "modal kernels: `{name}` is {x}, not a finite number"
            ))
        })
}

fn exact_matrix(name: &str, m: &nalgebra::DMatrix<f64>) -> Result<PolyMatrix, Error> {
    let mut out = PolyMatrix::zeros(m.nrows(), m.ncols());
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            *out.get_mut(i, j) = exact(name, m[(i, j)])?;
        }
    }
    Ok(out)
}

/// The numeric invariants `inv` (`n_f = k`) as exact constants: each entry
/// the rational that reproduces its `f64` bits. An error if a number is not
/// finite.
pub fn exact_invariants(inv: &Invariants) -> Result<ExactInvariants, Error> {
    let k = inv.m_ff.nrows();
    if inv.s_bar.shape() != (3, k) || inv.k_ff.shape() != (k, k) {
        return Err(Error::Body(format!(
            "modal kernels: S̄ is {}×{} and K_ff {}×{} for {k} modes",
            inv.s_bar.nrows(),
            inv.s_bar.ncols(),
            inv.k_ff.nrows(),
            inv.k_ff.ncols()
        )));
    }
    let mut s_kl: [[PolyMatrix; 3]; 3] =
        std::array::from_fn(|_| std::array::from_fn(|_| PolyMatrix::zeros(k, k)));
    let mut i_kl: [[Vec<Poly>; 3]; 3] = Default::default();
    let mut theta: [[Poly; 3]; 3] = Default::default();
    let mut s_t0: [Poly; 3] = Default::default();
    for a in 0..3 {
        s_t0[a] = exact("s_t0", inv.s_t0[a])?;
        for b in 0..3 {
            if inv.s_kl[a][b].shape() != (k, k) || inv.i_kl[a][b].len() != k {
                return Err(Error::Body(format!(
                    "modal kernels: S̄_kl or Ī_kl is not sized for {k} modes"
                )));
            }
            s_kl[a][b] = exact_matrix("s_kl", &inv.s_kl[a][b])?;
            i_kl[a][b] = inv.i_kl[a][b]
                .iter()
                .map(|x| exact("i_kl", *x))
                .collect::<Result<_, _>>()?;
            theta[a][b] = exact("theta", inv.theta[(a, b)])?;
        }
    }
    Ok(ExactInvariants {
        dim: inv.dim,
        nf: k,
        mass: exact("mass", inv.mass)?,
        s_t0,
        s_bar: exact_matrix("s_bar", &inv.s_bar)?,
        s_kl,
        i_kl,
        theta,
        m_ff: exact_matrix("m_ff", &inv.m_ff)?,
        k_ff: exact_matrix("k_ff", &inv.k_ff)?,
    })
}

/// Whether every literal of `p` is finite.
fn finite_literals(p: &Program) -> bool {
    fn ok(e: &Expr) -> bool {
        match e {
            Expr::Var(_) => true,
            Expr::Lit(x) => x.is_finite(),
            Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) => ok(a) && ok(b),
            Expr::Neg(a) => ok(a),
        }
    }
    p.stmts.iter().all(|(_, e)| ok(e)) && p.outputs.iter().all(|(_, e)| ok(e))
}

/// The programs of `model`'s inertia equations in a `scene` (see the
/// module documentation); `Ok(None)` above [`MAX_GENERATED_MODES`] modes
/// (the run-time equations then serve). An error if a number of the model
/// is not finite or a literal of the programs is outside the `f64` range.
pub fn generate_modal_kernels(
    model: &ModalModel,
    scene: SceneDim,
) -> Result<Option<ModalKernelSet>, Error> {
    let k = model.len();
    if k == 0 || k > MAX_GENERATED_MODES {
        return Ok(None);
    }
    let mut inv = exact_invariants(&model.projected)?;
    // With stiffening the runtime adds K̃ η with the stiffening force.
    let linear_elastic = !model.stiffening.is_on();
    if !linear_elastic {
        inv.k_ff = PolyMatrix::zeros(k, k);
    }
    let mut dag = Dag::new();
    let inputs = FrameInputs {
        planar: scene == SceneDim::Planar,
        zero_acceleration: false,
        free: true,
    };
    let eq = equations(&inv, None, inputs, &mut dag);
    let (Some(residual), Some(tangent)) = (&eq.residual, &eq.tangent) else {
        return Err(Error::Body(
            "modal kernels: no reference rows for a free frame (a generator bug)".into(),
        ));
    };
    let build = |outputs| ProgramBuilder::new(None).build(&dag, outputs);
    let set = ModalKernelSet {
        modes: k,
        scene,
        linear_elastic,
        mass: build(&eq.mass),
        residual: build(residual),
        tangent: build(tangent),
        residual_elastic: build(&eq.residual_elastic),
        tangent_elastic: build(&eq.tangent_elastic),
    };
    if let Some((name, _)) = set.programs().iter().find(|(_, p)| !finite_literals(p)) {
        return Err(Error::Body(format!(
            "modal kernels: `{name}` has a constant outside the f64 range"
        )));
    }
    Ok(Some(set))
}
