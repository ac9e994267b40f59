//! Rigid bodies as [`FlexBody`]s with no elastic coordinates.

use crate::body::{FlexBody, InertiaTerms, Invariants};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3xX, Vector2, Vector3};

/// A rigid body: mass, centre of mass `c̄` and inertia tensor `J_c` about the
/// centre of mass, in body axes. Its invariants are `m`, `S_t0 = m c̄` and
/// `Θ = ∫ρ ū ūᵀ dV = ½ tr(J_o) I − J_o` with `J_o = J_c + m (c̄ᵀc̄ I − c̄ c̄ᵀ)`.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    dim: usize,
    mass: f64,
    com: Vector3<f64>,
    inertia: Matrix3<f64>,
}

impl RigidBody {
    /// A planar rigid body (motion in x–y) with mass `mass`, moment of inertia
    /// `j_zz` about its centre of mass, centre of mass at `com` in body axes.
    pub fn planar(mass: f64, j_zz: f64, com: Vector2<f64>) -> Self {
        // Planar body: all mass in the x-y plane, so J_xx + J_yy = J_zz;
        // split J_zz evenly (only J_zz enters planar dynamics).
        Self {
            dim: 2,
            mass,
            com: Vector3::new(com.x, com.y, 0.0),
            inertia: Matrix3::from_diagonal(&Vector3::new(0.5 * j_zz, 0.5 * j_zz, j_zz)),
        }
    }

    /// A spatial rigid body with inertia tensor `inertia` about its centre of mass `com`.
    pub fn spatial(mass: f64, inertia: Matrix3<f64>, com: Vector3<f64>) -> Self {
        Self {
            dim: 3,
            mass,
            com,
            inertia,
        }
    }

    /// `J_o`, the inertia tensor about the body-frame origin.
    pub fn inertia_about_origin(&self) -> Matrix3<f64> {
        self.inertia
            + (Matrix3::identity() * self.com.norm_squared() - self.com * self.com.transpose())
                * self.mass
    }
}

impl FlexBody for RigidBody {
    fn nf(&self) -> usize {
        0
    }
    fn dim(&self) -> usize {
        self.dim
    }
    fn dof_labels(&self) -> Vec<String> {
        Vec::new()
    }
    fn invariants(&self) -> Invariants {
        let jo = self.inertia_about_origin();
        let theta = Matrix3::identity() * (0.5 * jo.trace()) - jo;
        let z = DMatrix::zeros(0, 0);
        let zv = DVector::zeros(0);
        Invariants {
            dim: self.dim,
            mass: self.mass,
            s_t0: self.com * self.mass,
            s_bar: Matrix3xX::zeros(0),
            s_kl: std::array::from_fn(|_| std::array::from_fn(|_| z.clone())),
            i_kl: std::array::from_fn(|_| std::array::from_fn(|_| zv.clone())),
            theta,
            m_ff: z.clone(),
            k_ff: z,
        }
    }
    /// `S_t = m c̄`, `Ī_θθ = J_o`, `Ī_θf` empty.
    fn inertia_terms(&self, _q_f: &[f64], out: &mut InertiaTerms) {
        out.s_t = self.com * self.mass;
        out.i_theta_theta = self.inertia_about_origin();
        out.i_theta_f = Matrix3xX::zeros(0);
    }
}
