//! Learning curves (thesis figs. 6.3, 7.1): the best score so far against the evaluation
//! number, one line per run, drawn into a PNG with plotters.

use std::path::Path;

use plotters::prelude::*;

/// Best score so far after each evaluation (failed evaluations keep the previous best).
pub fn best_so_far(scores: &[f64]) -> Vec<f64> {
    let mut best = f64::NEG_INFINITY;
    scores
        .iter()
        .map(|s| {
            if s.is_finite() {
                best = best.max(*s);
            }
            best
        })
        .collect()
}

/// Draws each `(label, scores in evaluation order)` as its best-so-far curve.
pub fn plot_curves(
    runs: &[(String, Vec<f64>)],
    y_label: &str,
    output: &Path,
    size: (u32, u32),
) -> Result<(), String> {
    let draw = |e: &dyn std::fmt::Display| format!("{}: cannot draw: {e}", output.display());
    let curves: Vec<(String, Vec<(f64, f64)>)> = runs
        .iter()
        .map(|(label, s)| {
            let pts = best_so_far(s)
                .into_iter()
                .enumerate()
                .filter(|(_, b)| b.is_finite())
                .map(|(i, b)| ((i + 1) as f64, b))
                .collect();
            (label.clone(), pts)
        })
        .collect();
    let all = curves.iter().flat_map(|c| c.1.iter());
    let (mut x1, mut y0, mut y1) = (1.0f64, f64::INFINITY, f64::NEG_INFINITY);
    for (x, y) in all {
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    if !y0.is_finite() {
        return Err("no finite scores to plot".into());
    }
    let pad = if y1 > y0 { (y1 - y0) * 0.05 } else { 0.5 };
    let root = BitMapBackend::new(output, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption("best score so far", ("monospace", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..x1 * 1.02, (y0 - pad)..(y1 + pad))
        .map_err(|e| draw(&e))?;
    chart
        .configure_mesh()
        .x_desc("evaluation")
        .y_desc(y_label)
        .draw()
        .map_err(|e| draw(&e))?;
    for (i, (label, pts)) in curves.into_iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
            .map_err(|e| draw(&e))?
            .label(label)
            .legend(move |(px, py)| PathElement::new(vec![(px, py), (px + 20, py)], colour));
    }
    chart
        .configure_series_labels()
        .label_font(("monospace", 14))
        .position(SeriesLabelPosition::MiddleRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| draw(&e))?;
    root.present().map_err(|e| draw(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn best_so_far_ignores_failures() {
        let b = best_so_far(&[1.0, f64::NEG_INFINITY, 0.5, 2.0, f64::NAN]);
        assert_eq!(b, vec![1.0, 1.0, 1.0, 2.0, 2.0]);
    }
}
