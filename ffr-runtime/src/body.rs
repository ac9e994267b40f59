//! A flexible body as the dynamics sees it: its constant inertia shape
//! integrals (the invariants) and the terms that depend on the elastic
//! coordinates `q_f` (theory sheet, "Mass matrix" and "Inertia shape integrals").
//!
//! Generated code (`#[flex_body]`, `ffr_codegen::Builder`) implements
//! [`FlexBody`] with unrolled expressions; [`InvariantBody`] implements it from
//! numeric invariants by the theory-sheet formulas, for bodies that come from
//! elsewhere and as a second route in cross-checks.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix3xX, Vector3};

/// Section and material parameters of a beam body, as the runtime fields of
/// generated code read them. SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Body length `L` (m); elements have `l = L / N`.
    pub length: f64,
    /// Density `ρ` (kg/m³).
    pub rho: f64,
    /// Cross-section area `A` (m²).
    pub area: f64,
    /// Second moment `I_y = ∫z² dA` (m⁴).
    pub iy: f64,
    /// Second moment `I_z = ∫y² dA` (m⁴).
    pub iz: f64,
    /// Young's modulus `E` (Pa).
    pub e: f64,
    /// Shear modulus `G` (Pa).
    pub g: f64,
    /// Torsion constant `J` (m⁴).
    pub j: f64,
}

/// The constant inertia shape integrals and stiffness of a body.
///
/// Index order `k, l ∈ {x, y, z} = {0, 1, 2}`. A planar body (`dim == 2`)
/// lives in the body x–y plane: every z component is exactly zero.
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
    /// `Ī_kl = ∫ρ ū₀_k S_l dV` (1 × n_f, stored as a column), `i_kl[k][l]`.
    pub i_kl: [[DVector<f64>; 3]; 3],
    /// `Θ_kl = ∫ρ ū₀_k ū₀_l dV`.
    pub theta: Matrix3<f64>,
    /// `m_ff = S̄_xx + S̄_yy + S̄_zz`.
    pub m_ff: DMatrix<f64>,
    /// `K_ff`.
    pub k_ff: DMatrix<f64>,
}

impl Invariants {
    /// All-zero invariants of a body of dimension `dim` with `nf` elastic
    /// coordinates (generated code fills in the non-zero entries).
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

/// The `q_f`-dependent inertia terms of the mass matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct InertiaTerms {
    /// `S_t = S_t0 + S̄ q_f`.
    pub s_t: Vector3<f64>,
    /// `Ī_θθ = ∫ρ ũᵀ ũ dV` (the inertia tensor of the deformed body).
    pub i_theta_theta: Matrix3<f64>,
    /// `Ī_θf = ∫ρ ũ S dV` (3 × n_f).
    pub i_theta_f: Matrix3xX<f64>,
}

impl InertiaTerms {
    /// Zeroed terms for a body with `nf` elastic coordinates.
    pub fn zeros(nf: usize) -> Self {
        Self {
            s_t: Vector3::zeros(),
            i_theta_theta: Matrix3::zeros(),
            i_theta_f: Matrix3xX::zeros(nf),
        }
    }
}

/// The blocks of the mass matrix `M = ∫ρ Lᵀ L dV` (theory sheet) for a body
/// with rotation `A` and `Ḡ` (3 × n_θ, `ω̄ = Ḡ θ̇`).
#[derive(Clone, Debug, PartialEq)]
pub struct MassBlocks {
    /// `m_RR = m I` (the scalar `m`).
    pub m_rr: f64,
    /// `m_Rθ = −A S̃_t Ḡ` (3 × n_θ).
    pub m_r_theta: Matrix3xX<f64>,
    /// `m_Rf = A S̄` (3 × n_f).
    pub m_rf: Matrix3xX<f64>,
    /// `m_θθ = Ḡᵀ Ī_θθ Ḡ` (n_θ × n_θ).
    pub m_theta_theta: DMatrix<f64>,
    /// `m_θf = Ḡᵀ Ī_θf` (n_θ × n_f).
    pub m_theta_f: DMatrix<f64>,
}

impl MassBlocks {
    /// The blocks from the invariants, the `q_f`-dependent terms at the
    /// current `q_f`, and `A`, `Ḡ` (`m_ff` is `inv.m_ff`, constant).
    pub fn new(
        inv: &Invariants,
        terms: &InertiaTerms,
        a: &Matrix3<f64>,
        g_bar: &Matrix3xX<f64>,
    ) -> Self {
        let s_t = terms.s_t;
        let s_t_skew = Matrix3::new(0.0, -s_t.z, s_t.y, s_t.z, 0.0, -s_t.x, -s_t.y, s_t.x, 0.0);
        Self {
            m_rr: inv.mass,
            m_r_theta: -(a * s_t_skew * g_bar),
            m_rf: a * &inv.s_bar,
            m_theta_theta: g_bar.transpose() * terms.i_theta_theta * g_bar,
            m_theta_f: g_bar.transpose() * &terms.i_theta_f,
        }
    }
}

/// A flexible body described by shape functions: what the FFR equations of
/// motion need from it. Dyn-compatible, so scenes can hold `Box<dyn FlexBody>`.
pub trait FlexBody {
    /// Number of elastic coordinates `n_f`.
    fn nf(&self) -> usize;
    /// 2 for a planar body (it lives in the body x–y plane), 3 for a spatial one.
    fn dim(&self) -> usize;
    /// A label for each elastic coordinate (kind and body node, e.g. `uy_3`).
    fn dof_labels(&self) -> Vec<String>;

    /// The constant invariants evaluated for this body's parameters.
    fn invariants(&self) -> Invariants;

    /// `S_t(q_f)`, `Ī_θθ(q_f)` and `Ī_θf(q_f)` into `out`
    /// (`q_f.len() == nf()`, `out` sized for `nf()`).
    fn inertia_terms(&self, q_f: &[f64], out: &mut InertiaTerms);

    /// The mass-matrix blocks at `q_f` for rotation `A` and `Ḡ` (3 × n_θ),
    /// from this body's invariants (pass them in: they are constant) and its
    /// `q_f`-dependent terms. `m_ff` is `invariants.m_ff`.
    fn mass_blocks(
        &self,
        invariants: &Invariants,
        q_f: &[f64],
        a: &Matrix3<f64>,
        g_bar: &Matrix3xX<f64>,
    ) -> MassBlocks {
        let mut terms = InertiaTerms::zeros(self.nf());
        self.inertia_terms(q_f, &mut terms);
        MassBlocks::new(invariants, &terms, a, g_bar)
    }

    /// Whether [`FlexBody::stiffening`] adds anything (geometric stiffening
    /// generated for this body).
    fn has_stiffening(&self) -> bool {
        false
    }

    /// Geometric (centrifugal) stiffening from the quadratic axial strain
    /// `ε = u' + ½(v'² + w'²)` taken as its mean over each element (which
    /// keeps coarse meshes free of membrane locking): with
    /// `U_nl(q_f) = Σ_e EA l (½ ū' s̄ + ⅛ s̄²)` (`ū'`, `s̄`: element means of
    /// `u'` and `v'² + w'²`), the part of the strain energy beyond
    /// `½ q_fᵀ K_ff q_f`, this **adds**
    /// `∂U_nl/∂q_f` to `force` and, when given, `∂²U_nl/∂q_f²` to `tangent`.
    /// The elastic generalized force is then `−K_ff q_f − ∂U_nl/∂q_f`.
    fn stiffening(&self, q_f: &[f64], force: &mut [f64], tangent: Option<&mut DMatrix<f64>>) {
        let _ = (q_f, force, tangent);
    }

    /// The stiffening energy `U_nl(q_f)` (zero without stiffening).
    ///
    /// Default: `U_nl(q) = ∫₀¹ ∂U_nl/∂q(s q) · q ds`, by two-point Gauss–Legendre
    /// quadrature on `[0, 1]` — exact because `U_nl` is a polynomial of degree
    /// at most 4 with `U_nl(0) = 0`, so the integrand is a cubic in `s`.
    fn stiffening_energy(&self, q_f: &[f64]) -> f64 {
        if !self.has_stiffening() {
            return 0.0;
        }
        let d = 0.5 / 3f64.sqrt();
        let mut energy = 0.0;
        let mut qs = vec![0.0; q_f.len()];
        let mut f = vec![0.0; q_f.len()];
        for s in [0.5 - d, 0.5 + d] {
            qs.iter_mut().zip(q_f).for_each(|(a, b)| *a = s * b);
            f.iter_mut().for_each(|x| *x = 0.0);
            self.stiffening(&qs, &mut f, None);
            energy += 0.5 * f.iter().zip(q_f).map(|(a, b)| a * b).sum::<f64>();
        }
        energy
    }
}

/// A [`FlexBody`] whose layout is fixed at compile time (generated code).
pub trait CompiledBody: FlexBody {
    /// Number of elastic coordinates `n_f`.
    const NF: usize;
    /// 2 (planar) or 3 (spatial).
    const DIM: usize;
    /// A label for each elastic coordinate.
    const DOFS: &'static [&'static str];
}

/// A body given by numeric invariants; its `q_f`-dependent terms follow the
/// theory-sheet formulas
///
/// `U_kl = Θ_kl + (Ī_kl + Ī_lk) q + qᵀ S̄_kl q`, `Ī_θθ = tr(U) I − U`,
/// `Ī_θf = [Ī_yz − Ī_zy + qᵀ(S̄_yz − S̄_zy); …]`.
#[derive(Clone, Debug)]
pub struct InvariantBody {
    /// The invariants the body is made of.
    pub invariants: Invariants,
}

impl InvariantBody {
    /// The body with these invariants.
    pub fn new(invariants: Invariants) -> Self {
        Self { invariants }
    }
}

impl FlexBody for InvariantBody {
    fn nf(&self) -> usize {
        self.invariants.nf()
    }

    fn dim(&self) -> usize {
        self.invariants.dim
    }

    fn dof_labels(&self) -> Vec<String> {
        (0..self.nf()).map(|i| format!("q{i}")).collect()
    }

    fn invariants(&self) -> Invariants {
        self.invariants.clone()
    }

    /// `S_t`, `Ī_θθ`, `Ī_θf` at `q_f` by the theory-sheet formulas.
    fn inertia_terms(&self, q_f: &[f64], out: &mut InertiaTerms) {
        let inv = &self.invariants;
        let nf = inv.nf();
        assert_eq!(
            q_f.len(),
            nf,
            "q_f has {} entries, the body has {nf} elastic coordinates",
            q_f.len()
        );
        let q = DVector::from_column_slice(q_f);
        out.s_t = inv.s_t0 + &inv.s_bar * &q;
        let mut u = Matrix3::zeros();
        for k in 0..3 {
            for l in 0..3 {
                u[(k, l)] = inv.theta[(k, l)]
                    + (&inv.i_kl[k][l] + &inv.i_kl[l][k]).dot(&q)
                    + q.dot(&(&inv.s_kl[k][l] * &q));
            }
        }
        out.i_theta_theta = Matrix3::identity() * u.trace() - u;
        // Row r of Ī_θf is Ī_ab − Ī_ba + qᵀ(S̄_ab − S̄_ba) with (a, b) cyclic after r.
        out.i_theta_f = Matrix3xX::zeros(nf);
        for (r, (a, b)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
            let row = &inv.i_kl[a][b] - &inv.i_kl[b][a]
                + (inv.s_kl[a][b].transpose() - inv.s_kl[b][a].transpose()) * &q;
            out.i_theta_f.set_row(r, &row.transpose());
        }
    }
}
