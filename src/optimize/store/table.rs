//! Every evaluation of a store's runs as one table: the rows `proleg results --export`
//! writes as TSV, the dashboard serves as CSV and JSON, and the Python package hands to
//! pandas (`proleg.read_store`), one construction for all, with each run's best score so
//! far computed here once ([`crate::optimize::curve::best_so_far`]).

use crate::optimize::curve::best_so_far;
use crate::optimize::store::{RunRow, Store, StoreError, StoredEval, engine_scores_text};

/// The table's columns, in order.
pub const COLUMNS: [&str; 12] = [
    "store",
    "run",
    "evaluation",
    "round",
    "score",
    "best",
    "wall_s",
    "genome",
    "values",
    "engine_scores",
    "rejected",
    "measures",
];

/// One evaluation of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaluationRow {
    /// The store as it may be shown (no password).
    pub store: String,
    /// The run.
    pub run: i64,
    /// The evaluation.
    pub eval: StoredEval,
    /// The run's best score up to and with this evaluation (`-inf` before any finite one).
    pub best: f64,
}

impl EvaluationRow {
    /// The row's fields as text, in [`COLUMNS`] order (lists joined by spaces).
    pub fn fields(&self) -> [String; 12] {
        let e = &self.eval;
        let join = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(" ");
        [
            self.store.clone(),
            self.run.to_string(),
            e.number.to_string(),
            e.round.to_string(),
            e.score.to_string(),
            self.best.to_string(),
            e.wall.to_string(),
            e.genome
                .iter()
                .map(|k| k.to_string())
                .collect::<Vec<_>>()
                .join(" "),
            join(&e.values),
            engine_scores_text(&e.engines),
            e.rejected.clone().unwrap_or_default(),
            join(&e.measures),
        ]
    }
}

/// Every finished evaluation of `runs` in `store`, run after run, by number.
pub fn evaluation_rows(
    store: &mut Store,
    runs: &[RunRow],
) -> Result<Vec<EvaluationRow>, StoreError> {
    let shown = store.describe();
    let mut rows = Vec::new();
    for r in runs {
        rows.extend(run_rows(&shown, r.id, store.evaluations(r.id)?));
    }
    Ok(rows)
}

/// The rows of run `run`'s evaluations `evals` (by number) of the store shown as `store`.
pub fn run_rows(store: &str, run: i64, evals: Vec<StoredEval>) -> Vec<EvaluationRow> {
    let scores: Vec<f64> = evals.iter().map(|e| e.score).collect();
    evals
        .into_iter()
        .zip(best_so_far(&scores))
        .map(|(eval, best)| EvaluationRow {
            store: store.to_string(),
            run,
            eval,
            best,
        })
        .collect()
}

/// The rows as CSV with a header line (the dashboard's download): the TSV's columns, a
/// field with a comma, a quote or a line break quoted.
pub fn csv(rows: &[EvaluationRow]) -> String {
    let field = |t: &str| {
        if t.contains([',', '"', '\n']) {
            format!("\"{}\"", t.replace('"', "\"\""))
        } else {
            t.to_string()
        }
    };
    let mut text = COLUMNS.join(",");
    text.push('\n');
    for r in rows {
        let fields: Vec<String> = r.fields().iter().map(|f| field(f)).collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

/// The rows as TSV with a header line (`proleg results --export`).
pub fn tsv(rows: &[EvaluationRow]) -> String {
    let mut text = COLUMNS.join("\t");
    text.push('\n');
    for r in rows {
        text.push_str(&r.fields().join("\t"));
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(number: u64, score: f64) -> StoredEval {
        StoredEval {
            number,
            round: 0,
            genome: vec![1, 2],
            values: vec![0.5, 1.5],
            score,
            engines: Vec::new(),
            rejected: None,
            measures: Vec::new(),
            wall: 0.25,
        }
    }

    #[test]
    fn rows_carry_the_best_so_far_and_read_the_same_as_tsv_and_csv() {
        let evals = vec![
            eval(0, 1.0),
            eval(1, f64::NEG_INFINITY),
            eval(2, 3.0),
            eval(3, 2.0),
        ];
        let rows = run_rows("a,store", 7, evals);
        let best: Vec<f64> = rows.iter().map(|r| r.best).collect();
        assert_eq!(best, [1.0, 1.0, 3.0, 3.0]);
        let tsv_lines: Vec<Vec<String>> = tsv(&rows)
            .lines()
            .map(|l| l.split('\t').map(str::to_string).collect())
            .collect();
        // The CSV quotes the store's name (it has a comma); otherwise the same fields.
        let csv_text = csv(&rows);
        let csv_lines: Vec<Vec<String>> = csv_text
            .lines()
            .map(|l| {
                l.replacen("\"a,store\"", "a;store", 1)
                    .split(',')
                    .map(|f| f.replace("a;store", "a,store"))
                    .collect()
            })
            .collect();
        assert_eq!(tsv_lines, csv_lines);
        assert_eq!(tsv_lines[0], COLUMNS);
        assert_eq!(tsv_lines[3][5], "3");
    }
}
