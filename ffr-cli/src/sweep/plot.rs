//! The study's plot (`results.svg`): one panel per figure against the first
//! axis, one line per combination of the other axes' values (ok cases only).

use super::cases;
use super::run::CaseResult;
use super::study::Study;
use crate::plot::{plot_text, MAX_LABEL_CHARS, MAX_TITLE_CHARS};
use ffr::scene::SceneValue;
use plotters::prelude::*;

/// The first line of every plot `ffr sweep` writes (how it knows the file
/// is its own).
pub const MARK: &str = "<!-- ffr sweep results plot -->";

const COLORS: [RGBColor; 6] = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];

/// A line of a panel: the other axes' value indices, and its points.
type Line = (Vec<usize>, Vec<(f64, f64)>);

/// Lines with a legend entry, per panel; more are drawn without one.
const MAX_LEGEND: usize = 12;

/// The x of a value of the first axis: the number, or its position on the
/// axis for anything else.
fn x_of(v: &SceneValue, position: usize) -> f64 {
    match v {
        SceneValue::Float(x) => *x,
        SceneValue::Int(i) => *i as f64,
        _ => position as f64,
    }
}

/// The plot as an SVG document.
pub fn svg(study: &Study, rows: &[CaseResult]) -> Result<String, Box<dyn std::error::Error>> {
    let panels = study.figures.len().max(1);
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (900, 320 * panels as u32)).into_drawing_area();
        root.fill(&WHITE)?;
        let areas = root.split_evenly((panels, 1));
        let x_desc = study
            .axes
            .first()
            .map_or("case".to_string(), |a| a.key.clone());
        for (k, area) in areas.iter().enumerate() {
            let Some(fig) = study.figures.get(k) else {
                area.titled("no figures collected", ("sans-serif", 18))?;
                continue;
            };
            // Lines keyed by the other axes' value indices.
            let mut lines: Vec<Line> = Vec::new();
            for r in rows.iter().filter(|r| r.ok()) {
                let idx = cases::indices(&study.axes, r.case);
                let x = match study.axes.first() {
                    Some(a) => x_of(&a.values[idx[0]], idx[0]),
                    None => r.case as f64,
                };
                let rest = idx.get(1..).unwrap_or_default().to_vec();
                let y = r.figures[k];
                if !(crate::plot::plottable(x) && crate::plot::plottable(y)) {
                    continue;
                }
                match lines.iter_mut().find(|(key, _)| *key == rest) {
                    Some((_, pts)) => pts.push((x, y)),
                    None => lines.push((rest, vec![(x, y)])),
                }
            }
            let all = lines.iter().flat_map(|(_, p)| p.iter());
            let (mut x0, mut x1, mut y0, mut y1) = (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            );
            for &(x, y) in all {
                x0 = x0.min(x);
                x1 = x1.max(x);
                y0 = y0.min(y);
                y1 = y1.max(y);
            }
            if !x0.is_finite() {
                (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
            }
            let title = plot_text(
                &format!("{}: {} of {}", fig.name, fig.stat.name(), fig.output),
                MAX_TITLE_CHARS,
            );
            let mut chart = ChartBuilder::on(area)
                .caption(&title, ("sans-serif", 18))
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(80)
                .build_cartesian_2d(
                    crate::plot::axis(x0, x1, 0.02),
                    crate::plot::axis(y0, y1, 0.05),
                )?;
            chart
                .configure_mesh()
                .x_desc(plot_text(&x_desc, MAX_LABEL_CHARS))
                .y_desc(plot_text(&fig.name, MAX_LABEL_CHARS))
                .draw()?;
            for (j, (key, pts)) in lines.iter().enumerate() {
                let color = COLORS[j % COLORS.len()];
                let series =
                    chart.draw_series(LineSeries::new(pts.iter().copied(), color).point_size(3))?;
                if j < MAX_LEGEND && !key.is_empty() {
                    let label: Vec<String> = study.axes[1..]
                        .iter()
                        .zip(key)
                        .map(|(a, &i)| format!("{}={}", a.key, cases::cell(&a.values[i])))
                        .collect();
                    series
                        .label(plot_text(&label.join(" "), MAX_LABEL_CHARS))
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
                }
            }
            if lines.len() > 1 {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()?;
            }
        }
        root.present()?;
    }
    Ok(format!("{MARK}\n{svg}"))
}
