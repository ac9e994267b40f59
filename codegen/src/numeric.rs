//! The generated programs evaluated in `f64`, in the emitted code's operation
//! order: the numbers the compiled code computes, without compiling it (the
//! command line's `invariants --json`).

use crate::error::Error;
use crate::generate::Generated;
use crate::poly::Param;
use crate::program::Target;

/// Values of a body's runtime parameters (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamValues {
    /// Body length `L`.
    pub length: f64,
    /// Density `ρ`.
    pub rho: f64,
    /// Area `A`.
    pub area: f64,
    /// `I_y`.
    pub iy: f64,
    /// `I_z`.
    pub iz: f64,
    /// Young's modulus `E`.
    pub e: f64,
    /// Shear modulus `G`.
    pub g: f64,
    /// Torsion constant `J`.
    pub j: f64,
}

impl ParamValues {
    /// In [`Param::FIELDS`] order.
    pub fn to_array(&self) -> [f64; 8] {
        [
            self.length,
            self.rho,
            self.area,
            self.iy,
            self.iz,
            self.e,
            self.g,
            self.j,
        ]
    }

    /// Every value finite, and the length strictly positive (it divides).
    pub fn validate(&self) -> Result<(), Error> {
        for (p, v) in Param::FIELDS.iter().zip(self.to_array()) {
            if !v.is_finite() {
                return Err(Error::Body(format!(
                    "parameter `{}` must be finite, found {v}",
                    p.field()
                )));
            }
        }
        if self.length <= 0.0 {
            return Err(Error::Body(format!(
                "parameter `length` must be positive, found {}",
                self.length
            )));
        }
        Ok(())
    }
}

/// Invariants as plain numbers; `k, l` index x, y, z.
#[derive(Clone, Debug, PartialEq)]
pub struct NumericInvariants {
    /// 2 or 3.
    pub dim: usize,
    /// Labels of the elastic coordinates.
    pub dofs: Vec<String>,
    /// `m`.
    pub mass: f64,
    /// `S_t0`.
    pub s_t0: [f64; 3],
    /// `S̄`, 3 rows of n_f.
    pub s_bar: Vec<Vec<f64>>,
    /// `S̄_kl`, n_f × n_f each.
    pub s_kl: [[Vec<Vec<f64>>; 3]; 3],
    /// `Ī_kl`, n_f each.
    pub i_kl: [[Vec<f64>; 3]; 3],
    /// `Θ_kl`.
    pub theta: [[f64; 3]; 3],
    /// `m_ff`.
    pub m_ff: Vec<Vec<f64>>,
    /// `K_ff`.
    pub k_ff: Vec<Vec<f64>>,
}

/// `S_t`, `Ī_θθ`, `Ī_θf` as plain numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct NumericInertia {
    /// `S_t(q)`.
    pub s_t: [f64; 3],
    /// `Ī_θθ(q)`.
    pub i_theta_theta: [[f64; 3]; 3],
    /// `Ī_θf(q)`, 3 rows of n_f.
    pub i_theta_f: Vec<Vec<f64>>,
}

impl Generated {
    /// Evaluate `invariants()` as the emitted code does.
    pub fn eval_invariants(&self, p: &ParamValues) -> NumericInvariants {
        let nf = self.dofs.len();
        let sq = || vec![vec![0.0; nf]; nf];
        let mut r = NumericInvariants {
            dim: self.exact.dim,
            dofs: self.dofs.iter().map(|d| d.to_string()).collect(),
            mass: 0.0,
            s_t0: [0.0; 3],
            s_bar: vec![vec![0.0; nf]; 3],
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| sq())),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; nf])),
            theta: [[0.0; 3]; 3],
            m_ff: sq(),
            k_ff: sq(),
        };
        for (t, v) in self.invariants.eval(&p.to_array(), &[]) {
            match t {
                Target::Mass => r.mass = v,
                Target::St0(k) => r.s_t0[k] = v,
                Target::SBar(k, a) => r.s_bar[k][a] = v,
                Target::Skl(k, l, a, b) => {
                    r.s_kl[k][l][a][b] = v;
                    r.s_kl[l][k][b][a] = v;
                }
                Target::Ikl(k, l, a) => r.i_kl[k][l][a] = v,
                Target::Theta(k, l) => {
                    r.theta[k][l] = v;
                    r.theta[l][k] = v;
                }
                Target::Mff(a, b) => {
                    r.m_ff[a][b] = v;
                    r.m_ff[b][a] = v;
                }
                Target::Kff(a, b) => {
                    r.k_ff[a][b] = v;
                    r.k_ff[b][a] = v;
                }
                other => unreachable!("{other:?} among invariants"),
            }
        }
        r
    }

    /// Evaluate `inertia_terms(q_f)` as the emitted code does.
    pub fn eval_inertia(&self, p: &ParamValues, q: &[f64]) -> NumericInertia {
        let nf = self.dofs.len();
        assert_eq!(q.len(), nf, "q_f must have {nf} entries");
        let mut r = NumericInertia {
            s_t: [0.0; 3],
            i_theta_theta: [[0.0; 3]; 3],
            i_theta_f: vec![vec![0.0; nf]; 3],
        };
        for (t, v) in self.inertia.eval(&p.to_array(), q) {
            match t {
                Target::St(k) => r.s_t[k] = v,
                Target::ItTheta(k, l) => {
                    r.i_theta_theta[k][l] = v;
                    r.i_theta_theta[l][k] = v;
                }
                Target::ItF(k, a) => r.i_theta_f[k][a] = v,
                other => unreachable!("{other:?} among inertia terms"),
            }
        }
        r
    }

    /// Evaluate the stiffening force and tangent (zero if not generated).
    pub fn eval_stiffening(&self, p: &ParamValues, q: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
        let nf = self.dofs.len();
        let mut f = vec![0.0; nf];
        let mut k = vec![vec![0.0; nf]; nf];
        if let (Some(fp), Some(tp)) = (&self.stiffening_force, &self.stiffening_tangent) {
            for (t, v) in fp.eval(&p.to_array(), q) {
                if let Target::Force(a) = t {
                    f[a] += v;
                }
            }
            for (t, v) in tp.eval(&p.to_array(), q) {
                if let Target::Tangent(a, b) = t {
                    k[a][b] += v;
                    if a != b {
                        k[b][a] += v;
                    }
                }
            }
        }
        (f, k)
    }
}
