//! Work-precision diagrams (SVG, plotters): error on a logarithmic x axis,
//! CPU time on a logarithmic y axis, one line per method family through
//! its own Pareto-optimal points, every point marked (ffr: discs; peers:
//! triangles and dashed lines), and the Pareto front of all methods as a
//! thick grey step line with its points ringed.

use super::analysis::{families, pareto, LEVELS};
use super::data::Point;
use plotters::prelude::*;

/// Colours for the families (Tableau 10, then a few more).
const PALETTE: [RGBColor; 14] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
    RGBColor(0, 128, 128),
    RGBColor(128, 128, 0),
];

/// `(lo, hi)` of positive values, widened by a factor on both sides.
fn log_range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| *x > 0.0 && x.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    let (lo, hi) = if hi / lo < 10.0 {
        let m = (lo * hi).sqrt();
        (m / 4.0, m * 4.0)
    } else {
        (lo, hi)
    };
    (lo / 1.6, hi * 1.6)
}

/// The step line of a front ordered by CPU time: for every error `x` the
/// least CPU time among the points with error ≤ `x`.
fn step_path(front: &[&Point], x_max: f64) -> Vec<(f64, f64)> {
    let mut path = Vec::new();
    if let Some(f) = front.first() {
        path.push((x_max, f.cpu_s));
    }
    for (i, p) in front.iter().enumerate() {
        path.push((p.error, p.cpu_s));
        if let Some(next) = front.get(i + 1) {
            path.push((p.error, next.cpu_s));
        }
    }
    path
}

/// The diagram of one scene's `points` (ffr's and peers'), as SVG text.
pub fn diagram(title: &str, x_label: &str, points: &[Point]) -> Result<String, String> {
    let mut svg = String::new();
    draw(&mut svg, title, x_label, points).map_err(|e| e.to_string())?;
    Ok(svg)
}

/// A legend entry: label, colour, peer (triangle, dashed) or ffr (disc).
enum Entry {
    Front,
    Family(String, RGBColor, bool),
}

fn draw(
    svg: &mut String,
    title: &str,
    x_label: &str,
    points: &[Point],
) -> Result<(), Box<dyn std::error::Error>> {
    let shown: Vec<Point> = points.iter().filter(|p| p.error > 0.0).cloned().collect();
    let (x0, x1) = log_range(shown.iter().map(|p| p.error));
    let (y0, y1) = log_range(shown.iter().map(|p| p.cpu_s));
    let root = SVGBackend::with_string(svg, (1100, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 20))?;
    let (left, right) = root.split_horizontally(800);
    let mut chart = ChartBuilder::on(&left)
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc("CPU time of the simulation (s)")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .light_line_style(WHITE.mix(0.0))
        .draw()?;

    // Error levels the report reads the diagram at.
    for level in LEVELS.into_iter().filter(|l| (x0..=x1).contains(l)) {
        chart.draw_series(DashedLineSeries::new(
            vec![(level, y0), (level, y1)],
            4,
            4,
            BLACK.mix(0.25).stroke_width(1),
        ))?;
    }

    let mut legend = Vec::new();
    // The front of all methods, under the families.
    let front = pareto(&shown);
    let grey = RGBColor(90, 90, 90);
    if !front.is_empty() {
        chart.draw_series(LineSeries::new(
            step_path(&front, x1),
            grey.mix(0.45).stroke_width(6),
        ))?;
        chart.draw_series(
            front
                .iter()
                .map(|p| Circle::new((p.error, p.cpu_s), 7, grey.stroke_width(2))),
        )?;
        legend.push(Entry::Front);
    }

    for (i, fam) in families(&shown).iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let pts: Vec<&Point> = shown.iter().filter(|p| &p.method == fam).collect();
        let peer = pts.first().is_some_and(|p| p.tool != "ffr");
        let line: Vec<(f64, f64)> = pareto(pts.iter().copied())
            .iter()
            .map(|p| (p.error, p.cpu_s))
            .collect();
        if peer {
            chart.draw_series(DashedLineSeries::new(line, 8, 4, color.stroke_width(2)))?;
            chart.draw_series(
                pts.iter()
                    .map(|p| TriangleMarker::new((p.error, p.cpu_s), 5, color.filled())),
            )?;
        } else {
            chart.draw_series(LineSeries::new(line, color.stroke_width(2)))?;
            chart.draw_series(
                pts.iter()
                    .map(|p| Circle::new((p.error, p.cpu_s), 3, color.filled())),
            )?;
        }
        // Peers' method names come from their CSV files.
        legend.push(Entry::Family(
            crate::plot::plot_text(fam, crate::plot::MAX_LABEL_CHARS),
            color,
            peer,
        ));
    }

    // The legend, beside the chart.
    let font = ("sans-serif", 13).into_font();
    right.draw(&Text::new(
        "method family (line: its Pareto points)",
        (4, 24),
        font.clone(),
    ))?;
    for (i, e) in legend.iter().enumerate() {
        let y = 52 + 22 * i as i32;
        match e {
            Entry::Front => {
                right.draw(&PathElement::new(
                    vec![(6, y), (34, y)],
                    grey.mix(0.45).stroke_width(6),
                ))?;
                right.draw(&Circle::new((20, y), 7, grey.stroke_width(2)))?;
                right.draw(&Text::new(
                    "Pareto front of all methods",
                    (42, y - 7),
                    font.clone(),
                ))?;
            }
            Entry::Family(name, color, peer) => {
                if *peer {
                    right.draw(&PathElement::new(
                        vec![(6, y), (14, y)],
                        color.stroke_width(2),
                    ))?;
                    right.draw(&PathElement::new(
                        vec![(26, y), (34, y)],
                        color.stroke_width(2),
                    ))?;
                    right.draw(&TriangleMarker::new((20, y), 5, color.filled()))?;
                } else {
                    right.draw(&PathElement::new(
                        vec![(6, y), (34, y)],
                        color.stroke_width(2),
                    ))?;
                    right.draw(&Circle::new((20, y), 3, color.filled()))?;
                }
                right.draw(&Text::new(name.as_str(), (42, y - 7), font.clone()))?;
            }
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_path_is_the_least_cost_at_each_error() {
        let p = |c: f64, e: f64| Point {
            scene: "s".into(),
            method: "m".into(),
            elements: 1,
            dt: 1.0,
            cpu_s: c,
            error: e,
            error_kind: "energy".into(),
            tool: "ffr".into(),
            reps: 1,
        };
        let pts = [p(1.0, 1e-1), p(2.0, 1e-3)];
        let f: Vec<&Point> = pts.iter().collect();
        assert_eq!(
            step_path(&f, 1.0),
            vec![(1.0, 1.0), (1e-1, 1.0), (1e-1, 2.0), (1e-3, 2.0)]
        );
    }
}
