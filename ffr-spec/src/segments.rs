//! A flexible body split into `segments = N` FFR sub-bodies at `N − 1`
//! cuts (issue 35): the data of segment `k` from the whole body's
//! [`FlexSpec`]. The cuts fall on nodes (`elements / N` elements per
//! segment); each segment keeps the whole body's shape, options and
//! parameters over its own span:
//!
//! - equal elements: `l_k = L / N` with `E / N` equal elements;
//! - a graded mesh (`nodes`): the nodes of its span, shifted to start at 0;
//! - a section table: the stations inside its span plus the two ends,
//!   interpolated linearly (the table is linear between stations, so the
//!   segment's properties are the whole body's at every x);
//! - attached masses: those on `[x_k, x_{k+1})` (the last segment also
//!   `x = L`), a mass at a cut on the outboard segment's root;
//! - a modal body: each segment reduced by Craig–Bampton with its outboard
//!   cut section (its end node) as a boundary node, besides the whole
//!   body's boundary nodes inside its span;
//! - the reference condition: the root segment the whole body's; the
//!   others clamped (their frame is their root section, which the cut
//!   joint fixes to the inboard segment's end section).

use crate::scene::{FlexSpec, MassSpec, ModalSettings, SectionTable, Station};
use crate::{FrameModel, Reference};

/// The most segments a body may be split into (each is a body with its own
/// frame: a bound on what one body of a scene may cost).
pub const MAX_SEGMENTS: usize = 256;

/// Why a body cannot be split as asked.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentError(pub String);

impl std::fmt::Display for SegmentError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SegmentError {}

/// Check that `segments` splits a body of `elements` elements: 1 to
/// [`MAX_SEGMENTS`], at most `elements`, and a divisor of it.
pub fn check_segments(segments: i64, elements: usize) -> Result<usize, SegmentError> {
    if segments < 1 || segments as u64 > MAX_SEGMENTS as u64 {
        return Err(SegmentError(format!(
            "`segments` must be 1 to {MAX_SEGMENTS}, found {segments}"
        )));
    }
    let n = segments as usize;
    if n > elements {
        return Err(SegmentError(format!(
            "`segments` = {n} is more than the body's {elements} elements: every segment needs at least one element"
        )));
    }
    if !elements.is_multiple_of(n) {
        return Err(SegmentError(format!(
            "`segments` = {n} does not divide the body's {elements} elements: the cuts fall on nodes, so each segment has elements / segments elements (try {})",
            divisors_near(elements, n)
        )));
    }
    Ok(n)
}

/// The `segments + 1` section positions bounding `segments` segments of a
/// body of `elements` equal elements and length `length`: the nodes
/// `k · elements / segments`, at `length · node / elements` (the last
/// exactly `length`). [`FlexSpec::segment_bounds`] of a body without a
/// graded mesh, and what `#[flex_body(segments = N)]` splits at.
pub fn uniform_bounds(length: f64, elements: usize, segments: usize) -> Vec<f64> {
    let n = segments.max(1);
    let per = elements / n;
    (0..=n)
        .map(|k| {
            let node = k * per;
            if node == elements {
                length
            } else {
                length * node as f64 / elements as f64
            }
        })
        .collect()
}

/// The divisors of `e` next to `n` (for a message).
fn divisors_near(e: usize, n: usize) -> String {
    let below = (1..n).rev().find(|d| e.is_multiple_of(*d));
    let above = (n + 1..=e).find(|d| e.is_multiple_of(*d));
    match (below, above) {
        (Some(b), Some(a)) => format!("{b} or {a}"),
        (Some(b), None) => b.to_string(),
        (None, Some(a)) => a.to_string(),
        (None, None) => "1".to_string(),
    }
}

impl FlexSpec {
    /// The name of segment `k` (0-based): the body's own name for the root
    /// segment, `NAME[k+1]` for the others (`beam`, `beam[2]`, …).
    pub fn segment_name(&self, k: usize) -> String {
        if k == 0 {
            self.name.clone()
        } else {
            format!("{}[{}]", self.name, k + 1)
        }
    }

    /// The `segments + 1` section positions bounding the segments, from 0
    /// to the length: the nodes `k · elements / segments`.
    pub fn segment_bounds(&self) -> Vec<f64> {
        let n = self.segments.max(1);
        let per = self.elements / n;
        match &self.nodes {
            Some(xs) => (0..=n).map(|k| xs[k * per]).collect(),
            None => uniform_bounds(self.params.length, self.elements, n),
        }
    }

    /// Segment `k` of this body as a body of its own (see the module's
    /// documentation); `segments = 1` gives the body itself.
    pub fn segment(&self, k: usize) -> FlexSpec {
        let n = self.segments.max(1);
        if n == 1 {
            return self.clone();
        }
        assert!(k < n, "segment {k} of {n}");
        let per = self.elements / n;
        let bounds = self.segment_bounds();
        let (x0, x1) = (bounds[k], bounds[k + 1]);
        let length = x1 - x0;
        let mut params = self.params;
        params.length = length;
        let nodes = self
            .nodes
            .as_ref()
            .map(|xs| xs[k * per..=(k + 1) * per].iter().map(|x| x - x0).collect());
        let sections = self.sections.as_ref().map(|t| SectionTable {
            stations: split_stations(&t.stations, x0, x1),
            at: t.at.clone(),
        });
        let masses = self
            .masses
            .iter()
            .filter(|m| m.mass.x >= x0 && (m.mass.x < x1 || (k + 1 == n && m.mass.x <= x1)))
            .map(|m| {
                let mut mass = m.mass;
                mass.x = (m.mass.x - x0).clamp(0.0, length);
                MassSpec {
                    mass,
                    at: m.at.clone(),
                }
            })
            .collect();
        let modal = self.modal.as_ref().map(|(s, at)| {
            let (start, end) = (k * per, (k + 1) * per);
            let mut boundary: Vec<usize> = s
                .boundary
                .iter()
                .filter(|&&b| b > start && b <= end)
                .map(|&b| b - start)
                .collect();
            if k + 1 < n {
                boundary.push(per);
            }
            boundary.sort_unstable();
            boundary.dedup();
            (
                ModalSettings {
                    modes: s.modes,
                    boundary,
                    static_modes: s.static_modes,
                    damping: s.damping.clone(),
                },
                at.clone(),
            )
        });
        let mut options = self.options;
        let reference = if k == 0 {
            self.reference
        } else {
            // Its frame moves with the inboard segment's end section.
            options.frame = FrameModel::Free;
            Reference::Clamped
        };
        FlexSpec {
            name: self.segment_name(k),
            shape: self.shape.clone(),
            shape_name: self.shape_name.clone(),
            shape_at: self.shape_at.clone(),
            elements: per,
            nodes,
            reference,
            options,
            params,
            given: self.given,
            params_at: self.params_at.clone(),
            modal,
            sections,
            masses,
            segments: 1,
            segments_at: self.segments_at.clone(),
        }
    }
}

/// The stations of `[x0, x1]`, shifted to start at 0: those strictly inside
/// and the two ends (a station there, or the linear interpolation).
fn split_stations(stations: &[Station], x0: f64, x1: f64) -> Vec<Station> {
    let at = |x: f64| -> Station {
        if let Some(s) = stations.iter().find(|s| s.x == x) {
            return *s;
        }
        let i = stations
            .windows(2)
            .position(|w| w[0].x < x && x < w[1].x)
            .expect("a cut inside the table");
        let (a, b) = (&stations[i], &stations[i + 1]);
        let t = (x - a.x) / (b.x - a.x);
        let l = |p: f64, q: f64| p + t * (q - p);
        Station {
            x,
            mass: l(a.mass, b.mass),
            ea: l(a.ea, b.ea),
            ei_y: l(a.ei_y, b.ei_y),
            ei_z: l(a.ei_z, b.ei_z),
            gj: l(a.gj, b.gj),
            rho_iy: l(a.rho_iy, b.rho_iy),
            rho_iz: l(a.rho_iz, b.rho_iz),
            rho_j: l(a.rho_j, b.rho_j),
            twist: l(a.twist, b.twist),
        }
    };
    let mut out = vec![at(x0)];
    out.extend(stations.iter().filter(|s| s.x > x0 && s.x < x1).copied());
    out.push(at(x1));
    for s in &mut out {
        s.x -= x0;
    }
    // The end's x as the segment's length is computed (x1 − x0).
    out.last_mut().expect("two stations").x = x1 - x0;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segments_are_checked() {
        assert_eq!(check_segments(4, 16), Ok(4));
        assert_eq!(check_segments(1, 3), Ok(1));
        for (s, e, want) in [
            (0, 16, "must be 1 to 256, found 0"),
            (-3, 16, "must be 1 to 256, found -3"),
            (i64::MAX, 16, "must be 1 to 256"),
            (17, 16, "more than the body's 16 elements"),
            (5, 16, "does not divide the body's 16 elements"),
        ] {
            let m = check_segments(s, e).unwrap_err().0;
            assert!(m.contains(want), "{s}, {e}: {m}");
        }
        assert!(check_segments(5, 16).unwrap_err().0.contains("try 4 or 8"));
    }

    #[test]
    fn stations_are_interpolated_at_the_cuts() {
        let st = |x: f64, m: f64| Station {
            x,
            mass: m,
            ea: 2.0 * m,
            ei_y: 3.0 * m,
            ei_z: 4.0 * m,
            gj: 5.0 * m,
            rho_iy: 6.0 * m,
            rho_iz: 7.0 * m,
            rho_j: 13.0 * m,
            twist: 0.1 * m,
        };
        let table = [st(0.0, 1.0), st(1.0, 3.0), st(4.0, 9.0)];
        let s = split_stations(&table, 0.5, 2.5);
        let xs: Vec<f64> = s.iter().map(|s| s.x).collect();
        assert_eq!(xs, [0.0, 0.5, 2.0]);
        assert_eq!(s[0].mass, 2.0);
        assert_eq!(s[1], Station { x: 0.5, ..table[1] });
        assert_eq!(s[2].mass, 6.0);
        assert_eq!(s[2].rho_j, 78.0);
        let whole = split_stations(&table, 0.0, 4.0);
        assert_eq!(whole, table);
    }
}
