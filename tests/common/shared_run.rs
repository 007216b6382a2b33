//! What the shared-store tests share: the GA run they compare, its one-process SQLite
//! reference, and the stored evaluations and worker reports they read back.

use super::pg::{Pg, output, spawn, text};

/// The configuration the runs optimize.
pub const GA: &str = "configs/experiment1_ga.simulation.xml";

/// The lines that state the result: best score and best values.
pub fn result_lines(out: &str) -> Vec<String> {
    out.lines()
        .skip_while(|l| !l.starts_with("best score"))
        .map(str::to_string)
        .collect()
}

/// `optimize` arguments of the GA runs below.
pub fn ga_args<'a>(evals: &'a str, duration: &'a str, store: &'a str) -> Vec<&'a str> {
    vec![
        "optimize",
        GA,
        "--max-evals",
        evals,
        "--duration",
        duration,
        "--quiet",
        "--store",
        store,
    ]
}

/// The same run on a SQLite store, in one process: its best and its store.
pub fn sqlite_run(name: &str, evals: &str, duration: &str) -> (Vec<String>, String) {
    let dir = super::scratch(name);
    let path = dir.join("reference.sqlite").display().to_string();
    let (ok, out, err) = super::proleg(&ga_args(evals, duration, &path));
    assert!(ok, "{err}");
    let lines = result_lines(&out);
    assert_eq!(lines.len(), 6, "{out}");
    (lines, path)
}

/// Every evaluation of a store's runs as (number, round, score, best so far, genome, engine
/// scores), by `proleg results --export` (store name and wall seconds left out).
pub fn evaluations(pg: &Pg, store: &str, name: &str) -> Vec<String> {
    let tsv = super::scratch(name).join("evaluations.tsv");
    let out = output(pg.proleg(&["results", store, "--export", tsv.to_str().unwrap()]));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let all = std::fs::read_to_string(&tsv).unwrap();
    let rows = super::table_columns(
        &all,
        &[
            "evaluation",
            "round",
            "score",
            "best",
            "genome",
            "engine_scores",
        ],
    );
    assert!(!rows.is_empty());
    rows
}

/// True once the driver has made the store's tables.
pub const HAS_STORE: &str = "SELECT to_regclass('evaluations') IS NOT NULL";

/// (written, discarded) of a worker's report.
pub fn worker_counts(out: &str) -> (u64, u64) {
    let number_before = |marker: &str| -> u64 {
        out.split(marker)
            .next()
            .and_then(|head| head.split_whitespace().last())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no '{marker}' in {out}"))
    };
    (
        number_before(" evaluations written"),
        number_before(" late results discarded"),
    )
}

/// A driver of the GA (`evals` evaluations of `duration` s, no threads of its own) on a
/// fresh database `db` of `pg`, once it has made the store: its URL and the driver.
pub fn driver_on_fresh_database(
    pg: &Pg,
    db: &str,
    evals: &str,
    duration: &str,
) -> (String, std::process::Child) {
    let url = pg.database(db);
    let mut args = ga_args(evals, duration, &url);
    args.extend(["--workers", "0"]);
    let mut driver = spawn(pg.proleg(&args));
    pg.wait_until(db, HAS_STORE, &mut driver);
    (url, driver)
}
