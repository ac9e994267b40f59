//! A body as the dynamics sees it: its generalized inertia and elastic
//! forces in body axes, their derivatives, its mass blocks and energy
//! (theory: `docs/theory.md`, "Equations of motion in body axes").
//!
//! A body with elastic coordinates `q_f` whose frame moves with `ā = Aᵀ(R̈ −
//! g)`, `α = ω̄̇`, `ω = ω̄` (body axes) has the generalized forces
//! `f_r` (3), `f_θ` (3) and `f_f` (`n_f`) of [`crate::kernel`]; the system
//! forms `r_R = A f_r`, `r_θ = Ḡᵀ f_θ`, `r_f = f_f`. Flexible bodies
//! assemble them from element kernels ([`crate::kernel_body::KernelBody`]);
//! rigid bodies ([`crate::rigid::RigidBody`]) compute them directly.

use crate::error::Result;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3xX, Vector3};

/// A square matrix with half-bandwidth `hb`: entry `(i, j)`, `|i − j| ≤ hb`,
/// at `data[i·(2hb + 1) + (j + hb − i)]`.
#[derive(Clone, Debug, PartialEq)]
pub struct BandBuf {
    n: usize,
    hb: usize,
    data: Vec<f64>,
}

impl BandBuf {
    /// An `n × n` zero matrix of half-bandwidth `hb`.
    pub fn zeros(n: usize, hb: usize) -> Self {
        Self {
            n,
            hb,
            data: vec![0.0; n * (2 * hb + 1)],
        }
    }
    /// Size.
    pub fn n(&self) -> usize {
        self.n
    }
    /// Half-bandwidth.
    pub fn half_bandwidth(&self) -> usize {
        self.hb
    }
    /// Set every entry to zero.
    pub fn clear(&mut self) {
        self.data.iter_mut().for_each(|x| *x = 0.0);
    }
    #[inline]
    fn at(&self, i: usize, j: usize) -> usize {
        debug_assert!(i.abs_diff(j) <= self.hb && i < self.n && j < self.n);
        i * (2 * self.hb + 1) + (j + self.hb - i)
    }
    /// Entry `(i, j)` (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i.abs_diff(j) > self.hb {
            0.0
        } else {
            self.data[self.at(i, j)]
        }
    }
    /// `A[i, j] += v` (inside the band).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let k = self.at(i, j);
        self.data[k] += v;
    }
    /// Row `i` as `(first column, values)` over the band.
    pub fn row(&self, i: usize) -> (usize, &[f64]) {
        let w = 2 * self.hb + 1;
        let lo = i.saturating_sub(self.hb);
        let start = i * w + (lo + self.hb - i);
        let hi = (i + self.hb).min(self.n - 1);
        (lo, &self.data[start..start + (hi + 1 - lo)])
    }
    /// `y += s · A x`.
    pub fn mul_add(&self, x: &[f64], s: f64, y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate().take(self.n) {
            let (lo, r) = self.row(i);
            let mut acc = 0.0;
            for (k, a) in r.iter().enumerate() {
                acc += a * x[lo + k];
            }
            *yi += s * acc;
        }
    }
    /// `self += s · other` (same shape).
    pub fn add_scaled(&mut self, s: f64, other: &BandBuf) {
        debug_assert_eq!((self.n, self.hb), (other.n, other.hb));
        for (a, b) in self.data.iter_mut().zip(&other.data) {
            *a += s * b;
        }
    }
    /// As a dense matrix (checks and tests).
    pub fn to_dense(&self) -> DMatrix<f64> {
        DMatrix::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }
}

/// The static description of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyLayout {
    /// Shape dimension: 2 (the body lies in its x–y plane) or 3.
    pub dim: usize,
    /// Scene dimension its equations are written for (2 or 3).
    pub scene_dim: usize,
    /// Number of elastic coordinates.
    pub nf: usize,
    /// Half-bandwidth of the elastic blocks (`m_ff`, `K_ff`, tangents).
    pub half_bandwidth: usize,
    /// Whether the reference rows (`f_r`, `f_θ`) and frame derivatives can
    /// be evaluated (otherwise the frame motion must be prescribed).
    pub free_frame: bool,
    /// Whether the body ignores `ā` (generated for `ā ≡ 0`: no gravity, the
    /// frame origin held at rest).
    pub zero_frame_acceleration: bool,
    /// A label for each elastic coordinate (`kind_node`, e.g. `uy_3`).
    pub labels: Vec<String>,
    /// The undeformed axis length of a beam body (markers `x = …` must lie
    /// in `[0, length]`); `None` for a rigid body.
    pub length: Option<f64>,
    /// One line saying what the body is (for messages and reports).
    pub description: String,
}

/// The state of one body passed to its force evaluation.
#[derive(Clone, Copy, Debug)]
pub struct BodyState<'a> {
    /// `q_f`.
    pub q_f: &'a [f64],
    /// `q̇_f`.
    pub qd_f: &'a [f64],
    /// `q̈_f`.
    pub qdd_f: &'a [f64],
    /// `[ā, α, ω]` in body axes: `ā = Aᵀ(R̈ − g)`, `α = ω̄̇`, `ω = ω̄`.
    pub frame: [f64; 9],
}

/// Generalized inertia and elastic forces of a body in body axes.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyForces {
    /// `f_r`.
    pub f_r: [f64; 3],
    /// `f_θ`.
    pub f_th: [f64; 3],
    /// `f_f` (`n_f`).
    pub f_f: Vec<f64>,
}

impl BodyForces {
    /// Zero forces for `nf` elastic coordinates.
    pub fn zeros(nf: usize) -> Self {
        Self {
            f_r: [0.0; 3],
            f_th: [0.0; 3],
            f_f: vec![0.0; nf],
        }
    }
    /// Set to zero.
    pub fn clear(&mut self) {
        self.f_r = [0.0; 3];
        self.f_th = [0.0; 3];
        self.f_f.iter_mut().for_each(|x| *x = 0.0);
    }
}

/// Derivatives of [`BodyForces`] for a Newton iteration with
/// `∂q̈/∂q = β'`, `∂q̇/∂q = γ'`.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyTangent {
    /// `β' ∂f_f/∂q̈_f + γ' ∂f_f/∂q̇_f + ∂f_f/∂q_f` (banded).
    pub k_ff: BandBuf,
    /// `∂f_f/∂[ā, α, ω]` (`n_f × 9`, row-major).
    pub d_f_frame: Vec<f64>,
    /// `β' ∂/∂q̈_f + γ' ∂/∂q̇_f + ∂/∂q_f` of `[f_r; f_θ]` (`6 × n_f`).
    pub k_ref_f: Vec<f64>,
    /// `∂[f_r; f_θ]/∂[ā, α, ω]` (`6 × 9`).
    pub d_ref_frame: [f64; 54],
}

impl BodyTangent {
    /// Zero derivatives for `nf` coordinates, half-bandwidth `hb`.
    pub fn zeros(nf: usize, hb: usize) -> Self {
        Self {
            k_ff: BandBuf::zeros(nf, hb),
            d_f_frame: vec![0.0; nf * 9],
            k_ref_f: vec![0.0; 6 * nf],
            d_ref_frame: [0.0; 54],
        }
    }
    /// Set to zero.
    pub fn clear(&mut self) {
        self.k_ff.clear();
        self.d_f_frame.iter_mut().for_each(|x| *x = 0.0);
        self.k_ref_f.iter_mut().for_each(|x| *x = 0.0);
        self.d_ref_frame = [0.0; 54];
    }
}

/// The mass blocks of a body in body axes (the acceleration-linear part of
/// [`BodyForces`]) and `S_t`.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyMass {
    /// `S_t = S_t0 + S̄ q_f`.
    pub s_t: [f64; 3],
    /// `m_ff` (banded).
    pub m_ff: BandBuf,
    /// `∂f_f/∂[ā, α] = [S̄ᵀ, Ī_θfᵀ]` (`n_f × 6`).
    pub m_f_frame: Vec<f64>,
    /// `∂[f_r; f_θ]/∂q̈_f = [S̄; Ī_θf]` (`6 × n_f`).
    pub m_ref_f: Vec<f64>,
    /// `∂[f_r; f_θ]/∂[ā, α] = [m I, −S̃_t; S̃_t, Ī_θθ]` (`6 × 6`).
    pub m_ref_frame: [f64; 36],
}

impl BodyMass {
    /// Zero blocks.
    pub fn zeros(nf: usize, hb: usize) -> Self {
        Self {
            s_t: [0.0; 3],
            m_ff: BandBuf::zeros(nf, hb),
            m_f_frame: vec![0.0; nf * 6],
            m_ref_f: vec![0.0; 6 * nf],
            m_ref_frame: [0.0; 36],
        }
    }
    /// Set to zero.
    pub fn clear(&mut self) {
        self.s_t = [0.0; 3];
        self.m_ff.clear();
        self.m_f_frame.iter_mut().for_each(|x| *x = 0.0);
        self.m_ref_f.iter_mut().for_each(|x| *x = 0.0);
        self.m_ref_frame = [0.0; 36];
    }

    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.m_ref_frame[0]
    }

    /// `M v` in body axes for velocities `v̄ = AᵀṘ`, `ω`, `q̇_f`: the
    /// translational momentum `p̄ = m v̄ − S̃_t ω + S̄ q̇_f`, the angular
    /// momentum about the frame origin `h̄ = S̃_t v̄ + Ī_θθ ω + Ī_θf q̇_f`
    /// (body axes) and `M_f v`.
    pub fn momenta(&self, v: &[f64; 3], w: &[f64; 3], qd_f: &[f64]) -> ([f64; 6], Vec<f64>) {
        let mut mf = vec![0.0; qd_f.len()];
        let h = self.momenta_into(v, w, qd_f, &mut mf);
        (h, mf)
    }

    /// [`BodyMass::momenta`] without allocating: the elastic part into `mf`
    /// (length `n_f`), the frame part returned.
    // Block matrix–vector products written by index, as in the formula.
    #[allow(clippy::needless_range_loop)]
    pub fn momenta_into(
        &self,
        v: &[f64; 3],
        w: &[f64; 3],
        qd_f: &[f64],
        mf: &mut [f64],
    ) -> [f64; 6] {
        let nf = qd_f.len();
        let vw = [v[0], v[1], v[2], w[0], w[1], w[2]];
        let mut h = [0.0; 6];
        for r in 0..6 {
            let mut s = 0.0;
            for k in 0..6 {
                s += self.m_ref_frame[r * 6 + k] * vw[k];
            }
            for a in 0..nf {
                s += self.m_ref_f[r * nf + a] * qd_f[a];
            }
            h[r] = s;
        }
        mf.iter_mut().for_each(|x| *x = 0.0);
        self.m_ff.mul_add(qd_f, 1.0, mf);
        for a in 0..nf {
            for k in 0..6 {
                mf[a] += self.m_f_frame[a * 6 + k] * vw[k];
            }
        }
        h
    }
}

/// The constant inertia shape integrals and stiffness of a body (dense; for
/// checks, exports and reports — the dynamics never assembles them).
///
/// Index order `k, l ∈ {x, y, z}`. A planar body has zero z components.
#[derive(Clone, Debug, PartialEq)]
pub struct Invariants {
    /// 2 (planar) or 3 (spatial).
    pub dim: usize,
    /// `m = ∫ρ dV`.
    pub mass: f64,
    /// `S_t0 = ∫ρ ū₀ dV`.
    pub s_t0: Vector3<f64>,
    /// `S̄ = ∫ρ S dV` (3 × n_f).
    pub s_bar: Matrix3xX<f64>,
    /// `S̄_kl = ∫ρ S_kᵀ S_l dV` (n_f × n_f), `s_kl[k][l]`.
    pub s_kl: [[DMatrix<f64>; 3]; 3],
    /// `Ī_kl = ∫ρ ū₀_k S_l dV` (n_f, as a column), `i_kl[k][l]`.
    pub i_kl: [[DVector<f64>; 3]; 3],
    /// `Θ_kl = ∫ρ ū₀_k ū₀_l dV`.
    pub theta: Matrix3<f64>,
    /// `m_ff = S̄_xx + S̄_yy + S̄_zz`.
    pub m_ff: DMatrix<f64>,
    /// `K_ff`.
    pub k_ff: DMatrix<f64>,
}

impl Invariants {
    /// All-zero invariants of a body of dimension `dim` with `nf` coordinates.
    pub fn zeros(dim: usize, nf: usize) -> Self {
        Self {
            dim,
            mass: 0.0,
            s_t0: Vector3::zeros(),
            s_bar: Matrix3xX::zeros(nf),
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(nf, nf))),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| DVector::zeros(nf))),
            theta: Matrix3::zeros(),
            m_ff: DMatrix::zeros(nf, nf),
            k_ff: DMatrix::zeros(nf, nf),
        }
    }

    /// Number of elastic coordinates.
    pub fn nf(&self) -> usize {
        self.m_ff.nrows()
    }
}

/// A point of a body on its undeformed axis (or any body-fixed point of a
/// rigid body): undeformed position `ū₀` and the elastic coordinates that
/// move it, `ū = ū₀ + Σ_j s_j q_f[dof_j]`, with its section rotation
/// `ψ = Σ_j ψ_j q_f[dof_j]` (small rotation of the attached section).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointShape {
    /// `ū₀` in body axes.
    pub u0: [f64; 3],
    /// `(dof, s_j, ψ_j)` for the coordinates with a non-zero entry.
    pub entries: Vec<(usize, [f64; 3], [f64; 3])>,
}

/// Per-body scratch space the caller owns (allocated once, by [`Body::work`]).
#[derive(Clone, Debug, Default)]
pub struct BodyWork {
    /// Scratch values.
    pub buf: Vec<f64>,
    /// The scratch of a body this body evaluates (a modal body's full body).
    pub inner: Option<Box<InnerWork>>,
}

/// Scratch for evaluating another body: its own [`BodyWork`] and outputs.
#[derive(Clone, Debug)]
pub struct InnerWork {
    /// The other body's scratch.
    pub work: BodyWork,
    /// Its forces.
    pub forces: BodyForces,
    /// Its tangent.
    pub tangent: BodyTangent,
}

/// A body of a scene: flexible (element kernels, modal) or rigid.
pub trait Body: Send + Sync {
    /// Static description.
    fn layout(&self) -> &BodyLayout;

    /// Scratch space for the evaluations (allocates; call once at set-up).
    fn work(&self) -> BodyWork;

    /// `f_r`, `f_θ` (when `frame_rows`) and `f_f` at `state` into `out`
    /// (cleared first).
    fn forces(&self, state: &BodyState, frame_rows: bool, w: &mut BodyWork, out: &mut BodyForces);

    /// [`Body::forces`] and its derivatives (all of [`BodyTangent`] when
    /// `frame_rows`, else only `k_ff`); both outputs are cleared first.
    #[allow(clippy::too_many_arguments)]
    fn tangent(
        &self,
        state: &BodyState,
        bp: f64,
        gp: f64,
        frame_rows: bool,
        w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    );

    /// The mass blocks and `S_t` at `q_f` (cleared first).
    fn mass(&self, q_f: &[f64], w: &mut BodyWork, out: &mut BodyMass);

    /// Elastic energy `½ q_fᵀ K_ff q_f + U_nl(q_f)`.
    fn elastic_energy(&self, q_f: &[f64], w: &mut BodyWork) -> f64;

    /// The invariants (dense; set-up, checks and exports).
    fn invariants(&self) -> Invariants;

    /// The point at `x` on the undeformed axis (a beam body), or an error
    /// naming the valid range.
    fn point_shape(&self, x: f64) -> Result<PointShape>;

    /// The number of nodes [`Body::node_shape`] names (an FE body's nodes,
    /// `0` to `node_count() − 1`); 0, the default, for bodies without nodes
    /// to name.
    fn node_count(&self) -> usize {
        0
    }

    /// Node `node` of an FE body (a marker `NAME@node=N`), or an error: the
    /// default, for bodies without nodes to name.
    fn node_shape(&self, node: usize) -> Result<PointShape> {
        let _ = node;
        Err(crate::error::Error::InvalidInput(
            "`@node=N` names a node of an FE body; this body has none".into(),
        ))
    }

    /// The body's own damping matrix `D` of its elastic coordinates (a
    /// modal body's per-mode ratios), added to any Rayleigh damping the
    /// system sets: the force `D q̇_f`. `None` (the default): none.
    fn damping(&self) -> Option<BandBuf> {
        None
    }

    /// The elastic force alone at `q_f`, `K_ff q_f + ∇U_nl(q_f)` (what
    /// [`Body::forces`] gives at rest: `q̇_f = q̈_f = 0`, the frame at rest),
    /// into `f_f` (overwritten), by kernels that evaluate nothing else; a
    /// modal body's stiffening calls it at `q_f = Φ η`. `false` (the
    /// default, `f_f` unspecified): not available, use [`Body::forces`].
    fn elastic_force(&self, q_f: &[f64], w: &mut BodyWork, f_f: &mut [f64]) -> bool {
        let _ = (q_f, w, f_f);
        false
    }

    /// The stiffening energy of the body's elements in their element
    /// scalars (`ElementKernels::elastic_scalars`, `docs/theory.md`
    /// "Geometric stiffening"): `U_nl = Σ_e U_e(z_e)`, `z_e = S_e q_e`
    /// linear in the element's coordinates. `None` (the default): not
    /// available; a modal body then projects [`Body::elastic_force`].
    fn scalar_layout(&self) -> Option<ScalarLayout> {
        None
    }

    /// Element `e`'s scalars `z_e = S_e q_e` at the body coordinates
    /// `q_f`, into `z[..scalars]` (`z` has [`ScalarLayout::local`] entries).
    /// Only meaningful for a body with a [`Body::scalar_layout`]; the
    /// default (no element scalars) leaves `z` untouched.
    fn element_scalars(&self, e: usize, q_f: &[f64], w: &mut BodyWork, z: &mut [f64]) {
        let _ = (e, q_f, w, z);
    }

    /// `g = ∂U_e/∂z` of element `e` at its scalars `z` (overwritten, `local`
    /// entries) and, with `h`, `∂²U_e/∂z²` (overwritten, `local × local`
    /// row-major). `false`: not available (no [`Body::scalar_layout`]).
    fn scalar_derivatives(
        &self,
        e: usize,
        z: &[f64],
        w: &mut BodyWork,
        g: &mut [f64],
        h: Option<&mut [f64]>,
    ) -> bool {
        let _ = (e, z, w, g, h);
        false
    }

    /// [`Body::scalar_derivatives`] of every element at once, without the
    /// Hessian: `g_all[j E + e] = ∂U_e/∂z_j` at `z_all[j E + e]` (`E`
    /// elements, `n_z` scalars each; `g_all` overwritten). `false`: not
    /// available.
    fn scalar_forces(&self, z_all: &[f64], w: &mut BodyWork, g_all: &mut [f64]) -> bool {
        let _ = (z_all, w, g_all);
        false
    }
}

/// How a body's stiffening energy splits into element scalars
/// ([`Body::scalar_layout`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScalarLayout {
    /// Number of elements.
    pub elements: usize,
    /// Scalars per element, `n_z`.
    pub scalars: usize,
    /// The length of the scalar arrays (the element's coordinates, `n ≥ n_z`).
    pub local: usize,
}

impl<B: Body + ?Sized> Body for Box<B> {
    fn layout(&self) -> &BodyLayout {
        (**self).layout()
    }
    fn work(&self) -> BodyWork {
        (**self).work()
    }
    fn forces(&self, s: &BodyState, fr: bool, w: &mut BodyWork, out: &mut BodyForces) {
        (**self).forces(s, fr, w, out)
    }
    fn elastic_force(&self, q_f: &[f64], w: &mut BodyWork, f_f: &mut [f64]) -> bool {
        (**self).elastic_force(q_f, w, f_f)
    }
    fn scalar_layout(&self) -> Option<ScalarLayout> {
        (**self).scalar_layout()
    }
    fn element_scalars(&self, e: usize, q_f: &[f64], w: &mut BodyWork, z: &mut [f64]) {
        (**self).element_scalars(e, q_f, w, z)
    }
    fn scalar_derivatives(
        &self,
        e: usize,
        z: &[f64],
        w: &mut BodyWork,
        g: &mut [f64],
        h: Option<&mut [f64]>,
    ) -> bool {
        (**self).scalar_derivatives(e, z, w, g, h)
    }
    fn scalar_forces(&self, z_all: &[f64], w: &mut BodyWork, g_all: &mut [f64]) -> bool {
        (**self).scalar_forces(z_all, w, g_all)
    }
    fn tangent(
        &self,
        s: &BodyState,
        bp: f64,
        gp: f64,
        fr: bool,
        w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    ) {
        (**self).tangent(s, bp, gp, fr, w, out, t)
    }
    fn mass(&self, q_f: &[f64], w: &mut BodyWork, out: &mut BodyMass) {
        (**self).mass(q_f, w, out)
    }
    fn elastic_energy(&self, q_f: &[f64], w: &mut BodyWork) -> f64 {
        (**self).elastic_energy(q_f, w)
    }
    fn invariants(&self) -> Invariants {
        (**self).invariants()
    }
    fn point_shape(&self, x: f64) -> Result<PointShape> {
        (**self).point_shape(x)
    }
    fn node_count(&self) -> usize {
        (**self).node_count()
    }
    fn node_shape(&self, node: usize) -> Result<PointShape> {
        (**self).node_shape(node)
    }
    fn damping(&self) -> Option<BandBuf> {
        (**self).damping()
    }
}

/// The bit patterns of everything `body` computes — invariants, mass blocks,
/// forces, tangent and elastic energy, at rest and at a deterministic
/// deformed, moving state of amplitude `amplitude` (in the units of the
/// coordinates) — to check that two builds of one body (an attribute and a
/// build script, compiled kernels and tapes) agree to the last bit.
pub fn sample_bits(body: &dyn Body, amplitude: f64) -> Vec<u64> {
    let lay = body.layout();
    let nf = lay.nf;
    let hb = lay.half_bandwidth;
    let wave = |phase: f64| -> Vec<f64> {
        (0..nf)
            .map(|i| amplitude * ((i as f64 + 1.0) * 0.7 + phase).sin())
            .collect()
    };
    let mut bits = vec![nf as u64, lay.dim as u64, lay.scene_dim as u64];
    let mut push = |xs: &[f64]| bits.extend(xs.iter().map(|x| x.to_bits()));
    let inv = body.invariants();
    push(&[inv.mass]);
    push(inv.s_t0.as_slice());
    push(inv.s_bar.as_slice());
    for k in 0..3 {
        for l in 0..3 {
            push(inv.s_kl[k][l].as_slice());
            push(inv.i_kl[k][l].as_slice());
        }
    }
    push(inv.theta.as_slice());
    push(inv.m_ff.as_slice());
    push(inv.k_ff.as_slice());
    let mut w = body.work();
    let mut forces = BodyForces::zeros(nf);
    let mut tangent = BodyTangent::zeros(nf, hb);
    let mut mass = BodyMass::zeros(nf, hb);
    let frame = [0.3, -0.2, 0.1, 0.5, -0.4, 0.2, 1.5, -0.7, 0.9];
    for scale in [0.0, 1.0] {
        let q: Vec<f64> = wave(0.0).iter().map(|x| scale * x).collect();
        let qd: Vec<f64> = wave(1.0).iter().map(|x| scale * 10.0 * x).collect();
        let qdd: Vec<f64> = wave(2.0).iter().map(|x| scale * 100.0 * x).collect();
        let state = BodyState {
            q_f: &q,
            qd_f: &qd,
            qdd_f: &qdd,
            frame: frame.map(|f| f * scale),
        };
        body.mass(&q, &mut w, &mut mass);
        push(&mass.s_t);
        push(mass.m_ff.to_dense().as_slice());
        push(&mass.m_f_frame);
        push(&mass.m_ref_f);
        push(&mass.m_ref_frame);
        body.forces(&state, lay.free_frame, &mut w, &mut forces);
        push(&forces.f_r);
        push(&forces.f_th);
        push(&forces.f_f);
        body.tangent(
            &state,
            4.0e4,
            2.0e2,
            lay.free_frame,
            &mut w,
            &mut forces,
            &mut tangent,
        );
        push(tangent.k_ff.to_dense().as_slice());
        push(&tangent.d_f_frame);
        push(&tangent.k_ref_f);
        push(&tangent.d_ref_frame);
        push(&[body.elastic_energy(&q, &mut w)]);
    }
    bits
}
