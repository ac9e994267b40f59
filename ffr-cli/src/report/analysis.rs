//! Reading work-precision points: Pareto fronts, the cheapest point at an
//! error level, and the cost of a front at a given error by interpolation.

use super::data::Point;

/// The error levels the report reads the diagrams at.
pub const LEVELS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// The Pareto front of `points` (those with a positive error): the points
/// that no other point beats in both CPU time and error, ordered by
/// increasing CPU time (and so decreasing error). Ties in CPU time keep the
/// smaller error.
pub fn pareto<'a>(points: impl IntoIterator<Item = &'a Point>) -> Vec<&'a Point> {
    let mut v: Vec<&Point> = points.into_iter().filter(|p| p.error > 0.0).collect();
    v.sort_by(|a, b| {
        a.cpu_s
            .total_cmp(&b.cpu_s)
            .then(a.error.total_cmp(&b.error))
    });
    let mut front: Vec<&Point> = Vec::new();
    for p in v {
        if front.last().is_none_or(|l| p.error < l.error) {
            front.push(p);
        }
    }
    front
}

/// The cheapest point with `error ≤ level`.
pub fn cheapest<'a>(points: impl IntoIterator<Item = &'a Point>, level: f64) -> Option<&'a Point> {
    points
        .into_iter()
        .filter(|p| p.error <= level)
        .min_by(|a, b| a.cpu_s.total_cmp(&b.cpu_s))
}

/// The CPU time a Pareto front (as [`pareto`] returns it) needs for error
/// `level`, interpolated:
///
/// - `level` at or above the error of the front's cheapest point: that
///   point's CPU time (it already reaches the level);
/// - between two consecutive front points `(e₁, c₁)`, `(e₂, c₂)` with
///   `e₁ > level ≥ e₂`: linear interpolation of `log c` in `log e`;
/// - below the front's smallest error: `None` (no extrapolation).
pub fn cost_at(front: &[&Point], level: f64) -> Option<f64> {
    let first = front.first()?;
    if level >= first.error {
        return Some(first.cpu_s);
    }
    for w in front.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a.error > level && level >= b.error {
            let s = (level.ln() - a.error.ln()) / (b.error.ln() - a.error.ln());
            return Some((a.cpu_s.ln() + s * (b.cpu_s.ln() - a.cpu_s.ln())).exp());
        }
    }
    None
}

/// Method families of `points` in order of first appearance.
pub fn families(points: &[Point]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for p in points {
        if !out.contains(&p.method) {
            out.push(p.method.clone());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(cpu: f64, err: f64) -> Point {
        Point {
            scene: "s".into(),
            method: "m".into(),
            elements: 1,
            dt: 1.0,
            cpu_s: cpu,
            error: err,
            error_kind: "energy".into(),
            tool: "ffr".into(),
            reps: 1,
        }
    }

    #[test]
    fn front_cheapest_and_interpolated_cost() {
        let pts = [
            p(1.0, 1e-2),
            p(2.0, 1e-2),
            p(4.0, 1e-4),
            p(3.0, 1e-1),
            p(0.5, 1e-1),
        ];
        let f = pareto(&pts);
        let fe: Vec<(f64, f64)> = f.iter().map(|q| (q.cpu_s, q.error)).collect();
        assert_eq!(fe, vec![(0.5, 1e-1), (1.0, 1e-2), (4.0, 1e-4)]);
        assert_eq!(cheapest(&pts, 1e-2).unwrap().cpu_s, 1.0);
        assert_eq!(cheapest(&pts, 1e-3).unwrap().cpu_s, 4.0);
        assert!(cheapest(&pts, 1e-5).is_none());
        // At or above the cheapest point's error: its cost.
        assert_eq!(cost_at(&f, 0.5), Some(0.5));
        assert_eq!(cost_at(&f, 1e-2), Some(1.0));
        // Half-way in log error between (1e-2, 1) and (1e-4, 4): 2.
        assert!((cost_at(&f, 1e-3).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(cost_at(&f, 1e-4), Some(4.0));
        assert_eq!(cost_at(&f, 1e-5), None);
    }
}
