//! SVG plots of simulation results (plotters).

use crate::runtime::scenes::SpinUpResult;
use plotters::prelude::*;
use std::path::Path;

/// Tip displacement in the hub frame against time, written to `path`
/// atomically (see [`crate::output::write_atomic`]).
pub fn tip_plot(
    path: &Path,
    title: &str,
    r: &SpinUpResult,
) -> Result<(), Box<dyn std::error::Error>> {
    let svg = tip_svg(title, r)?;
    crate::output::write_atomic(path, svg.as_bytes())?;
    Ok(())
}

/// Tip displacement in the hub frame against time, as an SVG document.
pub fn tip_svg(title: &str, r: &SpinUpResult) -> Result<String, Box<dyn std::error::Error>> {
    let mut svg = String::new();
    draw(&mut svg, title, r)?;
    Ok(svg)
}

fn draw(svg: &mut String, title: &str, r: &SpinUpResult) -> Result<(), Box<dyn std::error::Error>> {
    let t_max = r.t.last().copied().unwrap_or(1.0).max(1e-9);
    let finite = r
        .tip_transverse
        .iter()
        .chain(&r.tip_axial)
        .copied()
        .filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let pad = 0.05 * (hi - lo).max(1e-6);
    let root = SVGBackend::with_string(svg, (900, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..t_max, (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("tip displacement (m)")
        .draw()?;
    let series = |v: &[f64]| -> Vec<(f64, f64)> {
        r.t.iter()
            .zip(v)
            .filter(|(_, y)| y.is_finite())
            .map(|(t, y)| (*t, *y))
            .collect()
    };
    chart
        .draw_series(LineSeries::new(series(&r.tip_transverse), &BLUE))?
        .label("tip_transverse")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    chart
        .draw_series(LineSeries::new(series(&r.tip_axial), &RED))?
        .label("tip_axial")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
