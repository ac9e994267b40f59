//! When one floating frame is not enough (issue 35): the largest elastic
//! section rotation of every flexible body (or segment) over a run or at a
//! static state, and the warning past [`SINGLE_FRAME_ROTATION`].
//!
//! A floating frame of reference with a stiffening model of finite order
//! describes the beam's kinematics well while its sections turn little
//! relative to the frame; its error grows quickly with that rotation. The
//! threshold comes from the convergence study in `bench/segments/`
//! (`bench/segments/README.md`): on the report's spatial spin-up under
//! gravity and the planar spin-ups, run with 1, 2, 4 and 8 segments, the
//! tip error against the geometrically exact reference (over its peak)
//! follows the largest elastic rotation `θ` of a body or segment as
//! `e ≈ 0.01 (θ / 0.27)⁴` once `θ` passes 0.18 rad (0.183 rad: 1.9e-3,
//! 0.325: 0.019, 0.513: 0.107, 0.616: 0.147), and stays below 2e-3 under
//! it (where the mesh and the step set the error). The error passes 1 %
//! at 0.27 rad, the threshold.

use super::model::Scene;
use crate::runtime::monitor::ElasticRotation;
use crate::runtime::BodyId;

/// The largest elastic section rotation (rad) up to which one floating
/// frame is accurate to about 1 % (module documentation).
pub const SINGLE_FRAME_ROTATION: f64 = 0.27;

/// The largest elastic section rotation of one flexible body of a scene (a
/// body run as segments: of its segment that turned most).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyRotation {
    /// The body's name in the scene (of a segmented body: the body's, not
    /// the segment's).
    pub body: String,
    /// The segment (1-based) and the body's segment count; `(1, 1)` for a
    /// body without segments.
    pub segment: (usize, usize),
    /// The largest angle (rad) relative to its (segment's) frame.
    pub angle: f64,
    /// When (s).
    pub t: f64,
    /// Where on the body's axis (m from its root; of the whole body).
    pub x: f64,
}

/// The largest rotation of each flexible body of `scene` from the
/// runtime's per-body record: one entry per scene body (segments merged).
pub fn body_rotations(scene: &Scene, rotations: &[ElasticRotation]) -> Vec<BodyRotation> {
    let sys = &scene.system;
    let mut out: Vec<BodyRotation> = Vec::new();
    for r in rotations {
        let id = BodyId(r.body);
        let (name, segment, x) = match sys.segment_group(id) {
            Some(g) => {
                let k = g.bodies.iter().position(|b| *b == id).expect("a member");
                let root = &sys.bodies()[g.root().0].name;
                (root.clone(), (k + 1, g.bodies.len()), g.bounds[k] + r.x)
            }
            None => (sys.bodies()[r.body].name.clone(), (1, 1), r.x),
        };
        let entry = BodyRotation {
            body: name,
            segment,
            angle: r.angle,
            t: r.t,
            x,
        };
        match out.iter_mut().find(|b| b.body == entry.body) {
            Some(b) if entry.angle > b.angle => *b = entry,
            Some(_) => {}
            None => out.push(entry),
        }
    }
    out
}

/// The warnings for the bodies of `rotations` that turned more than
/// [`SINGLE_FRAME_ROTATION`]: one per body, saying how far, when, where,
/// what accuracy to expect and how many segments to try.
pub fn warnings(scene: &Scene, rotations: &[BodyRotation]) -> Vec<String> {
    let q = crate::runtime::spec::text::quoted;
    rotations
        .iter()
        .filter(|r| r.angle > SINGLE_FRAME_ROTATION)
        .map(|r| {
            let (k, n) = r.segment;
            let elements = scene
                .flex
                .iter()
                .find(|f| f.name == r.body)
                .map_or(0, |f| f.elements);
            let frame = if n == 1 {
                "one floating frame".to_string()
            } else {
                format!("one floating frame per segment (segment {k} of {n})")
            };
            let advice = match suggest_segments(r.angle, n, elements) {
                Some(m) => format!("try segments = {m}"),
                None => format!(
                    "refine: {elements} elements cannot be cut into enough segments; give more elements (a multiple of the segments) and segments"
                ),
            };
            format!(
                "body `{}`: elastic rotation {:.2} rad at t = {:.4} s (x = {:.4} m); {frame} is accurate to about 1 % of the motion up to {SINGLE_FRAME_ROTATION} rad, and its error grows quickly beyond (on the spin-ups about as the rotation to the fourth power: 2 % at 0.33 rad, 15 % at 0.62 rad); {advice} (docs/scenes.md, \"Segments\")",
                q(&r.body),
                r.angle,
                r.t,
                r.x,
            )
        })
        .collect()
}

/// The segments to try for a body of `elements` elements now run as `n`
/// segments whose largest rotation is `angle`: the least divisor `m` of
/// `elements` with `angle (n/m)^0.58` below the threshold (`None` when no
/// divisor is enough). A segment's rotation relative to its frame shrinks
/// with its length, but the root segment of a cantilever less than in
/// proportion: on the spin-up under gravity 0.616, 0.513, 0.325, 0.183 rad
/// for 1, 2, 4, 8 segments, `N^-0.58` (bench/segments/study.csv).
fn suggest_segments(angle: f64, n: usize, elements: usize) -> Option<usize> {
    let need = n as f64 * (angle / SINGLE_FRAME_ROTATION).powf(1.0 / 0.58);
    (n + 1..=elements.min(crate::runtime::spec::MAX_SEGMENTS))
        .find(|&m| elements.is_multiple_of(m) && m as f64 >= need)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_are_suggested_as_divisors() {
        // 0.9 rad on one frame: at least 7.9 segments, a divisor of 16.
        assert_eq!(suggest_segments(0.9, 1, 16), Some(8));
        // 0.5 rad per segment of 4: 11.5, so 16.
        assert_eq!(suggest_segments(0.5, 4, 16), Some(16));
        // 0.616 rad (the spin-up under gravity): 4.1, so 8 (which turns
        // 0.183 rad, below the threshold; 4 segments still turn 0.325).
        assert_eq!(suggest_segments(0.616, 1, 16), Some(8));
        // 0.325 rad in 4 segments: 5.5, so 8.
        assert_eq!(suggest_segments(0.325, 4, 16), Some(8));
        // No divisor of 3 is enough for 2 rad.
        assert_eq!(suggest_segments(2.0, 1, 3), None);
    }
}
