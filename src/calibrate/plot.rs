//! The calibration's picture: per joint, the recorded real angle against the replayed one
//! with the robot file's servo model (before) and with the fitted one (after).

use std::path::Path;

use plotters::prelude::*;

use crate::calibrate::recording::Recording;
use crate::calibrate::replay::replay;
use crate::calibrate::{CalibrateError, CalibrationReport};

/// Draws `report`'s joints (at most 6, stacked) into the PNG `output`.
pub fn plot_calibration(
    rec: &Recording,
    report: &CalibrationReport,
    output: &Path,
) -> Result<(), CalibrateError> {
    let fail = |e: &dyn std::fmt::Display| CalibrateError::Plot {
        file: output.to_path_buf(),
        message: e.to_string(),
    };
    let joints = rec.joints().min(6);
    let root = BitMapBackend::new(output, (1100, 220 * joints.max(1) as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let panels = root.split_evenly((joints.max(1), 1));
    let (t0, t1) = (
        rec.times.first().copied().unwrap_or(0.0),
        rec.times.last().copied().unwrap_or(1.0).max(1e-3),
    );
    for (j, panel) in panels.iter().enumerate().take(joints) {
        let start = rec.real[j].first().copied().unwrap_or(0.0);
        let before = replay(&report.before[j], &rec.times, &rec.desired[j], start);
        let after = replay(&report.after(j), &rec.times, &rec.desired[j], start);
        let all = rec.real[j].iter().chain(&before).chain(&after);
        let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(*v), h.max(*v))
        });
        let pad = ((hi - lo) * 0.05).max(0.5);
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!(
                    "J{}: recorded (black), robot file's servo (red, RMS {:.2} deg), calibrated (blue, RMS {:.2} deg)",
                    j + 1,
                    report.rms_before[j],
                    report.rms_after[j]
                ),
                ("monospace", 14),
            )
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
            .map_err(|e| fail(&e))?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("deg")
            .draw()
            .map_err(|e| fail(&e))?;
        for (series, colour) in [(&rec.real[j], BLACK), (&before, RED), (&after, BLUE)] {
            let points = rec.times.iter().copied().zip(series.iter().copied());
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(1)))
                .map_err(|e| fail(&e))?;
        }
    }
    root.present().map_err(|e| fail(&e))
}
