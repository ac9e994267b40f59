//! Constraint equations `Φ(q, t) = 0` between markers: the building blocks
//! of joints (ground, fixed, revolute, spherical) and driving constraints.

use crate::driver::Driver;
use crate::marker::{BodyId, Marker};

/// One group of scalar constraint equations.
#[derive(Clone, Debug)]
pub enum Constraint {
    /// `q_i − f(t) = 0` on body coordinate `index` (local to the body).
    Coordinate {
        /// The body.
        body: BodyId,
        /// Index into the body's coordinates `[R; θ; q_f]`.
        index: usize,
        /// Prescribed value.
        driver: Driver,
    },
    /// `r_b − r_a = 0` (the scene's `d` components): a revolute joint in the
    /// plane, a spherical joint in space.
    Coincident {
        /// First marker.
        a: Marker,
        /// Second marker.
        b: Marker,
    },
    /// `a_i · b_j = 0` between marker axes `i` of `a` and `j` of `b`.
    Perpendicular {
        /// First marker.
        a: Marker,
        /// Axis index (0, 1, 2 = x, y, z) of `a`.
        axis_a: usize,
        /// Second marker.
        b: Marker,
        /// Axis index of `b`.
        axis_b: usize,
    },
    /// Marker `b` turned by `f(t)` about the z axis of `a`:
    /// `(x_b · y_a) cos f − (x_b · x_a) sin f = 0` (= `sin(φ − f)` for a relative angle `φ`).
    Angle {
        /// Reference marker (its z axis is the rotation axis).
        a: Marker,
        /// Driven marker.
        b: Marker,
        /// Prescribed relative angle.
        driver: Driver,
    },
}

impl Constraint {
    /// Number of scalar equations in a scene of dimension `d`.
    pub fn len(&self, d: usize) -> usize {
        match self {
            Constraint::Coincident { .. } => d,
            _ => 1,
        }
    }

    /// Bodies this constraint touches.
    pub fn bodies(&self) -> Vec<BodyId> {
        match self {
            Constraint::Coordinate { body, .. } => vec![*body],
            Constraint::Coincident { a, b }
            | Constraint::Perpendicular { a, b, .. }
            | Constraint::Angle { a, b, .. } => a.body.into_iter().chain(b.body).collect(),
        }
    }
}
