//! A stored MAP-Elites run's archive, rebuilt from its stored files and evaluations (the
//! archive is a function of them: [`Archive::replayed`]), and drawn as a heat map over its
//! two descriptors.

use std::path::Path;

use plotters::prelude::*;

use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::map_elites::Archive;
use crate::optimize::map_elites::map_axes;
use crate::optimize::prepare::prepare;
use crate::optimize::shared::stored_simulation;
use crate::optimize::store::Store;

/// Run `run`'s stored configuration, loaded here with `registry`'s module types.
pub(crate) fn stored_run(
    store: &mut Store,
    run: i64,
    registry: &ModuleRegistry,
) -> Result<crate::config::Simulation, OptimizeError> {
    let spec = store.run_spec(run)?;
    crate::optimize::shared::candidate_run(&spec)
        .map_err(|why| OptimizeError::Unevaluable { run, why })?;
    stored_simulation(&spec, registry).map_err(|why| OptimizeError::Unevaluable { run, why })
}

/// A MAP-Elites run's archive and what its axes are.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredArchive {
    /// The run.
    pub run: i64,
    /// The archive its evaluations make.
    pub archive: Archive,
    /// The two descriptors' genes, as `proleg results` names genes.
    pub labels: [String; 2],
    /// A co-design run's best body: modules, orientations (`p`/`y` per joint), parts.
    pub best_body: Option<String>,
}

impl StoredArchive {
    /// One line: coverage and QD-score (elites' scores above 0).
    pub fn summary(&self) -> String {
        let a = &self.archive;
        let filled = a.cells.iter().filter(|c| c.is_some()).count();
        let body = self
            .best_body
            .as_ref()
            .map(|b| format!("; best body {b}"))
            .unwrap_or_default();
        format!(
            "run {} archive: {filled} of {} cells ({:.1} %), QD-score {:.4}, over {} x {}{body}",
            self.run,
            a.cells.len(),
            100.0 * a.coverage(),
            a.qd_score(0.0),
            self.labels[0],
            self.labels[1]
        )
    }
}

/// The archive of `run` in `store` when the run is a MAP-Elites run (`None` otherwise),
/// its configuration loaded with `registry`'s module types.
pub fn stored_archive(
    store: &mut Store,
    run: i64,
    registry: &ModuleRegistry,
) -> Result<Option<StoredArchive>, OptimizeError> {
    let sim = stored_run(store, run, registry)?;
    let Some(crate::config::optimizer::Algorithm::MapElites(m)) =
        sim.optimizer.as_ref().map(|o| &o.spec.algorithm)
    else {
        return Ok(None);
    };
    let (space, _) = prepare(&sim, registry)?;
    let design = sim
        .optimizer
        .as_ref()
        .and_then(crate::optimize::design::DesignSpace::from_model);
    let axes = map_axes(m, &space, design.clone())?;
    let labels = [axes[0].label(&space), axes[1].label(&space)];
    let evaluations = store.evaluations(run)?;
    let archive = Archive::replayed(
        axes,
        evaluations
            .iter()
            .map(|e| (&e.genome, e.measures.as_slice(), e.score)),
    );
    let best_body = design
        .zip(archive.best())
        .map(|(d, (g, _))| d.body(g, "best").summary());
    Ok(Some(StoredArchive {
        run,
        archive,
        labels,
        best_body,
    }))
}

/// Draws the archive as a heat map: one square per cell, coloured by its elite's score
/// (empty cells white), the descriptors' places in their ranges on the axes.
pub fn plot_map(
    a: &StoredArchive,
    y_label: &str,
    output: &Path,
    size: (u32, u32),
) -> Result<(), OptimizeError> {
    let draw = OptimizeError::plot(output);
    let scores: Vec<f64> = a.archive.cells.iter().flatten().map(|c| c.1).collect();
    let (lo, hi) = scores
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), s| {
            (l.min(*s), h.max(*s))
        });
    if !lo.is_finite() {
        return Err(draw(&"the archive holds no elite"));
    }
    let [xa, ya] = &a.archive.axes;
    let root = BitMapBackend::new(output, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw(&e))?;
    let caption = format!(
        "MAP-Elites archive of run {}: {y_label} {lo:.3} (blue) .. {hi:.3} (red)",
        a.run
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, ("monospace", 16))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0f64, 0.0..1.0f64)
        .map_err(|e| draw(&e))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .axis_desc_style(("monospace", 14))
        .x_desc(format!("{} ({})", a.labels[0], xa.scale()))
        .y_desc(format!("{} ({})", a.labels[1], ya.scale()))
        .draw()
        .map_err(|e| draw(&e))?;
    let (w, h) = (1.0 / xa.bins as f64, 1.0 / ya.bins as f64);
    let cells = a.archive.cells.iter().enumerate().filter_map(|(i, c)| {
        let (_, s) = c.as_ref()?;
        let t = if hi > lo { (s - lo) / (hi - lo) } else { 1.0 };
        let (x, y) = ((i % xa.bins) as f64 * w, (i / xa.bins) as f64 * h);
        let colour = HSLColor(0.66 * (1.0 - t), 0.85, 0.5);
        Some(Rectangle::new([(x, y), (x + w, y + h)], colour.filled()))
    });
    chart.draw_series(cells).map_err(|e| draw(&e))?;
    root.present().map_err(|e| draw(&e))
}
