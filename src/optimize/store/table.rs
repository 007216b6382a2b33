//! Every evaluation of a store's runs as one table: the rows `proleg results --export`
//! writes as TSV and the Python package hands to pandas (`proleg.read_store`), one
//! construction for both.

use crate::optimize::store::{RunRow, Store, StoreError, StoredEval, engine_scores_text};

/// The table's columns, in order.
pub const COLUMNS: [&str; 11] = [
    "store",
    "run",
    "evaluation",
    "round",
    "score",
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
}

impl EvaluationRow {
    /// The row's fields as text, in [`COLUMNS`] order (lists joined by spaces).
    pub fn fields(&self) -> [String; 11] {
        let e = &self.eval;
        let join = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(" ");
        [
            self.store.clone(),
            self.run.to_string(),
            e.number.to_string(),
            e.round.to_string(),
            e.score.to_string(),
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
        rows.extend(
            store
                .evaluations(r.id)?
                .into_iter()
                .map(|eval| EvaluationRow {
                    store: shown.clone(),
                    run: r.id,
                    eval,
                }),
        );
    }
    Ok(rows)
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
