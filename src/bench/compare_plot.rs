//! The picture of a [`Comparison`]: on the left the centre-of-mass paths of every engine
//! seen from above (equal scales, start marked), on the right every joint's angle over
//! time, one colour per engine (plotters).

use std::path::Path;

use plotters::prelude::*;

use crate::bench::compare::{CompareError, Comparison};

/// Colour of the `i`-th engine's curves.
fn colour(i: usize) -> RGBColor {
    [
        RGBColor(200, 60, 30),
        RGBColor(30, 90, 200),
        RGBColor(40, 150, 60),
    ][i % 3]
}

/// Draws `c` into the PNG `output` (`size` pixels).
pub fn plot_comparison(
    c: &Comparison,
    output: &Path,
    size: (u32, u32),
) -> Result<(), CompareError> {
    let fail = |e: &dyn std::fmt::Display| CompareError::Plot {
        file: output.to_path_buf(),
        message: e.to_string(),
    };
    let root = BitMapBackend::new(output, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let (left, right) = root.split_horizontally(size.0 * 2 / 5);
    draw_paths(c, &left).map_err(|e| fail(&e))?;
    draw_joints(c, &right).map_err(|e| fail(&e))?;
    root.present().map_err(|e| fail(&e))
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
type DrawResult<'a> = plotters::prelude::DrawResult<(), BitMapBackend<'a>>;

/// The centre-of-mass paths, top view, on equal axes.
fn draw_paths<'a>(c: &Comparison, area: &Area<'a>) -> DrawResult<'a> {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in c.runs.iter().flat_map(|r| r.path.iter()) {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    let half = ((x1 - x0).max(y1 - y0) / 2.0).max(0.05) * 1.1;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let mut chart = ChartBuilder::on(area)
        .caption("centre of mass, top view", ("monospace", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d((cx - half)..(cx + half), (cy - half)..(cy + half))?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .draw()?;
    for (i, r) in c.runs.iter().enumerate() {
        let col = colour(i);
        chart
            .draw_series(LineSeries::new(r.path.iter().copied(), col.stroke_width(2)))?
            .label(format!("{} {:.3} m", r.engine, r.displacement))
            .legend(move |(px, py)| PathElement::new(vec![(px, py), (px + 20, py)], col));
        if let Some(start) = r.path.first() {
            chart.draw_series(std::iter::once(Circle::new(*start, 4, col.filled())))?;
        }
    }
    chart
        .configure_series_labels()
        .label_font(("monospace", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
}

/// Every joint's angle over time, one colour per engine.
fn draw_joints<'a>(c: &Comparison, area: &Area<'a>) -> DrawResult<'a> {
    let mut lim = 10.0f64;
    for (_, angles) in c.runs.iter().flat_map(|r| r.joints.iter()) {
        for a in angles {
            if a.is_finite() {
                lim = lim.max(a.abs());
            }
        }
    }
    let mut chart = ChartBuilder::on(area)
        .caption("joint angles", ("monospace", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..c.duration, -lim * 1.05..lim * 1.05)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("angle (deg)")
        .draw()?;
    for (i, r) in c.runs.iter().enumerate() {
        let col = colour(i);
        let joints = r.joints.first().map_or(0, |(_, a)| a.len());
        for j in 0..joints {
            let line = r
                .joints
                .iter()
                .filter_map(|(t, a)| a.get(j).map(|v| (*t, *v)));
            let series = chart.draw_series(LineSeries::new(line, col.mix(0.7).stroke_width(1)))?;
            if j == 0 {
                series
                    .label(format!("{} ({joints} joints)", r.engine))
                    .legend(move |(px, py)| PathElement::new(vec![(px, py), (px + 20, py)], col));
            }
        }
    }
    chart
        .configure_series_labels()
        .label_font(("monospace", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
}
