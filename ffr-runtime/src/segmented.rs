//! Flexible bodies run as a chain of FFR sub-bodies (`segments = N`,
//! issue 35).
//!
//! One floating frame is accurate while a body's elastic rotations stay
//! small; past that its error stalls (on the report's spatial spin-up at
//! 0.15 whatever the mesh). A body split at `N − 1` cuts into `N`
//! segments, each with its own floating frame, keeps every segment's
//! elastic rotation small, and converges to the geometrically exact beam
//! as `N` grows (Wu & Haug 1988, *Geometric non-linear substructuring for
//! dynamics of flexible mechanical systems*, IJNME 26).
//!
//! # The coupling
//!
//! Segment `k + 1`'s frame is its root section (it is clamped there) and
//! is fixed to segment `k`'s deformed end section by a fixed joint between
//! the two markers: the end section's point `r_k(l_k)` and axes
//! `A_k R(ψ_k(l_k))` (the exact section rotation of
//! [`crate::section`]) equal segment `k + 1`'s origin and axes. The joint
//! is exact for the beam's model (no linearized rotation), so the chain is
//! the beam's kinematics section by section; its Lagrange multipliers are
//! the section forces and moments at the cuts.
//!
//! The cut joints are ordinary constraints of the system (`kind` =
//! `"segment cut"`), solved by the same bordered solver; the border of a
//! long chain is ordered by reverse Cuthill–McKee so that its Schur
//! complement is banded (`crate::linalg`), and a step costs
//! `O(N)` in the segments.
//!
//! # Names
//!
//! The root segment is the body as added (its name, its [`BodyId`]); the
//! others are `NAME[2]`, …, `NAME[N]`. [`System::point`] on the root maps
//! `x ∈ [0, L]` of the whole body to its segment (a point on a cut to the
//! outboard segment's root); points fixed in the body's frame
//! ([`Marker::at`]) and its origin stay the root segment's.

use crate::body::Body;
use crate::error::{Error, Result};
use crate::marker::{BodyId, Marker};
use crate::system::System;

/// A body run as segments: the bodies from root to tip and the sections
/// bounding them.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentGroup {
    /// The segments' bodies, root first.
    pub bodies: Vec<BodyId>,
    /// The `N + 1` positions on the whole body's axis bounding the
    /// segments, `0 = x_0 < x_1 < … < x_N = L`.
    pub bounds: Vec<f64>,
    /// The system constraints of the cuts (`N − 1`, in order).
    pub cuts: Vec<usize>,
}

impl SegmentGroup {
    /// The segment holding `x` of the whole body's axis and `x` on it; a
    /// point on a cut is on the outboard segment's root; `None` off
    /// `[0, L]`.
    pub fn locate(&self, x: f64) -> Option<(usize, f64)> {
        let n = self.bodies.len();
        let l = self.bounds[n];
        if !(0.0..=l).contains(&x) {
            return None;
        }
        let k = (1..n).rev().find(|&k| x >= self.bounds[k]).unwrap_or(0);
        let local = if k + 1 == n && x == l {
            // The tip as the last segment's length (not a rounded
            // difference past it).
            self.bounds[n] - self.bounds[k]
        } else {
            x - self.bounds[k]
        };
        Some((k, local))
    }

    /// The root segment.
    pub fn root(&self) -> BodyId {
        self.bodies[0]
    }
}

impl<B: Body> System<B> {
    /// Run body `root` (a beam of length `bounds[1]`, already added) as the
    /// first of `segments.len() + 1` segments: the others are added as
    /// `NAME[2]`, … with their frames at `root`'s undeformed sections
    /// `bounds[1], …` (same orientation, at rest: set velocities after, on
    /// the root, which moves the whole body), each clamped at its root and
    /// fixed to the previous segment's end section by a cut joint. `bounds`
    /// are the `N + 1` section positions on the whole body's axis, from 0
    /// to its length, increasing; segment `k`'s length must be
    /// `bounds[k + 1] − bounds[k]`. Returns the group.
    pub fn add_segments(
        &mut self,
        root: BodyId,
        segments: Vec<B>,
        bounds: &[f64],
    ) -> Result<&SegmentGroup> {
        let name = self.body_entry_checked(root)?.name.clone();
        let n = segments.len() + 1;
        if bounds.len() != n + 1
            || bounds[0] != 0.0
            || !bounds.iter().all(|x| x.is_finite())
            || bounds.windows(2).any(|w| w[1] <= w[0])
        {
            return Err(Error::InvalidInput(format!(
                "body `{name}`: {n} segments need {} increasing section positions from 0, found {bounds:?}",
                n + 1
            )));
        }
        if self.segment_group(root).is_some() {
            return Err(Error::InvalidInput(format!(
                "body `{name}` already runs as segments"
            )));
        }
        // Every segment's end is at its length (the cut's marker).
        self.point_on(root, bounds[1]).map_err(|e| {
            Error::InvalidInput(format!(
                "body `{name}`: its first segment does not reach the cut at x = {:?}: {e}",
                bounds[1]
            ))
        })?;
        let (o, d, nth) = {
            let e = self.body_entry(root);
            (e.offset, e.d, e.n_theta)
        };
        let q = self.q0[o..o + d + nth].to_vec();
        let rot = crate::rotation::Rotation::new(&q[d..d + nth]);
        let mut bodies = vec![root];
        for (i, body) in segments.into_iter().enumerate() {
            let k = i + 1;
            let seg = format!("{name}[{}]", k + 1);
            let offset = rot.a * crate::nalgebra::Vector3::new(bounds[k], 0.0, 0.0);
            let pose = if d == 2 {
                crate::system::Pose::planar(q[0] + offset.x, q[1] + offset.y, q[2])
            } else {
                let e = crate::nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]);
                crate::system::Pose::spatial(
                    crate::nalgebra::Vector3::new(q[0], q[1], q[2]) + offset,
                    crate::nalgebra::UnitQuaternion::from_quaternion(e),
                )
            };
            let id = self.add_body(&seg, body, pose)?;
            let length = bounds[k + 1] - bounds[k];
            self.point_on(id, length).map_err(|e| {
                Error::InvalidInput(format!(
                    "segment `{seg}` does not reach its end at x = {length:?}: {e}"
                ))
            })?;
            bodies.push(id);
        }
        let mut cuts = Vec::with_capacity(n - 1);
        for k in 0..n - 1 {
            let end = self.point_on(bodies[k], bounds[k + 1] - bounds[k])?;
            cuts.push(self.constraints.len());
            self.fixed(end, Marker::origin(bodies[k + 1]))?;
            if let Some(c) = self.constraints.last_mut() {
                c.kind = "segment cut".to_string();
            }
        }
        self.segments.push(SegmentGroup {
            bodies,
            bounds: bounds.to_vec(),
            cuts,
        });
        Ok(self.segments.last().expect("just added"))
    }

    /// The bodies run as segments.
    pub fn segment_groups(&self) -> &[SegmentGroup] {
        &self.segments
    }

    /// The group body `b` is a segment of (any segment, root or not).
    pub fn segment_group(&self, b: BodyId) -> Option<&SegmentGroup> {
        self.segments.iter().find(|g| g.bodies.contains(&b))
    }

    /// Whether `b` is a segment other than its body's root.
    pub fn is_outboard_segment(&self, b: BodyId) -> bool {
        self.segment_group(b).is_some_and(|g| g.root() != b)
    }

    fn body_entry_checked(&self, id: BodyId) -> Result<&crate::system::BodyEntry<B>> {
        self.bodies
            .get(id.0)
            .ok_or_else(|| Error::InvalidInput(format!("no body {}", id.0)))
    }

    /// The point at `x` on body `b`'s own axis (not mapped through a
    /// segment group).
    pub(crate) fn point_on(&self, b: BodyId, x: f64) -> Result<Marker> {
        let e = self.body_entry_checked(b)?;
        let shape = e
            .body
            .point_shape(x)
            .map_err(|err| Error::InvalidInput(format!("body `{}`: {err}", e.name)))?;
        Ok(Marker::point(b, shape))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_are_located_on_their_segments() {
        let g = SegmentGroup {
            bodies: vec![BodyId(0), BodyId(3), BodyId(4)],
            bounds: vec![0.0, 0.1, 0.2, 0.3],
            cuts: vec![0, 1],
        };
        assert_eq!(g.locate(0.0), Some((0, 0.0)));
        assert_eq!(g.locate(0.05), Some((0, 0.05)));
        assert_eq!(g.locate(0.1), Some((1, 0.0)));
        assert_eq!(g.locate(0.3), Some((2, 0.3 - 0.2)));
        assert_eq!(g.locate(0.30000000000000004), None);
        assert_eq!(g.locate(-1e-300), None);
        assert_eq!(g.locate(f64::NAN), None);
    }
}
