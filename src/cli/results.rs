//! `proleg results`: the runs of one or more experiment stores, their best candidates,
//! learning curves (PNG, all runs together as in thesis fig. 7.1a), every evaluation as
//! TSV, and an evaluation as a 3D replay page (`--html`).

use std::path::{Path, PathBuf};

use crate::cli::error::CliError;
use crate::control::ModuleRegistry;
use crate::optimize::archive::{StoredArchive, plot_map, stored_archive};
use crate::optimize::curve::{CurveGroup, plot_curves};
use crate::optimize::export::export_candidate;
use crate::optimize::replay::{Which, load_replay};
use crate::optimize::store::table::{self, evaluation_rows};
use crate::optimize::store::{RunRow, Store, StoreLocation};

/// Which curve a run belongs to: its configuration file's name and its optimizer.
type GroupKey = (String, String);
/// A run's id and its scores in evaluation order.
type RunScores = (i64, Vec<f64>);

/// `proleg results`: what the stores hold, drawn and exported.
#[derive(clap::Args, Debug)]
pub struct ResultsArgs {
    /// Stores written by `proleg optimize`: SQLite files or postgres:// URLs (runs of all
    /// are drawn together).
    #[arg(required = true)]
    pub stores: Vec<String>,
    /// Only these runs (comma-separated ids).
    #[arg(long, value_delimiter = ',')]
    pub runs: Vec<i64>,
    /// Draw the learning curves (best score so far per evaluation) into this PNG.
    #[arg(long)]
    pub curve: Option<PathBuf>,
    /// Write every evaluation as TSV.
    #[arg(long)]
    pub export: Option<PathBuf>,
    /// Draw the first MAP-Elites run's archive (best score per cell of its two
    /// descriptors) into this PNG.
    #[arg(long)]
    pub map: Option<PathBuf>,
    /// Write the first run's evaluation N (or the best) into the folder -o names, a folder
    /// that runs on its own anywhere: the run's configuration files as stored, and a
    /// simulation file that runs the candidate with the run's seed and duration (a co-design
    /// run's design.simulation.xml with its robot and actuation, any other run's
    /// candidate.simulation.xml with its actuation and networks' weights files).
    #[arg(long, value_name = "N|best", requires = "out")]
    pub export_robot: Option<String>,
    /// Write the first run's evaluation N (or the best), replayed as the optimization
    /// scored it, as a self-contained 3D replay page into the file -o names.
    #[arg(
        long,
        value_name = "N|best",
        requires = "out",
        conflicts_with = "export_robot"
    )]
    pub html: Option<String>,
    /// The folder --export-robot writes, or the page --html writes.
    #[arg(short, long)]
    pub out: Option<PathBuf>,
    /// Render a co-design run's best distinct bodies (the first run listed: choose it with
    /// --runs) off-screen, each replayed with its gait, into this PNG as a captioned grid.
    #[arg(long)]
    pub gallery: Option<PathBuf>,
    /// With --gallery: how many designs.
    #[arg(long, default_value_t = 6, requires = "gallery")]
    pub gallery_count: usize,
    /// With --gallery: each picture's size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x320", value_parser = crate::cli::parse_size, requires = "gallery")]
    pub gallery_tile: (u32, u32),
    /// With --gallery: the moment of each design's episode shown (simulated seconds).
    #[arg(long, default_value_t = 3.0, requires = "gallery")]
    pub gallery_at: f64,
}

impl ResultsArgs {
    /// The options of [`run`] these arguments ask for (the gallery is drawn by a window).
    pub fn options(&self) -> Result<ResultsOptions, CliError> {
        let export_robot = match self.export_robot.as_deref() {
            None => None,
            Some("best") => Some(None),
            Some(n) => Some(Some(n.parse().map_err(|_| CliError::Option {
                option: "--export-robot",
                value: n.to_string(),
                want: "give an evaluation number or best",
            })?)),
        };
        let html = match self.html.as_deref() {
            None => None,
            Some(text) => Some((Which::parse(text)?, self.out.clone().unwrap_or_default())),
        };
        Ok(ResultsOptions {
            stores: self.stores.clone(),
            runs: self.runs.clone(),
            curve: self.curve.clone(),
            export: self.export.clone(),
            map: self.map.clone(),
            export_robot: export_robot.map(|n| (n, self.out.clone().unwrap_or_default())),
            html,
        })
    }
}

/// Options of `proleg results`.
pub struct ResultsOptions {
    /// One or more stores (SQLite files or postgres:// URLs); their runs are listed and
    /// drawn together.
    pub stores: Vec<String>,
    /// Only these runs (default: all).
    pub runs: Vec<i64>,
    /// Draw the learning curves into this PNG.
    pub curve: Option<PathBuf>,
    /// Write every evaluation as TSV here.
    pub export: Option<PathBuf>,
    /// Draw the first MAP-Elites run's archive as a heat map into this PNG.
    pub map: Option<PathBuf>,
    /// Write an evaluation (its number, or `None`: the best) of the first run as
    /// configuration files into this folder (a co-design run's body, any other run's
    /// actuation file).
    pub export_robot: Option<(Option<u64>, PathBuf)>,
    /// Write an evaluation of the first run as a 3D replay page into this file.
    pub html: Option<(Which, PathBuf)>,
}

/// The runs of the stores, and the files written.
#[derive(Debug, Clone, PartialEq)]
pub struct ResultsReport {
    /// Each store (as it may be shown: no password) and its runs (those asked for).
    pub stores: Vec<(String, Vec<RunRow>)>,
    /// The learning curves' PNG, if drawn.
    pub curve: Option<PathBuf>,
    /// The evaluations' TSV, if written.
    pub export: Option<PathBuf>,
    /// The archives of the MAP-Elites runs among them.
    pub archives: Vec<StoredArchive>,
    /// The archive's heat map, if drawn.
    pub map: Option<PathBuf>,
    /// The exported candidate's main file (a design's simulation file, else the
    /// actuation file), if written.
    pub exported: Option<PathBuf>,
    /// The 3D replay page written: the evaluation's number, the file and its size (bytes).
    pub html: Option<(u64, PathBuf, u64)>,
}

impl std::fmt::Display for ResultsReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (path, runs) in &self.stores {
            if self.stores.len() > 1 {
                writeln!(f, "{path}:")?;
            }
            if runs.is_empty() {
                f.write_str("no runs stored\n")?;
            }
            for r in runs {
                describe(f, r)?;
            }
        }
        for a in &self.archives {
            writeln!(f, "{}", a.summary())?;
        }
        if let Some(png) = &self.curve {
            writeln!(f, "learning curves written to {}", png.display())?;
        }
        if let Some(png) = &self.map {
            writeln!(f, "archive map written to {}", png.display())?;
        }
        if let Some(sim) = &self.exported {
            writeln!(f, "candidate written: {}", sim.display())?;
        }
        if let Some((number, page, bytes)) = &self.html {
            writeln!(
                f,
                "3D replay of evaluation {number} written to {} ({:.2} MB)",
                page.display(),
                *bytes as f64 / 1e6
            )?;
        }
        if let Some(tsv) = &self.export {
            writeln!(f, "evaluations written to {}", tsv.display())?;
        }
        Ok(())
    }
}

fn describe(f: &mut std::fmt::Formatter<'_>, r: &RunRow) -> std::fmt::Result {
    writeln!(
        f,
        "run {:>3}  {}  {}  seed {}  {} ({} s)  {} evaluations{}",
        r.id,
        r.info.config,
        r.info.algorithm,
        r.info.seed,
        r.info.fitness,
        r.info.duration,
        r.evaluations,
        if r.finished {
            ""
        } else {
            "  (unfinished: --resume continues it)"
        }
    )?;
    if r.rejected > 0 {
        writeln!(
            f,
            "         {} candidates rejected (bodies unrun, modules failed; each with its reason: --export lists them)",
            r.rejected
        )?;
    }
    if let (Some(s), Some(v)) = (r.best_score, &r.best_values) {
        let engines: Vec<String> = r
            .best_engines
            .iter()
            .map(|(k, e)| format!("{k} {e:.4}"))
            .collect();
        match engines.as_slice() {
            [] => writeln!(f, "         best {s:.4}")?,
            _ => writeln!(f, "         best {s:.4} ({})", engines.join(", "))?,
        }
        // A network's weights are many: the first few stand for them.
        const SHOWN: usize = 12;
        for (g, val) in r.info.genes.iter().zip(v).take(SHOWN) {
            writeln!(f, "           {g:<40} {val}")?;
        }
        if r.info.genes.len() > SHOWN {
            writeln!(
                f,
                "           ... and {} more values",
                r.info.genes.len() - SHOWN
            )?;
        }
    }
    Ok(())
}

/// Lists the runs and best candidates of the stores; draws and exports as asked.
pub fn run(o: &ResultsOptions, registry: &ModuleRegistry) -> Result<ResultsReport, CliError> {
    let mut opened: Vec<(Store, Vec<RunRow>)> = Vec::new();
    for text in &o.stores {
        let mut store = Store::open_existing(&StoreLocation::parse(text)?)?;
        let mut runs = store.runs()?;
        if !o.runs.is_empty() {
            runs.retain(|r| o.runs.contains(&r.id));
        }
        opened.push((store, runs));
    }
    if let Some(missing) = o.runs.iter().find(|id| {
        !opened
            .iter()
            .any(|(_, runs)| runs.iter().any(|r| r.id == **id))
    }) {
        return Err(CliError::NoRun(*missing));
    }
    let mut archives = Vec::new();
    for (store, runs) in &mut opened {
        for r in runs.iter() {
            if let Some(a) = stored_archive(store, r.id, registry)? {
                archives.push(a);
            }
        }
    }
    if let Some(png) = &o.map {
        let first = archives.first().ok_or(CliError::Options(
            "--map draws a MAP-Elites run's archive; the runs asked for hold none",
        ))?;
        let fitness = opened
            .iter()
            .flat_map(|(_, runs)| runs.iter())
            .find(|r| r.id == first.run)
            .map(|r| r.info.fitness.clone())
            .unwrap_or_else(|| "score".into());
        plot_map(first, &fitness, png, (900, 760))?;
    }
    let exported = match &o.export_robot {
        Some((number, dir)) => {
            let (store, runs) = opened.first_mut().ok_or(CliError::NoRun(0))?;
            let run = runs.first().ok_or(CliError::NoRun(0))?.id;
            Some(export_candidate(store, run, *number, dir, registry)?)
        }
        None => None,
    };
    let html = match &o.html {
        Some((which, file)) => Some(replay_page(&mut opened, *which, file, registry)?),
        None => None,
    };
    if let Some(png) = &o.curve {
        let curves = curve_groups(&mut opened)?;
        let fitness = opened
            .iter()
            .find_map(|(_, runs)| runs.first())
            .map(|r| r.info.fitness.clone())
            .unwrap_or_else(|| "score".into());
        plot_curves(&curves, &fitness, png, (1100, 600))?;
    }
    if let Some(tsv) = &o.export {
        let mut rows = Vec::new();
        for (store, runs) in &mut opened {
            rows.extend(evaluation_rows(store, runs)?);
        }
        std::fs::write(tsv, table::tsv(&rows)).map_err(CliError::write(tsv))?;
    }
    Ok(ResultsReport {
        stores: opened
            .into_iter()
            .map(|(store, runs)| (store.describe(), runs))
            .collect(),
        curve: o.curve.clone(),
        export: o.export.clone(),
        archives,
        map: o.map.clone(),
        exported,
        html,
    })
}

/// Writes `which` evaluation of the first run as a 3D replay page into `file`: its number,
/// the file and its size.
fn replay_page(
    opened: &mut [(Store, Vec<RunRow>)],
    which: Which,
    file: &Path,
    registry: &ModuleRegistry,
) -> Result<(u64, PathBuf, u64), CliError> {
    let (store, runs) = opened.first_mut().ok_or(CliError::NoRun(0))?;
    let run = runs.first().ok_or(CliError::NoRun(0))?.id;
    let number = which.number(store, run)?;
    let replay = load_replay(store, run, number, None, registry)?;
    let stream = replay.pose_stream(registry, crate::playback::DEFAULT_FPS)?;
    let bytes = crate::playback::page::write_standalone(file, &[&stream])?;
    Ok((number, file.to_path_buf(), bytes))
}

/// The runs' learning curves: runs of one optimizer on one configuration (seeds) make one
/// group, drawn as a band.
fn curve_groups(
    opened: &mut [(Store, Vec<RunRow>)],
) -> Result<Vec<CurveGroup>, crate::optimize::store::StoreError> {
    let mut groups: Vec<(GroupKey, Vec<RunScores>)> = Vec::new();
    for (store, runs) in opened.iter_mut() {
        for r in runs.iter() {
            let scores: Vec<f64> = store.evaluations(r.id)?.iter().map(|e| e.score).collect();
            let name = Path::new(&r.info.config)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let key = (name, r.info.algorithm.clone());
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, g)) => g.push((r.id, scores)),
                None => groups.push((key, vec![(r.id, scores)])),
            }
        }
    }
    Ok(groups
        .into_iter()
        .map(|((name, algorithm), runs)| CurveGroup {
            label: match runs.as_slice() {
                [(id, _)] => format!("{name} run {id} ({algorithm})"),
                _ => format!(
                    "{name} ({algorithm}): mean and range of {} runs",
                    runs.len()
                ),
            },
            runs: runs.into_iter().map(|(_, s)| s).collect(),
        })
        .collect())
}
