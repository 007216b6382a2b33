//! Learning curves (thesis figs. 6.3, 7.1): the best score so far against the evaluation
//! number, drawn into a PNG with plotters: one line per run, or, for several runs of one
//! optimizer (seeds), their mean with the band between the lowest and the highest.

use std::path::Path;

use plotters::prelude::*;

use crate::optimize::error::OptimizeError;

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

/// Runs of one optimizer on one configuration, each its scores in evaluation order.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveGroup {
    /// The legend's text.
    pub label: String,
    /// The runs' scores.
    pub runs: Vec<Vec<f64>>,
}

/// Over the evaluations all runs reached (with a finite best): (evaluation, mean, lowest,
/// highest) of their best so far.
pub fn band(runs: &[Vec<f64>]) -> Vec<(f64, f64, f64, f64)> {
    let bests: Vec<Vec<f64>> = runs.iter().map(|r| best_so_far(r)).collect();
    let common = bests.iter().map(Vec::len).min().unwrap_or(0);
    (0..common)
        .filter_map(|i| {
            let at: Vec<f64> = bests.iter().map(|b| b[i]).collect();
            if !at.iter().all(|v| v.is_finite()) {
                return None;
            }
            let mean = at.iter().sum::<f64>() / at.len() as f64;
            let lo = at.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = at.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            Some(((i + 1) as f64, mean, lo, hi))
        })
        .collect()
}

/// A group as points: the mean (or the one run's) curve and, for several runs, the band.
struct Drawn {
    label: String,
    line: Vec<(f64, f64)>,
    band: Option<Vec<(f64, f64)>>,
}

fn drawn(g: &CurveGroup) -> Drawn {
    let b = band(&g.runs);
    let line = b.iter().map(|(x, m, _, _)| (*x, *m)).collect();
    let band = (g.runs.len() > 1).then(|| {
        b.iter()
            .map(|(x, _, lo, _)| (*x, *lo))
            .chain(b.iter().rev().map(|(x, _, _, hi)| (*x, *hi)))
            .collect()
    });
    Drawn {
        label: g.label.clone(),
        line,
        band,
    }
}

/// Draws each group's best-so-far curve (a band for several runs).
pub fn plot_curves(
    groups: &[CurveGroup],
    y_label: &str,
    output: &Path,
    size: (u32, u32),
) -> Result<(), OptimizeError> {
    let draw = OptimizeError::plot(output);
    let curves: Vec<Drawn> = groups.iter().map(drawn).collect();
    let all = curves
        .iter()
        .flat_map(|c| c.line.iter().chain(c.band.iter().flatten()));
    let (mut x1, mut y0, mut y1) = (1.0f64, f64::INFINITY, f64::NEG_INFINITY);
    for (x, y) in all {
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    if !y0.is_finite() {
        return Err(draw(&"no finite scores to plot"));
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
    for (i, c) in curves.into_iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        if let Some(band) = c.band {
            chart
                .draw_series(std::iter::once(Polygon::new(
                    band,
                    colour.mix(0.2).filled(),
                )))
                .map_err(|e| draw(&e))?;
        }
        chart
            .draw_series(LineSeries::new(c.line, colour.stroke_width(2)))
            .map_err(|e| draw(&e))?
            .label(c.label)
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
    fn several_runs_make_a_mean_and_a_band_over_their_common_length() {
        let b = band(&[
            vec![1.0, 3.0, 2.0],
            vec![2.0, 2.0],
            vec![f64::NAN, 5.0, 6.0],
        ]);
        // The third run has no finite best at evaluation 1; the second stops at 2.
        assert_eq!(b, vec![(2.0, 10.0 / 3.0, 2.0, 5.0)]);
    }

    #[test]
    fn best_so_far_ignores_failures() {
        let b = best_so_far(&[1.0, f64::NEG_INFINITY, 0.5, 2.0, f64::NAN]);
        assert_eq!(b, vec![1.0, 1.0, 1.0, 2.0, 2.0]);
    }
}
