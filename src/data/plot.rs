//! `proleg data plot`: chosen series of a data file drawn as lines into a PNG (plotters),
//! with axes, units and a legend. Long series are thinned to a few points per pixel
//! column (keeping each bucket's minimum and maximum) before drawing.

use std::path::Path;

use plotters::prelude::*;

use crate::data::export::{SeriesSelector, XAxis, for_each_row};
use crate::data::read::DataError;

/// The unit of a series, by its B.8 name ("" when unknown).
pub fn unit_of(series: &str) -> &'static str {
    match series {
        "x_pos" | "y_pos" | "z_pos" | "range" => "m",
        "speed" | "average_com_speed" => "m/s",
        "alpha"
        | "beta"
        | "gamma"
        | "Angle"
        | "desired_angle"
        | "Phase"
        | "Phase_Difference"
        | "desired_joint_positions"
        | "real_joint_positions"
        | "Offset" => "deg",
        "servo_speeds" => "deg/s",
        "servo_currents" => "N m",
        "potential_energy" | "energy" => "J",
        "power" => "W",
        "Frequency" => "Hz",
        _ => "",
    }
}

/// What a plot drew.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotStats {
    /// Samples read.
    pub rows: u64,
    /// Series drawn.
    pub series: usize,
    /// Points drawn over all series.
    pub points_drawn: usize,
}

/// Draws the chosen series of `path` against `x` into the PNG `output` (`size` pixels).
pub fn plot(
    path: &Path,
    x: XAxis,
    wanted: &[SeriesSelector],
    output: &Path,
    size: (u32, u32),
) -> Result<PlotStats, DataError> {
    let fail = |message: String| DataError {
        file: output.to_path_buf(),
        line: None,
        message,
    };
    let mut xs: Vec<f64> = Vec::new();
    let mut ys: Vec<Vec<f64>> = Vec::new();
    let (rows, _info, cols) = for_each_row(path, x, wanted, |cols, xv, values| {
        if ys.is_empty() {
            ys = vec![Vec::new(); cols.len()];
        }
        xs.push(xv);
        for (y, v) in ys.iter_mut().zip(values) {
            y.push(*v);
        }
        Ok(())
    })?;
    if rows == 0 {
        return Err(DataError {
            file: path.to_path_buf(),
            line: None,
            message: "no frames to plot".into(),
        });
    }
    let finite = |v: &&f64| v.is_finite();
    let (x0, x1) = bounds(xs.iter().filter(finite));
    let (y0, y1) = bounds(ys.iter().flatten().filter(finite));
    let (x_label, y_unit) = axis_labels(x, wanted);
    let root = BitMapBackend::new(output, size).into_drawing_area();
    let draw = |e: &dyn std::fmt::Display| fail(format!("cannot draw: {e}"));
    root.fill(&WHITE).map_err(|e| draw(&e))?;
    let title = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("monospace", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| draw(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_unit)
        .draw()
        .map_err(|e| draw(&e))?;
    let buckets = (size.0 as usize).max(1);
    let mut points_drawn = 0;
    for (i, (col, y)) in cols.iter().zip(&ys).enumerate() {
        let points = thin(&xs, y, buckets);
        points_drawn += points.len();
        let colour = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))
            .map_err(|e| draw(&e))?
            .label(col.title.clone())
            .legend(move |(px, py)| PathElement::new(vec![(px, py), (px + 20, py)], colour));
    }
    chart
        .configure_series_labels()
        // DejaVu Sans loses the `j` of "joint" in plotters' bitmap text; the mono face keeps it.
        .label_font(("monospace", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| draw(&e))?;
    root.present().map_err(|e| draw(&e))?;
    Ok(PlotStats {
        rows,
        series: cols.len(),
        points_drawn,
    })
}

/// The axes' descriptions: the x axis's quantity, and the y axis's unit when every series
/// shares one.
fn axis_labels(x: XAxis, wanted: &[SeriesSelector]) -> (&'static str, String) {
    let units: Vec<&str> = wanted.iter().map(|w| unit_of(&w.series)).collect();
    let y_unit = if units.iter().all(|u| *u == units[0]) && !units[0].is_empty() {
        format!("value ({})", units[0])
    } else {
        "value".to_string()
    };
    let x_label = match x {
        XAxis::SimTime => "simulated time (s)",
        XAxis::RealTime => "real time since start (s)",
        XAxis::StepCount => "step",
        XAxis::Index => "frame index",
    };
    (x_label, y_unit)
}

/// Range of the values, widened a little (and made non-empty).
fn bounds<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(*v), b.max(*v))
    });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo { (hi - lo) * 0.05 } else { 0.5 };
    (lo - pad, hi + pad)
}

/// At most two points (min and max, in order) per bucket of consecutive samples.
fn thin(xs: &[f64], ys: &[f64], buckets: usize) -> Vec<(f64, f64)> {
    let n = xs.len().min(ys.len());
    let per = n.div_ceil(buckets).max(1);
    if per <= 2 {
        return xs
            .iter()
            .zip(ys)
            .filter(|(_, y)| y.is_finite())
            .map(|(x, y)| (*x, *y))
            .collect();
    }
    let mut out = Vec::with_capacity(2 * buckets);
    for start in (0..n).step_by(per) {
        let end = (start + per).min(n);
        let mut lo: Option<usize> = None;
        let mut hi: Option<usize> = None;
        for k in start..end {
            if !ys[k].is_finite() {
                continue;
            }
            if lo.is_none_or(|l| ys[k] < ys[l]) {
                lo = Some(k);
            }
            if hi.is_none_or(|h| ys[k] > ys[h]) {
                hi = Some(k);
            }
        }
        if let (Some(a), Some(b)) = (lo, hi) {
            let (a, b) = (a.min(b), a.max(b));
            out.push((xs[a], ys[a]));
            if b != a {
                out.push((xs[b], ys[b]));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_the_extremes() {
        let xs: Vec<f64> = (0..10_000).map(f64::from).collect();
        let ys: Vec<f64> = xs.iter().map(|x| (x / 100.0).sin()).collect();
        let t = thin(&xs, &ys, 100);
        assert!(t.len() <= 200);
        let max = t.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let min = t.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert!(max > 0.9999 && min < -0.9999);
        assert!(t.windows(2).all(|w| w[0].0 <= w[1].0));
    }
}
