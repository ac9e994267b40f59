//! Force elements acting at markers, with their derivatives.
//!
//! A global force `F` at a marker maps to `Q = J_pᵀ F` with `J_p = ∂p/∂q`
//! (`[I, ∂(A ū)/∂θ, A S_P]`); its derivative is `∂Q/∂q = Σ_k F_k ∂²p_k/∂q²`.
//! A torque `τ` about `z_a` between two markers does the work `τ δφ` with the
//! relative angle `φ = atan2(x_b·y_a, x_b·x_a)` (the angle of `b`'s x axis
//! about `a`'s z axis): `Q = τ ∇φ`.

use crate::driver::Driver;
use crate::joint::{Row, RowEval, Side, Term, What};
use crate::marker::{Marker, MarkerKin};
use nalgebra::Vector3;
use std::fmt;
use std::sync::Arc;

/// A time-dependent vector.
pub type VectorFn = Arc<dyn Fn(f64) -> Vector3<f64> + Send + Sync>;

/// A torque law between two markers, in terms of their relative angle `φ`
/// about `z_a` and its rate `φ̇`.
#[derive(Clone)]
pub enum TorqueLaw {
    /// `τ = τ(t)` (a motor torque).
    Torque(Arc<dyn Fn(f64) -> f64 + Send + Sync>),
    /// `τ = u_k`: the value of the system's input `k` (held over a step;
    /// [`crate::System::add_input`]).
    Input(usize),
    /// `τ = −k (φ − φ₀) − c φ̇` (a rotational spring–damper; the angle
    /// difference is taken in `(−π, π]`).
    SpringDamper {
        /// Stiffness `k` (N m/rad).
        stiffness: f64,
        /// Damping `c` (N m s/rad).
        damping: f64,
        /// Rest angle `φ₀` (rad).
        rest_angle: f64,
    },
    /// `τ = k_p (φ*(t) − φ) + k_d (φ̇*(t) − φ̇)` (a PD-controlled motor; the
    /// angle error is taken in `(−π, π]`).
    Pd {
        /// Target angle `φ*(t)` with its rate.
        target: Driver,
        /// Proportional gain `k_p` (N m/rad).
        kp: f64,
        /// Derivative gain `k_d` (N m s/rad).
        kd: f64,
    },
}

/// The direction convention of a point force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForceAxes {
    /// `F` in global axes.
    Global,
    /// `F` in the marker's axes (a follower force turning with the body and
    /// its section).
    Marker,
}

/// A force element.
#[derive(Clone)]
pub enum ForceElement {
    /// A force `F(t)` at a marker, in global or marker axes.
    Point {
        /// Where it acts.
        marker: Marker,
        /// The force as a function of time.
        force: VectorFn,
        /// The axes `F` is given in.
        axes: ForceAxes,
    },
    /// A torque between two markers about `z_a` (equal and opposite).
    Torque {
        /// First marker (its z axis is the torque's axis).
        a: Marker,
        /// Second marker.
        b: Marker,
        /// The law.
        law: TorqueLaw,
    },
    /// A force `u_k d` at a marker: the value of the system's input `k`
    /// times a fixed direction `d` (global or marker axes).
    Input {
        /// Where it acts.
        marker: Marker,
        /// The direction `d` (the force per unit input).
        direction: Vector3<f64>,
        /// The axes `d` is given in.
        axes: ForceAxes,
        /// The input.
        input: usize,
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
            ForceElement::Point { marker, axes, .. } => {
                write!(f, "Point({:?}, {axes:?})", marker.body)
            }
            ForceElement::Torque { a, b, .. } => write!(f, "Torque({:?}, {:?})", a.body, b.body),
            ForceElement::Input {
                marker,
                axes,
                input,
                ..
            } => write!(f, "Input({:?}, {axes:?}, input {input})", marker.body),
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
            ForceElement::Point { marker, .. } | ForceElement::Input { marker, .. } => {
                (marker, None)
            }
            ForceElement::SpringDamper { a, b, .. } | ForceElement::Torque { a, b, .. } => {
                (a, Some(b))
            }
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
    /// The relative angle `φ` and rate `φ̇` of a torque element.
    pub angle: (f64, f64),
    /// The rate its damper acts on (`l̇` of a spring–damper, `φ̇` of a
    /// torque), 0 for a point force.
    pub rate: f64,
    dv: Vec<Vector3<f64>>,
    rows: [Row; 2],
    evals: [RowEval; 2],
    grad: Vec<f64>,
    hess: Vec<f64>,
}

/// The rows `s = x_b · y_a` and `c = x_b · x_a` of the relative angle.
fn angle_rows() -> [Row; 2] {
    let dot = |i: usize| Row {
        v1: vec![Term::new(1.0, Side::B, What::Axis(0))],
        v2: vec![Term::new(1.0, Side::A, What::Axis(i))],
        offset: None,
    };
    [dot(1), dot(0)]
}

/// `x` wrapped into `(−π, π]`.
fn wrap(x: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let y = x - tau * (x / tau).round();
    if y <= -std::f64::consts::PI {
        y + tau
    } else {
        y
    }
}

impl ForceEval {
    pub fn new(n: usize) -> Self {
        Self {
            q: vec![0.0; n],
            k: vec![0.0; n * n],
            energy: 0.0,
            angle: (0.0, 0.0),
            rate: 0.0,
            dv: vec![Vector3::zeros(); n],
            rows: angle_rows(),
            evals: [RowEval::new(n), RowEval::new(n)],
            grad: vec![0.0; n],
            hess: vec![0.0; n * n],
        }
    }

    /// Evaluate `fe` with marker kinematics `ka` (and `kb`), local velocities
    /// `qd`, the system's input values `inputs`; with `gp = Some(γ')` also
    /// the tangent.
    #[allow(clippy::too_many_arguments)]
    pub fn eval(
        &mut self,
        fe: &ForceElement,
        ka: &MarkerKin,
        kb: Option<&MarkerKin>,
        t: f64,
        qd: &[f64],
        gp: Option<f64>,
        inputs: &[f64],
    ) {
        let n = self.q.len();
        self.q.iter_mut().for_each(|x| *x = 0.0);
        self.energy = 0.0;
        self.rate = 0.0;
        if gp.is_some() {
            self.k.iter_mut().for_each(|x| *x = 0.0);
        }
        let point = match fe {
            ForceElement::Point { force, axes, .. } => Some((force(t), axes)),
            ForceElement::Input {
                direction,
                axes,
                input,
                ..
            } => Some((direction * inputs[*input], axes)),
            _ => None,
        };
        match fe {
            ForceElement::Point { .. } | ForceElement::Input { .. } => {
                let (f_loc, axes) = point.expect("a point force");
                let f = match axes {
                    ForceAxes::Global => f_loc,
                    ForceAxes::Marker => {
                        ka.axes[0] * f_loc.x + ka.axes[1] * f_loc.y + ka.axes[2] * f_loc.z
                    }
                };
                for i in 0..n {
                    self.q[i] = ka.dpos[i].dot(&f);
                }
                if gp.is_some() {
                    for i in 0..n {
                        for j in 0..n {
                            let mut kij = -ka.d2pos(i, j).dot(&f);
                            if *axes == ForceAxes::Marker {
                                // ∂F/∂q_j = Σ_k f_k ∂a_k/∂q_j.
                                let df = ka.daxes[0][j] * f_loc.x
                                    + ka.daxes[1][j] * f_loc.y
                                    + ka.daxes[2][j] * f_loc.z;
                                kij -= ka.dpos[i].dot(&df);
                            }
                            self.k[i * n + j] = kij;
                        }
                    }
                }
            }
            ForceElement::Torque { law, .. } => {
                let kb = kb.expect("a torque acts between two markers");
                for (row, ev) in self.rows.iter().zip(self.evals.iter_mut()) {
                    ev.eval(row, ka, kb, t);
                }
                let (sv, cv) = (self.evals[0].phi, self.evals[1].phi);
                let r2 = sv * sv + cv * cv;
                let phi = sv.atan2(cv);
                for i in 0..n {
                    self.grad[i] = (cv * self.evals[0].grad[i] - sv * self.evals[1].grad[i]) / r2;
                }
                let phid: f64 = (0..n).map(|i| self.grad[i] * qd[i]).sum();
                self.angle = (phi, phid);
                self.rate = phid;
                let (tau, dtau_dphi, dtau_dphid) = match law {
                    TorqueLaw::Torque(f) => (f(t), 0.0, 0.0),
                    TorqueLaw::Input(k) => (inputs[*k], 0.0, 0.0),
                    TorqueLaw::SpringDamper {
                        stiffness,
                        damping,
                        rest_angle,
                    } => {
                        let d = wrap(phi - rest_angle);
                        self.energy = 0.5 * stiffness * d * d;
                        (-stiffness * d - damping * phid, -stiffness, -damping)
                    }
                    TorqueLaw::Pd { target, kp, kd } => {
                        let [f, fd, _] = target.eval(t);
                        (kp * wrap(f - phi) + kd * (fd - phid), -kp, -kd)
                    }
                };
                for i in 0..n {
                    self.q[i] = tau * self.grad[i];
                }
                if let Some(gp) = gp {
                    // H_φ = (c H_s − s H_c)/r² + (∇s ∇cᵀ − ∇c ∇sᵀ)/r²
                    //       − 2 ∇φ (s ∇s + c ∇c)ᵀ / r².
                    let (es, ec) = (&self.evals[0], &self.evals[1]);
                    for i in 0..n {
                        for j in 0..n {
                            let hs = es.hess(&self.rows[0], ka, kb, t, i, j);
                            let hc = ec.hess(&self.rows[1], ka, kb, t, i, j);
                            self.hess[i * n + j] = (cv * hs - sv * hc + es.grad[i] * ec.grad[j]
                                - ec.grad[i] * es.grad[j]
                                - 2.0 * self.grad[i] * (sv * es.grad[j] + cv * ec.grad[j]))
                                / r2;
                        }
                    }
                    // φ̇ = ∇φ · q̇: ∂φ̇/∂q_j = Σ_i H_ij q̇_i.
                    for j in 0..n {
                        let dphid: f64 = (0..n).map(|i| self.hess[i * n + j] * qd[i]).sum();
                        let dtau = dtau_dphi * self.grad[j] + dtau_dphid * dphid;
                        for i in 0..n {
                            // −∂Q_i/∂q_j − γ' ∂Q_i/∂q̇_j, Q_i = τ ∇φ_i.
                            self.k[i * n + j] = -(tau * self.hess[i * n + j] + self.grad[i] * dtau)
                                - gp * self.grad[i] * dtau_dphid * self.grad[j];
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
                self.rate = ldot;
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
