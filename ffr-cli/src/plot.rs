//! SVG plots of simulation results (plotters), written atomically.

use plotters::prelude::*;
use std::path::Path;

const COLORS: [RGBColor; 6] = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];

/// Longest title of a plot, in characters (longer ones are cut with `…`).
pub const MAX_TITLE_CHARS: usize = 120;

/// Longest series name or axis label of a plot, in characters.
pub const MAX_LABEL_CHARS: usize = 48;

/// User text for a plot: non-printing characters escaped, shortened
/// (`ffr_codegen::sanitize::snippet`); plotters escapes `<`, `&` and quotes.
pub fn plot_text(s: &str, max_chars: usize) -> String {
    ffr_codegen::sanitize::snippet(s, max_chars)
}

/// The largest magnitude a plot's axis reaches: values beyond it are drawn
/// at the edge. (plotters' tick computation did not end on an axis near
/// `f64::MAX`: `ffr run` of a body started at 1.8e308 m/s hung in the plot.)
pub const MAX_AXIS: f64 = 1e300;

/// Whether a value is drawn: finite and within [`MAX_AXIS`] (a value
/// beyond is left out of the plot, as a non-finite one is; plotters'
/// pixel mapping overflows on it).
pub fn plottable(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_AXIS
}

/// An axis from `lo` to `hi` with `frac` of its span added on each side,
/// never empty, its ends finite and within [`MAX_AXIS`] (non-finite ends
/// become 0), computed without overflow.
pub fn axis(lo: f64, hi: f64, frac: f64) -> std::ops::Range<f64> {
    let c = |x: f64| {
        if x.is_finite() {
            x.clamp(-MAX_AXIS, MAX_AXIS)
        } else {
            0.0
        }
    };
    let (lo, hi) = (c(lo).min(c(hi)), c(lo).max(c(hi)));
    let pad = (frac * hi - frac * lo).max(1e-9 * (1.0 + lo.abs().max(hi.abs())));
    (lo - pad)..(hi + pad)
}

/// Lines `series` (name, values) against `t`, as an SVG document. The title,
/// label and names are shown through [`plot_text`].
pub fn time_svg(
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[(&str, &[f64])],
) -> Result<String, Box<dyn std::error::Error>> {
    time_svg_with(title, y_label, t, series, &[])
}

/// A series on its own time grid: name, times, values.
pub type TimedSeries<'a> = (&'a str, &'a [f64], &'a [f64]);

/// [`time_svg`] with `overlays` (e.g. a reference history on its own time
/// grid) drawn as thin black lines over the same axes, cut to the run's time
/// span, each named in the legend.
pub fn time_svg_with(
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[(&str, &[f64])],
    overlays: &[TimedSeries],
) -> Result<String, Box<dyn std::error::Error>> {
    let title = plot_text(title, MAX_TITLE_CHARS);
    let y_label = plot_text(y_label, MAX_LABEL_CHARS);
    let mut svg = String::new();
    {
        let t_max = t.last().copied().unwrap_or(1.0).max(1e-9);
        let t_min = t.first().copied().unwrap_or(0.0).min(t_max - 1e-9);
        // The overlays' points inside the run's time span.
        let overlays: Vec<(&str, Vec<(f64, f64)>)> = overlays
            .iter()
            .map(|(name, ot, ov)| {
                let pts = envelope(ot, ov, PLOT_BUCKETS)
                    .into_iter()
                    .filter(|(x, _)| (t_min..=t_max).contains(x))
                    .collect();
                (*name, pts)
            })
            .collect();
        let finite = series
            .iter()
            .flat_map(|(_, v)| v.iter().copied())
            .chain(overlays.iter().flat_map(|(_, p)| p.iter().map(|q| q.1)))
            .filter(|v| plottable(*v));
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
        let root = SVGBackend::with_string(&mut svg, (900, 500)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(axis(t_min, t_max, 0.0), axis(lo, hi, 0.05))?;
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .y_desc(&y_label)
            .draw()?;
        for (i, (name, v)) in series.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let pts = envelope(t, v, PLOT_BUCKETS);
            chart
                .draw_series(LineSeries::new(pts, color))?
                .label(plot_text(name, MAX_LABEL_CHARS))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
        for (name, pts) in overlays {
            chart
                .draw_series(LineSeries::new(pts, BLACK.stroke_width(1)))?
                .label(plot_text(name, MAX_LABEL_CHARS))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        root.present()?;
    }
    Ok(svg)
}

/// Samples per series above which a plot draws the envelope (the smallest
/// and largest value of each of this many time buckets) instead of every
/// point: a line 900 pixels wide shows no more, and a run of 10⁷ steps
/// would otherwise write a plot of hundreds of megabytes.
const PLOT_BUCKETS: usize = 2000;

/// The finite points of `(t, v)`; beyond `4 buckets` of them, the first and
/// the smallest and largest of each of `buckets` equal runs of samples, in
/// time order.
fn envelope(t: &[f64], v: &[f64], buckets: usize) -> Vec<(f64, f64)> {
    let finite = || {
        t.iter()
            .zip(v.iter())
            .filter(|(_, y)| plottable(**y))
            .map(|(a, b)| (*a, *b))
    };
    let n = t.len().min(v.len());
    if n <= 4 * buckets {
        return finite().collect();
    }
    let mut out = Vec::with_capacity(2 * buckets + 2);
    for b in 0..buckets {
        let (lo, hi) = (b * n / buckets, (b + 1) * n / buckets);
        let mut min: Option<(f64, f64)> = None;
        let mut max: Option<(f64, f64)> = None;
        for i in lo..hi {
            let p = (t[i], v[i]);
            if !plottable(p.1) {
                continue;
            }
            if min.is_none_or(|m| p.1 < m.1) {
                min = Some(p);
            }
            if max.is_none_or(|m| p.1 > m.1) {
                max = Some(p);
            }
        }
        if let (Some(a), Some(b)) = (min, max) {
            if a.0 <= b.0 {
                out.push(a);
                if b != a {
                    out.push(b);
                }
            } else {
                out.push(b);
                out.push(a);
            }
        }
    }
    out
}

/// [`time_svg`] written to `path`.
pub fn time_plot(
    path: &Path,
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[(&str, &[f64])],
) -> Result<(), Box<dyn std::error::Error>> {
    let svg = time_svg(title, y_label, t, series)?;
    crate::output::write_atomic(path, svg.as_bytes())?;
    Ok(())
}

/// A CSV of `t` and named columns, numbers in shortest round-trip form.
pub fn csv(t: &[f64], names: &[&str], columns: &[&[f64]]) -> String {
    let mut s = String::from("t");
    for n in names {
        s.push(',');
        s.push_str(n);
    }
    s.push('\n');
    for (i, ti) in t.iter().enumerate() {
        s.push_str(&crate::output::number(*ti));
        for c in columns {
            s.push(',');
            s.push_str(&crate::output::number(
                c.get(i).copied().unwrap_or(f64::NAN),
            ));
        }
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::envelope;

    #[test]
    fn long_series_are_drawn_as_their_envelope() {
        let n = 100_000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        let v: Vec<f64> = t.iter().map(|x| (7.0 * x).sin() + 1e-3 * x).collect();
        let e = envelope(&t, &v, 500);
        assert!(e.len() <= 1000 && e.len() >= 500, "{}", e.len());
        assert!(e.windows(2).all(|w| w[0].0 < w[1].0), "not in time order");
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        assert!(e.iter().any(|p| p.1 == lo) && e.iter().any(|p| p.1 == hi));
        // Short series keep every finite point.
        let short = envelope(&t[..100], &v[..100], 500);
        assert_eq!(short.len(), 100);
        let mut w = v[..100].to_vec();
        w[3] = f64::NAN;
        assert_eq!(envelope(&t[..100], &w, 500).len(), 99);
    }
}

#[cfg(test)]
mod huge_values {
    use super::*;

    /// Values near `f64::MAX` (finite, their span not) are plotted in
    /// bounded time: the plot hung in plotters' tick computation before.
    #[test]
    fn huge_values_are_plotted() {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let t = [0.0, 0.5, 1.0];
            let big = [-1.7e308, 0.0, 1.7976931348623157e308];
            let odd = [f64::NAN, f64::INFINITY, 1e300];
            let svg = time_svg("huge", "m", &t, &[("big", &big[..]), ("odd", &odd[..])]);
            tx.send(svg.map(|s| s.len()).map_err(|e| e.to_string()))
                .unwrap();
        });
        let r = rx
            .recv_timeout(std::time::Duration::from_secs(60))
            .expect("the plot should take well under a minute");
        assert!(r.unwrap() > 1000);
        let a = axis(-1.7e308, 1.7e308, 0.05);
        assert!(a.start.is_finite() && a.end.is_finite() && (a.end - a.start).is_finite());
        assert!(axis(2.0, 2.0, 0.05).start < 2.0);
    }
}
