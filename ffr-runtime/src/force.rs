//! Force elements acting at markers: point forces and spring–dampers.
//!
//! A global force `F` at a marker maps to `Q = J_Pᵀ F` with
//! `J_P = [I, −A ũ_P Ḡ, A S_P]`.

use crate::marker::Marker;
use nalgebra::Vector3;
use std::fmt;
use std::sync::Arc;

/// A force element.
#[derive(Clone)]
pub enum ForceElement {
    /// A global force `F(t)` at a marker.
    Point {
        /// Where it acts.
        marker: Marker,
        /// The force (global axes) as a function of time.
        force: Arc<dyn Fn(f64) -> Vector3<f64> + Send + Sync>,
    },
    /// A linear spring–damper along the line of two markers: tension
    /// `f = k (l − l₀) + c l̇`, force `f e` on `a` and `−f e` on `b`, `e = (r_b − r_a)/l`.
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
            ForceElement::Point { marker, .. } => write!(f, "Point({marker:?})"),
            ForceElement::SpringDamper {
                a,
                b,
                stiffness,
                damping,
                rest_length,
            } => {
                write!(
                    f,
                    "SpringDamper({a:?}, {b:?}, k={stiffness}, c={damping}, l0={rest_length})"
                )
            }
        }
    }
}
