//! Force elements acting at markers, with their derivatives.
//!
//! A global force `F` at a marker maps to `Q = J_pᵀ F` with `J_p = ∂p/∂q`
//! (`[I, ∂(A ū)/∂θ, A S_P]`); its derivative is `∂Q/∂q = Σ_k F_k ∂²p_k/∂q²`.

use crate::marker::{Marker, MarkerKin};
use nalgebra::Vector3;
use std::fmt;
use std::sync::Arc;

/// A time-dependent vector.
pub type VectorFn = Arc<dyn Fn(f64) -> Vector3<f64> + Send + Sync>;

/// A force element.
#[derive(Clone)]
pub enum ForceElement {
    /// A global force `F(t)` at a marker.
    Point {
        /// Where it acts.
        marker: Marker,
        /// The force (global axes) as a function of time.
        force: VectorFn,
    },
    /// A linear spring–damper along the line of two markers: tension
    /// `f = k (l − l₀) + c l̇`, force `f e` on `a` and `−f e` on `b`, `e = (p_b − p_a)/l`.
    SpringDamper {
        /// First end.
        a: Marker,
        /// Second end.
        b: Marker,
        /// Stiffness `k` (N/m).
        stiffness: f64,
        /// Damping `c` (N s/m).
        damping: f64,
        /// Rest length `l₀` (m).
        rest_length: f64,
    },
}

impl fmt::Debug for ForceElement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ForceElement::Point { marker, .. } => write!(f, "Point({:?})", marker.body),
            ForceElement::SpringDamper {
                a,
                b,
                stiffness,
                damping,
                rest_length,
            } => write!(
                f,
                "SpringDamper({:?}, {:?}, k={stiffness}, c={damping}, l0={rest_length})",
                a.body, b.body
            ),
        }
    }
}

impl ForceElement {
    /// The markers it acts at: the first, and the second if it has one.
    pub fn markers(&self) -> (&Marker, Option<&Marker>) {
        match self {
            ForceElement::Point { marker, .. } => (marker, None),
            ForceElement::SpringDamper { a, b, .. } => (a, Some(b)),
        }
    }
}

/// Workspace and result of one force element's evaluation over its local
/// coordinates (those of its first marker, then its second).
pub(crate) struct ForceEval {
    /// Generalized force `Q` (local).
    pub q: Vec<f64>,
    /// `−∂Q/∂q − γ' ∂Q/∂q̇` (local, row-major), when asked for.
    pub k: Vec<f64>,
    /// Potential energy (springs).
    pub energy: f64,
    dv: Vec<Vector3<f64>>,
}

impl ForceEval {
    pub fn new(n: usize) -> Self {
        Self {
            q: vec![0.0; n],
            k: vec![0.0; n * n],
            energy: 0.0,
            dv: vec![Vector3::zeros(); n],
        }
    }

    /// Evaluate `fe` with marker kinematics `ka` (and `kb`), local velocities
    /// `qd`; with `gp = Some(γ')` also the tangent.
    pub fn eval(
        &mut self,
        fe: &ForceElement,
        ka: &MarkerKin,
        kb: Option<&MarkerKin>,
        t: f64,
        qd: &[f64],
        gp: Option<f64>,
    ) {
        let n = self.q.len();
        self.q.iter_mut().for_each(|x| *x = 0.0);
        self.energy = 0.0;
        if gp.is_some() {
            self.k.iter_mut().for_each(|x| *x = 0.0);
        }
        match fe {
            ForceElement::Point { force, .. } => {
                let f = force(t);
                for i in 0..n {
                    self.q[i] = ka.dpos[i].dot(&f);
                }
                if gp.is_some() {
                    for i in 0..n {
                        for j in 0..n {
                            self.k[i * n + j] = -ka.d2pos(i, j).dot(&f);
                        }
                    }
                }
            }
            ForceElement::SpringDamper {
                stiffness,
                damping,
                rest_length,
                ..
            } => {
                let kb = kb.expect("a spring–damper has two markers");
                let na = ka.len();
                // d = p_b − p_a over the local coordinates [a…, b…].
                let dvec = kb.pos - ka.pos;
                for i in 0..na {
                    self.dv[i] = -ka.dpos[i];
                }
                for i in 0..kb.len() {
                    self.dv[na + i] = kb.dpos[i];
                }
                let d2 = |i: usize, j: usize| -> Vector3<f64> {
                    match (i < na, j < na) {
                        (true, true) => -ka.d2pos(i, j),
                        (false, false) => kb.d2pos(i - na, j - na),
                        _ => Vector3::zeros(),
                    }
                };
                let l = dvec.norm();
                self.energy = 0.5 * stiffness * (l - rest_length).powi(2);
                if l <= f64::EPSILON * (1.0 + rest_length.abs()) {
                    // Coincident ends: no line of action, no force.
                    return;
                }
                let e = dvec / l;
                let ddot: Vector3<f64> = (0..n).map(|i| self.dv[i] * qd[i]).sum();
                let ldot = e.dot(&ddot);
                let f = stiffness * (l - rest_length) + damping * ldot;
                let fe_vec = e * f;
                for i in 0..n {
                    self.q[i] = -self.dv[i].dot(&fe_vec);
                }
                if let Some(gp) = gp {
                    // P = (I − e eᵀ)/l.
                    let p = |v: &Vector3<f64>| (v - e * e.dot(v)) / l;
                    let pddot = p(&ddot);
                    for j in 0..n {
                        let dj = self.dv[j];
                        let c_j: Vector3<f64> = (0..n).map(|i| d2(i, j) * qd[i]).sum();
                        let dldot = pddot.dot(&dj) + e.dot(&c_j);
                        let df = stiffness * e.dot(&dj) + damping * dldot;
                        let dfe = e * df + p(&dj) * f;
                        let dfe_v = e * (damping * e.dot(&dj));
                        for i in 0..n {
                            // −∂Q_i/∂q_j − γ' ∂Q_i/∂q̇_j with Q_i = −dv_i · (f e).
                            self.k[i * n + j] = d2(i, j).dot(&fe_vec)
                                + self.dv[i].dot(&dfe)
                                + gp * self.dv[i].dot(&dfe_v);
                        }
                    }
                }
            }
        }
    }
}
