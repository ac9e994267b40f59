//! Invariants as `f64` (nalgebra), correctly rounded from the exact ones, and
//! their projection onto a modal basis.

// Tensor code over coordinate and axis indices (`k`, `l`, `a`, `b` as in
// the theory): index loops read closer to the formulas than iterators.
#![allow(clippy::needless_range_loop)]

use super::ModalError;
use crate::body::{ExactInvariants, PolyMatrix};
use crate::poly::{to_f64, Monomial, Param, Poly, Rational, Sym};
use ffr_spec::Params;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use num_traits::{One, Zero};
use std::collections::BTreeMap;

/// The invariants of a body (or of a reduced body) as numbers; names and
/// index order as in [`ExactInvariants`] (`k, l ∈ {x, y, z}`; a planar
/// body's z components are zero).
///
/// The same struct describes the full nodal body (`n_f` nodal coordinates,
/// from [`Invariants::from_exact`]) and a modal body (`n_f = k` modal
/// coordinates, from [`Invariants::project`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Invariants {
    /// 2 or 3.
    pub dim: usize,
    /// `m`.
    pub mass: f64,
    /// `S_t0`.
    pub s_t0: Vector3<f64>,
    /// `S̄`, 3 × n_f.
    pub s_bar: DMatrix<f64>,
    /// `S̄_kl`, n_f × n_f each; `S̄_lk = S̄_klᵀ` exactly.
    pub s_kl: [[DMatrix<f64>; 3]; 3],
    /// `Ī_kl` (a row of n_f, stored as a column vector).
    pub i_kl: [[DVector<f64>; 3]; 3],
    /// `Θ_kl` (symmetric).
    pub theta: Matrix3<f64>,
    /// `m_ff` (symmetric).
    pub m_ff: DMatrix<f64>,
    /// `K_ff` (symmetric).
    pub k_ff: DMatrix<f64>,
}

/// Exact values of the parameters and of the parameter monomials met so far.
struct ExactParams {
    values: [Rational; 8],
    /// The element length `l = L/N` of a body of `N` equal elements, for
    /// polynomials in `l` (`None`: they must not contain it).
    elem_length: Option<Rational>,
    cache: BTreeMap<Monomial, Rational>,
}

impl ExactParams {
    fn new(p: &Params) -> Result<Self, ModalError> {
        let mut values: [Rational; 8] = std::array::from_fn(|_| Rational::zero());
        for (i, (param, v)) in Param::FIELDS.iter().zip(p.to_array()).enumerate() {
            values[i] = Rational::from_float(v).ok_or_else(|| {
                ModalError::Input(format!(
                    "parameter `{}` must be finite, found {v}",
                    param.field()
                ))
            })?;
        }
        Ok(Self {
            values,
            elem_length: None,
            cache: BTreeMap::new(),
        })
    }

    /// With the element length `l = L/N` of `elements` equal elements.
    fn with_elements(p: &Params, elements: usize) -> Result<Self, ModalError> {
        let mut x = Self::new(p)?;
        let n = i64::try_from(elements)
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| ModalError::Input(format!("{elements} elements")))?;
        x.elem_length = Some(
            x.values[Param::Length.field_index().expect("a field")].clone()
                / Rational::from_integer(n.into()),
        );
        Ok(x)
    }

    /// The exact value of a monomial in the parameters; `None` for a symbol
    /// that is not a runtime parameter.
    fn monomial(&mut self, m: &Monomial) -> Result<Option<Rational>, ModalError> {
        if let Some(v) = self.cache.get(m) {
            return Ok(Some(v.clone()));
        }
        let mut v = Rational::one();
        for &(s, e) in m.factors() {
            let Sym::Param(param) = s else {
                return Ok(None);
            };
            let base = match (param.field_index(), &self.elem_length) {
                (Some(i), _) => &self.values[i],
                (None, Some(l)) if param == Param::ElemLength => l,
                _ => {
                    return Err(ModalError::Eval {
                        poly: m.to_string(),
                        reason: format!(
                            "`{}` is the element length, which a body's invariants do not contain",
                            param.field()
                        ),
                    })
                }
            };
            if e < 0 && base.is_zero() {
                return Err(ModalError::Eval {
                    poly: m.to_string(),
                    reason: format!("parameter `{}` is zero and divides", param.field()),
                });
            }
            let f = if e >= 0 {
                num_traits::pow(base.clone(), e as usize)
            } else {
                num_traits::pow(base.recip(), (-e) as usize)
            };
            v *= f;
        }
        self.cache.insert(m.clone(), v.clone());
        Ok(Some(v))
    }

    /// `poly` at the parameters, exact.
    fn eval(&mut self, poly: &Poly) -> Result<Rational, ModalError> {
        let mut sum = Rational::zero();
        for (m, c) in poly.terms() {
            match self.monomial(m)? {
                Some(v) => sum += v * c,
                None => {
                    return Err(ModalError::Eval {
                        poly: poly.to_string(),
                        reason: format!(
                            "the term `{m}` has a symbol other than the runtime parameters"
                        ),
                    })
                }
            }
        }
        Ok(sum)
    }

    fn eval_f64(&mut self, poly: &Poly) -> Result<f64, ModalError> {
        if poly.is_zero() {
            return Ok(0.0);
        }
        Ok(to_f64(&self.eval(poly)?))
    }

    /// A square matrix known to be symmetric: the upper triangle evaluated,
    /// mirrored.
    fn symmetric(&mut self, m: &PolyMatrix) -> Result<DMatrix<f64>, ModalError> {
        let n = m.rows;
        let mut out = DMatrix::zeros(n, n);
        for i in 0..n {
            for j in i..n {
                let v = self.eval_f64(m.get(i, j))?;
                out[(i, j)] = v;
                out[(j, i)] = v;
            }
        }
        Ok(out)
    }

    fn full(&mut self, m: &PolyMatrix) -> Result<DMatrix<f64>, ModalError> {
        let mut out = DMatrix::zeros(m.rows, m.cols);
        for i in 0..m.rows {
            for j in 0..m.cols {
                out[(i, j)] = self.eval_f64(m.get(i, j))?;
            }
        }
        Ok(out)
    }
}

/// The value of a polynomial in the runtime parameters at `p`: evaluated
/// exactly (each parameter is the exact rational its `f64` denotes) and
/// rounded once to the nearest `f64`.
pub fn eval_poly(poly: &Poly, p: &Params) -> Result<f64, ModalError> {
    ExactParams::new(p)?.eval_f64(poly)
}

/// `(A + Aᵀ)/2`: exactly symmetric, and `A` itself when `A` already is.
fn symmetrize(a: DMatrix<f64>) -> DMatrix<f64> {
    let t = a.transpose();
    (a + t) * 0.5
}

impl Invariants {
    /// Number of (nodal or modal) elastic coordinates.
    pub fn nf(&self) -> usize {
        self.m_ff.nrows()
    }

    /// The exact invariants at parameter values `p`, each entry correctly
    /// rounded (see [`eval_poly`]). Symmetric matrices (`m_ff`, `K_ff`,
    /// `S̄_kk`, `Θ`) are evaluated on one triangle and mirrored; `S̄_lk` is
    /// set to `S̄_klᵀ` (both hold exactly for the exact invariants).
    pub fn from_exact(exact: &ExactInvariants, p: &Params) -> Result<Self, ModalError> {
        Self::evaluate(exact, ExactParams::new(p)?)
    }

    /// [`Invariants::from_exact`] of invariants in the element length
    /// (`BodySpec::exact_invariants_in_element_length`) of a body of
    /// `elements` equal elements: evaluated at `l = L/N` exactly, so the
    /// same bits as `from_exact` of `BodySpec::exact_invariants`.
    pub fn from_exact_elements(
        exact: &ExactInvariants,
        p: &Params,
        elements: usize,
    ) -> Result<Self, ModalError> {
        Self::evaluate(exact, ExactParams::with_elements(p, elements)?)
    }

    fn evaluate(exact: &ExactInvariants, mut x: ExactParams) -> Result<Self, ModalError> {
        let nf = exact.nf;
        let mass = x.eval_f64(&exact.mass)?;
        let mut s_t0 = Vector3::zeros();
        let mut theta = Matrix3::zeros();
        for k in 0..3 {
            s_t0[k] = x.eval_f64(&exact.s_t0[k])?;
            for l in k..3 {
                let v = x.eval_f64(&exact.theta[k][l])?;
                theta[(k, l)] = v;
                theta[(l, k)] = v;
            }
        }
        let s_bar = x.full(&exact.s_bar)?;
        let mut s_kl: [[DMatrix<f64>; 3]; 3] =
            std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(nf, nf)));
        for k in 0..3 {
            s_kl[k][k] = x.symmetric(&exact.s_kl[k][k])?;
            for l in k + 1..3 {
                let m = x.full(&exact.s_kl[k][l])?;
                s_kl[l][k] = m.transpose();
                s_kl[k][l] = m;
            }
        }
        let mut i_kl: [[DVector<f64>; 3]; 3] =
            std::array::from_fn(|_| std::array::from_fn(|_| DVector::zeros(nf)));
        for k in 0..3 {
            for l in 0..3 {
                for a in 0..nf {
                    i_kl[k][l][a] = x.eval_f64(&exact.i_kl[k][l][a])?;
                }
            }
        }
        let m_ff = x.symmetric(&exact.m_ff)?;
        let k_ff = x.symmetric(&exact.k_ff)?;
        Ok(Self {
            dim: exact.dim,
            mass,
            s_t0,
            s_bar,
            s_kl,
            i_kl,
            theta,
            m_ff,
            k_ff,
        })
    }

    /// The invariants of the body reduced by `q_f = Φ η` (`phi`: n_f × k):
    /// `m`, `S_t0`, `Θ` unchanged; `S̄Φ`, `Φᵀ S̄_kl Φ`, `Φᵀ Ī_klᵀ` (i.e. the
    /// row `Ī_kl Φ`), `Φᵀ m_ff Φ`, `Φᵀ K_ff Φ`. Symmetric results are
    /// symmetrized (`(A + Aᵀ)/2`), `S̄_lk` set to the transpose of `S̄_kl`, so
    /// the identities of the full body hold exactly.
    ///
    /// # Panics
    /// If `phi` does not have `n_f` rows.
    pub fn project(&self, phi: &DMatrix<f64>) -> Self {
        assert_eq!(
            phi.nrows(),
            self.nf(),
            "the basis must have one row per elastic coordinate ({}), found {}",
            self.nf(),
            phi.nrows()
        );
        let pt = phi.transpose();
        let k = phi.ncols();
        let sandwich = |m: &DMatrix<f64>| &pt * m * phi;
        let mut s_kl: [[DMatrix<f64>; 3]; 3] =
            std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(k, k)));
        for a in 0..3 {
            s_kl[a][a] = symmetrize(sandwich(&self.s_kl[a][a]));
            for b in a + 1..3 {
                let m = sandwich(&self.s_kl[a][b]);
                s_kl[b][a] = m.transpose();
                s_kl[a][b] = m;
            }
        }
        Self {
            dim: self.dim,
            mass: self.mass,
            s_t0: self.s_t0,
            s_bar: &self.s_bar * phi,
            s_kl,
            i_kl: std::array::from_fn(|a| std::array::from_fn(|b| &pt * &self.i_kl[a][b])),
            theta: self.theta,
            m_ff: symmetrize(sandwich(&self.m_ff)),
            k_ff: symmetrize(sandwich(&self.k_ff)),
        }
    }

    /// The inertia tensor about the body-frame origin of the undeformed body,
    /// `Ī_θθ(0) = tr(Θ) I − Θ`.
    pub fn inertia_tensor(&self) -> Matrix3<f64> {
        Matrix3::identity() * self.theta.trace() - self.theta
    }

    /// `Ī_θf` of the undeformed body (3 × n_f): rows `Ī_yz − Ī_zy`,
    /// `Ī_zx − Ī_xz`, `Ī_xy − Ī_yx` (`∫ρ ũ₀ S dV`).
    pub fn i_theta_f(&self) -> DMatrix<f64> {
        let n = self.nf();
        let mut out = DMatrix::zeros(3, n);
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let row = &self.i_kl[b][c] - &self.i_kl[c][b];
            for j in 0..n {
                out[(a, j)] = row[j];
            }
        }
        out
    }
}
