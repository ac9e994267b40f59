//! Geometric stiffening: the strain energy `U_nl` a body carries beyond the
//! linear `½ q_fᵀ K_ff q_f`, its gradient (force) and Hessian (tangent), for
//! the two models of the project's theory document (`docs/theory.md`).
//!
//! Per element of length `l`, with centreline fields `u, v, w` at `η = ζ = 0`
//! and `' = d/dx`:
//! - `ū'` = element mean of `u'` (constant for the linear axial field), `s̄` =
//!   element mean of `v'² + w'²`;
//! - second-order: `U_e = E A l (½ ū' s̄ + ⅛ s̄²)`;
//! - fourth-order: `U_e = ½ E A l (ε̄² − ū'²)` with `ε̄ = ū' + ½ ū'² + ½ s̄`, plus
//!   `½ ∫₀ˡ g (E I_z v'v'' + E I_y w'w'') dx` with `g = v'v'' + w'w''`.
//!
//! The gradient and Hessian are worked out here by hand: the axial part as a
//! function `φ(d, s)` of the two element scalars `d = ū' = ā·q_e` and
//! `s = s̄ = q_eᵀ B q_e`; the bending part at each quadrature point as a
//! function `ψ(y)` of `y = (v', v'', w', w'') = J q_e`, so that its gradient is
//! `Jᵀ ∂ψ/∂y` and its Hessian `Jᵀ (∂²ψ/∂y²) J` (the map is linear).

use super::{gauss_legendre, RefBody};
use nalgebra::{DMatrix, DVector, Matrix4, RowDVector, Vector4};

/// What the nonlinear strain energy `U_nl` contains.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StiffeningModel {
    /// von Kármán: element-mean axial strain `ε̄ = ū' + ½ s̄`, linear bending.
    SecondOrder,
    /// Green–Lagrange element-mean axial strain `ε̄ = ū' + ½ ū'² + ½ s̄` and the
    /// curvature of an inextensible centreline to fourth order in bending.
    FourthOrder,
}

/// Gauss–Legendre points per element for the mean `s̄`: `v'² + w'²` has
/// degree 4 in ξ, and 3 points integrate degree ≤ 5 exactly.
pub const N_MEAN: usize = 3;

/// Gauss–Legendre points per element for the fourth-order bending part:
/// `v''·v'·(v'v'' + w'w'')` has degree 1 + 2 + 3 = 6 in ξ (v'' linear, v'
/// quadratic), and 4 points integrate degree ≤ 7 exactly.
pub const N_BEND: usize = 4;

/// `U_nl` split into its axial (element-mean strain) and bending parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffeningEnergy {
    /// `Σ_e E A l (½ ū' s̄ + ⅛ s̄²)` or `Σ_e ½ E A l (ε̄² − ū'²)`.
    pub axial: f64,
    /// `½ ∫ g (E I_z v'v'' + E I_y w'w'') dx` (fourth-order; 0 for second-order).
    pub bending: f64,
}

impl StiffeningEnergy {
    /// `axial + bending`.
    pub fn total(&self) -> f64 {
        self.axial + self.bending
    }
}

/// Element data, the same for every element of a body (the fields do not
/// depend on the element offset).
struct ElemStiff {
    /// `E A l`.
    ea_l: f64,
    /// `ū' = ā·q_e`.
    abar: DVector<f64>,
    /// `s̄ = q_eᵀ B q_e`, `B = ∫₀¹ (b bᵀ + c cᵀ) dξ`.
    bm: DMatrix<f64>,
    /// `E I_z`, `E I_y`.
    ei_z: f64,
    ei_y: f64,
    /// Bending quadrature: `(l·w_i, J_i)` with `J_i` the 4 × n_e rows of
    /// `(v', v'', w', w'')` at ξ_i.
    bend: Vec<(f64, DMatrix<f64>)>,
}

/// Derivatives of the axial density `φ(d, s)` (energy per `E A l`).
struct AxialDensity {
    phi: f64,
    d: f64,
    s: f64,
    dd: f64,
    ds: f64,
    ss: f64,
}

impl AxialDensity {
    fn new(model: StiffeningModel, d: f64, s: f64) -> Self {
        match model {
            // φ = ½ d s + ⅛ s²
            StiffeningModel::SecondOrder => Self {
                phi: 0.5 * d * s + 0.125 * s * s,
                d: 0.5 * s,
                s: 0.5 * d + 0.25 * s,
                dd: 0.0,
                ds: 0.5,
                ss: 0.25,
            },
            // φ = ½ (ε² − d²), ε = d + ½ d² + ½ s: ∂ε/∂d = 1 + d, ∂ε/∂s = ½.
            StiffeningModel::FourthOrder => {
                let eps = d + 0.5 * d * d + 0.5 * s;
                let e_d = 1.0 + d;
                Self {
                    // ε² − d² = (ε − d)(ε + d) avoids cancelling the large ū'² terms.
                    phi: 0.5 * (0.5 * d * d + 0.5 * s) * (eps + d),
                    // ε (1 + d) − d and (1 + d)² + ε − 1, written without cancellation.
                    d: 0.5 * d * d + 0.5 * s + d * eps,
                    s: 0.5 * eps,
                    dd: 2.0 * d + d * d + eps,
                    ds: 0.5 * e_d,
                    ss: 0.25,
                }
            }
        }
    }
}

/// Bending density `ψ(y) = ½ g p` at one point, `y = (v', v'', w', w'')`,
/// `g = v'v'' + w'w''`, `p = E I_z v'v'' + E I_y w'w''`; returns
/// `(ψ, ∂ψ/∂y, ∂²ψ/∂y²)`.
fn bending_density(y: &Vector4<f64>, ei_z: f64, ei_y: f64) -> (f64, Vector4<f64>, Matrix4<f64>) {
    let (v1, v2, w1, w2) = (y[0], y[1], y[2], y[3]);
    let g = v1 * v2 + w1 * w2;
    let p = ei_z * v1 * v2 + ei_y * w1 * w2;
    let dg = Vector4::new(v2, v1, w2, w1);
    let dp = Vector4::new(ei_z * v2, ei_z * v1, ei_y * w2, ei_y * w1);
    #[rustfmt::skip]
    let hg = Matrix4::new(
        0.0, 1.0, 0.0, 0.0,
        1.0, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        0.0, 0.0, 1.0, 0.0,
    );
    #[rustfmt::skip]
    let hp = Matrix4::new(
        0.0, ei_z, 0.0, 0.0,
        ei_z, 0.0, 0.0, 0.0,
        0.0, 0.0, 0.0, ei_y,
        0.0, 0.0, ei_y, 0.0,
    );
    let psi = 0.5 * g * p;
    let grad = 0.5 * (g * dp + p * dg);
    let hess = 0.5 * (dp * dg.transpose() + dg * dp.transpose()) + 0.5 * (p * hg + g * hp);
    (psi, grad, hess)
}

/// One element's contribution: energy parts, gradient and (optionally) Hessian in `q_e`.
struct ElemResult {
    axial: f64,
    bending: f64,
    grad: DVector<f64>,
    hess: Option<DMatrix<f64>>,
}

impl ElemStiff {
    fn eval(&self, model: StiffeningModel, qe: &DVector<f64>, hessian: bool) -> ElemResult {
        let ne = qe.len();
        // Axial: φ(d, s), ∇d = ā, ∇s = 2 B q, ∇²s = 2 B.
        let d = self.abar.dot(qe);
        let bq = &self.bm * qe;
        let s = qe.dot(&bq);
        let ds = 2.0 * &bq;
        let a = AxialDensity::new(model, d, s);
        let mut grad = self.ea_l * (a.d * &self.abar + a.s * &ds);
        let mut hess = hessian.then(|| {
            self.ea_l
                * (a.dd * &self.abar * self.abar.transpose()
                    + a.ds * (&self.abar * ds.transpose() + &ds * self.abar.transpose())
                    + a.ss * &ds * ds.transpose()
                    + (2.0 * a.s) * &self.bm)
        });
        let axial = self.ea_l * a.phi;

        let mut bending = 0.0;
        if model == StiffeningModel::FourthOrder {
            for (wl, j) in &self.bend {
                let y = Vector4::from_iterator((j * qe).iter().copied());
                let (psi, gy, hy) = bending_density(&y, self.ei_z, self.ei_y);
                bending += wl * psi;
                grad += *wl * j.transpose() * gy;
                if let Some(h) = hess.as_mut() {
                    let hy = DMatrix::from_column_slice(4, 4, hy.as_slice());
                    *h += *wl * j.transpose() * hy * j;
                }
            }
        }
        debug_assert_eq!(grad.len(), ne);
        ElemResult {
            axial,
            bending,
            grad,
            hess,
        }
    }
}

impl RefBody {
    fn elem_stiff(&self) -> ElemStiff {
        let l = self.l();
        let p = &self.params;
        let ne = self.shape.elem_dofs();
        let mut abar = DVector::zeros(ne);
        let mut bm = DMatrix::zeros(ne, ne);
        for &(xi, w) in &gauss_legendre(N_MEAN, 0.0, 1.0) {
            let (a, b, c) = self.shape.centerline_grad(l, xi);
            abar += w * a;
            bm += w * (&b * b.transpose() + &c * c.transpose());
        }
        let bend = gauss_legendre(N_BEND, 0.0, 1.0)
            .into_iter()
            .map(|(xi, w)| {
                let (_, b, c) = self.shape.centerline_grad(l, xi);
                let (b2, c2) = self.shape.centerline_curv(l, xi);
                let rows: [RowDVector<f64>; 4] =
                    [b.transpose(), b2.transpose(), c.transpose(), c2.transpose()];
                (l * w, DMatrix::from_rows(&rows))
            })
            .collect();
        ElemStiff {
            ea_l: p.e * p.area() * l,
            abar,
            bm,
            ei_z: p.e * p.iz(),
            ei_y: p.e * p.iy(),
            bend,
        }
    }

    /// Calls `f(map, result)` for every element at `q_f`.
    fn each_stiff(
        &self,
        model: StiffeningModel,
        q_f: &[f64],
        hessian: bool,
        mut f: impl FnMut(&[Option<usize>], ElemResult),
    ) {
        self.check_q(q_f);
        let data = self.elem_stiff();
        let full = self.dof_map();
        for e in 0..self.elements {
            let map = self.elem_map(&full, e);
            let qe = Self::gather(&map, q_f);
            f(&map, data.eval(model, &qe, hessian));
        }
    }

    /// `U_nl` of `model` at `q_f`, split into axial and bending parts.
    pub fn stiffening_energy_parts(&self, model: StiffeningModel, q_f: &[f64]) -> StiffeningEnergy {
        let mut r = StiffeningEnergy {
            axial: 0.0,
            bending: 0.0,
        };
        self.each_stiff(model, q_f, false, |_, e| {
            r.axial += e.axial;
            r.bending += e.bending;
        });
        r
    }

    /// `U_nl` of `model` at `q_f` (energy beyond `½ q_fᵀ K_ff q_f`).
    pub fn stiffening_energy_with(&self, model: StiffeningModel, q_f: &[f64]) -> f64 {
        self.stiffening_energy_parts(model, q_f).total()
    }

    /// `∂U_nl/∂q_f` of `model`.
    pub fn stiffening_force_with(&self, model: StiffeningModel, q_f: &[f64]) -> DVector<f64> {
        let mut f = DVector::zeros(self.nf());
        self.each_stiff(model, q_f, false, |map, e| {
            Self::scatter_vec(map, &e.grad, &mut f)
        });
        f
    }

    /// `∂²U_nl/∂q_f²` of `model`.
    pub fn stiffening_tangent_with(&self, model: StiffeningModel, q_f: &[f64]) -> DMatrix<f64> {
        let nf = self.nf();
        let mut h = DMatrix::zeros(nf, nf);
        self.each_stiff(model, q_f, true, |map, e| {
            Self::scatter_mat(map, e.hess.as_ref().expect("hessian requested"), &mut h)
        });
        h
    }

    /// Second-order `U_nl = Σ_e E A l (½ ū' s̄ + ⅛ s̄²)`: the strain energy of the
    /// element-mean axial strain `ε̄ = ū' + ½ s̄` beyond its linear part, where
    /// `ū'` and `s̄` are the element means of `u'` and `v'² + w'²`.
    pub fn stiffening_energy(&self, q_f: &[f64]) -> f64 {
        self.stiffening_energy_with(StiffeningModel::SecondOrder, q_f)
    }

    /// Second-order `∂U_nl/∂q = Σ_e E A l (½ s̄ ā + P̄ B q)`, `P̄ = ū' + ½ s̄`.
    pub fn stiffening_force(&self, q_f: &[f64]) -> DVector<f64> {
        self.stiffening_force_with(StiffeningModel::SecondOrder, q_f)
    }

    /// Second-order `∂²U_nl/∂q² = Σ_e E A l (ā (Bq)ᵀ + Bq āᵀ + Bq (Bq)ᵀ + P̄ B)`.
    pub fn stiffening_tangent(&self, q_f: &[f64]) -> DMatrix<f64> {
        self.stiffening_tangent_with(StiffeningModel::SecondOrder, q_f)
    }
}
