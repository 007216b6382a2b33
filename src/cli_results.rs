//! `proleg results`: the runs of an experiment store, their best candidates, learning
//! curves (PNG) and every evaluation as TSV.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use proleg::optimize::curve::plot_curves;
use proleg::optimize::store::Store;

/// Options of `proleg results`.
pub struct ResultsOptions {
    pub store: PathBuf,
    /// Only these runs (default: all).
    pub runs: Vec<i64>,
    pub curve: Option<PathBuf>,
    pub export: Option<PathBuf>,
}

pub fn run(o: &ResultsOptions) -> Result<String, String> {
    if !o.store.exists() {
        return Err(format!("{}: no such store", o.store.display()));
    }
    let store = Store::open(&o.store)?;
    let mut runs = store.runs()?;
    if !o.runs.is_empty() {
        runs.retain(|r| o.runs.contains(&r.id));
        if let Some(missing) = o.runs.iter().find(|id| !runs.iter().any(|r| r.id == **id)) {
            return Err(format!("{}: no run {missing}", o.store.display()));
        }
    }
    let mut out = String::new();
    for r in &runs {
        let _ = writeln!(
            out,
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
        );
        if let (Some(s), Some(v)) = (r.best_score, &r.best_values) {
            let _ = writeln!(out, "         best {s:.4}");
            for (g, val) in r.info.genes.iter().zip(v.split_whitespace()) {
                let _ = writeln!(out, "           {g:<40} {val}");
            }
        }
    }
    if runs.is_empty() {
        out.push_str("no runs stored\n");
    }
    if let Some(png) = &o.curve {
        let mut curves = Vec::new();
        for r in &runs {
            let scores: Vec<f64> = store.evaluations(r.id)?.iter().map(|e| e.score).collect();
            let name = Path::new(&r.info.config)
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            curves.push((
                format!("run {} {} ({})", r.id, name, r.info.algorithm),
                scores,
            ));
        }
        let fitness = runs
            .first()
            .map(|r| r.info.fitness.as_str())
            .unwrap_or("score");
        plot_curves(&curves, fitness, png, (1100, 600))?;
        let _ = writeln!(out, "learning curves written to {}", png.display());
    }
    if let Some(tsv) = &o.export {
        let mut text = String::from("run\tevaluation\tround\tscore\twall_s\tgenome\tvalues\n");
        for r in &runs {
            for e in store.evaluations(r.id)? {
                let g: Vec<String> = e.genome.iter().map(|k| k.to_string()).collect();
                let v: Vec<String> = e.values.iter().map(|k| k.to_string()).collect();
                let _ = writeln!(
                    text,
                    "{}\t{}\t{}\t{}\t{}\t{}\t{}",
                    r.id,
                    e.number,
                    e.round,
                    e.score,
                    e.wall,
                    g.join(" "),
                    v.join(" ")
                );
            }
        }
        std::fs::write(tsv, text).map_err(|e| format!("{}: cannot write: {e}", tsv.display()))?;
        let _ = writeln!(out, "evaluations written to {}", tsv.display());
    }
    Ok(out)
}
