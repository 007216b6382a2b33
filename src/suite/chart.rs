//! The suite's picture: one bar per task (its mean distance, each course by its lower
//! engine), held-out families in their own colour, the goal lines drawn across.

use std::path::Path;

use plotters::prelude::*;

use crate::suite::error::SuiteError;
use crate::suite::report::SuiteReport;

/// Draws `report` into the PNG `output` of `size` pixels; `goals` are the tasks' goal lines
/// (m), in the report's task order.
pub fn plot(
    report: &SuiteReport,
    goals: &[f64],
    output: &Path,
    size: (u32, u32),
) -> Result<(), SuiteError> {
    let draw = |e: &dyn std::fmt::Display| SuiteError::Chart {
        file: output.to_path_buf(),
        message: e.to_string(),
    };
    let n = report.tasks.len();
    if n == 0 {
        return Err(draw(&"no task has every course done"));
    }
    let top = axis_top(report, goals);
    let root = BitMapBackend::new(output, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw(&e))?;
    let caption = format!(
        "{} on suite {} ({})",
        report.controller,
        report.suite,
        report.engines.join(" + ")
    );
    let names: Vec<String> = report.tasks.iter().map(|t| t.task.clone()).collect();
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(120)
        .y_label_area_size(60)
        .build_cartesian_2d((0..n).into_segmented(), 0.0..top)
        .map_err(|e| draw(&e))?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n)
        // Plotters centres a turned label on its tick: as many spaces before the name put
        // all of it below the axis.
        .x_label_formatter(&|v| {
            let name = names.get(segment(v)).map_or("", String::as_str);
            format!("{}{name}", " ".repeat(name.len() + 3))
        })
        .x_label_style(
            ("sans-serif", 12)
                .into_font()
                .transform(FontTransform::Rotate90),
        )
        .y_desc("mean distance along the course (m)")
        .draw()
        .map_err(|e| draw(&e))?;
    let trained = RGBColor(70, 110, 200);
    let held = RGBColor(220, 120, 40);
    let held_out: Vec<bool> = report.tasks.iter().map(|t| t.held_out).collect();
    chart
        .draw_series(
            Histogram::vertical(&chart)
                .margin(6)
                .style_func(|x, _| {
                    let held_out = held_out.get(segment(x)).copied().unwrap_or(false);
                    if held_out { held } else { trained }.filled()
                })
                .data(report.tasks.iter().enumerate().map(|(i, t)| (i, t.mean))),
        )
        .map_err(|e| draw(&e))?;
    let goal_marks = goals.iter().enumerate().map(|(i, g)| {
        let (a, b) = (SegmentValue::Exact(i), SegmentValue::Exact(i + 1));
        PathElement::new(vec![(a, *g), (b, *g)], BLACK.stroke_width(2))
    });
    chart
        .draw_series(goal_marks)
        .map_err(|e| draw(&e))?
        .label("goal line")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    chart
        .draw_series(std::iter::empty::<Rectangle<(SegmentValue<usize>, f64)>>())
        .map_err(|e| draw(&e))?
        .label("held-out family")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], held.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| draw(&e))?;
    root.present().map_err(|e| draw(&e))
}

/// The y axis's top: a tenth above the longest bar or goal line.
fn axis_top(report: &SuiteReport, goals: &[f64]) -> f64 {
    let most = report
        .tasks
        .iter()
        .map(|t| t.mean)
        .chain(goals.iter().copied())
        .fold(0.0_f64, f64::max);
    (most * 1.1).max(0.1)
}

/// The task a segment of the x axis stands for (past the last: none, `usize::MAX`).
fn segment(v: &SegmentValue<usize>) -> usize {
    match v {
        SegmentValue::CenterOf(i) | SegmentValue::Exact(i) => *i,
        SegmentValue::Last => usize::MAX,
    }
}
