//! `read_store`: every evaluation of an experiment store (SQLite file or postgres:// URL)
//! as columns, the table `proleg results --export` writes (`proleg::optimize::store::table`).

use proleg::optimize::store::table::{COLUMNS, evaluation_rows};
use proleg::optimize::store::{Store, StoreLocation};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::other;

/// The evaluations of `runs` (all by default) in `location` as a dict of columns: `store`,
/// `run`, `evaluation`, `round`, `score`, `best` (the run's best so far), `wall_s`, lists
/// `genome`, `values`, `measures`, text `engine_scores` and `rejected`.
#[pyfunction]
#[pyo3(signature = (location, runs=None))]
pub fn read_store<'py>(
    py: Python<'py>,
    location: &str,
    runs: Option<Vec<i64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let where_ =
        StoreLocation::parse(location).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let rows = py
        .detach(|| -> Result<_, proleg::optimize::store::StoreError> {
            let mut store = Store::open_existing(&where_)?;
            let mut all = store.runs()?;
            if let Some(wanted) = &runs {
                all.retain(|r| wanted.contains(&r.id));
            }
            evaluation_rows(&mut store, &all)
        })
        .map_err(other)?;
    let d = PyDict::new(py);
    let text = |k: usize| -> Vec<String> { rows.iter().map(|r| r.fields()[k].clone()).collect() };
    d.set_item(COLUMNS[0], text(0))?;
    d.set_item(COLUMNS[1], rows.iter().map(|r| r.run).collect::<Vec<_>>())?;
    d.set_item(
        COLUMNS[2],
        rows.iter().map(|r| r.eval.number).collect::<Vec<_>>(),
    )?;
    d.set_item(
        COLUMNS[3],
        rows.iter().map(|r| r.eval.round).collect::<Vec<_>>(),
    )?;
    d.set_item(
        COLUMNS[4],
        rows.iter().map(|r| r.eval.score).collect::<Vec<_>>(),
    )?;
    d.set_item(COLUMNS[5], rows.iter().map(|r| r.best).collect::<Vec<_>>())?;
    d.set_item(
        COLUMNS[6],
        rows.iter().map(|r| r.eval.wall).collect::<Vec<_>>(),
    )?;
    d.set_item(
        COLUMNS[7],
        rows.iter()
            .map(|r| r.eval.genome.clone())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        COLUMNS[8],
        rows.iter()
            .map(|r| r.eval.values.clone())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(COLUMNS[9], text(9))?;
    d.set_item(COLUMNS[10], text(10))?;
    d.set_item(
        COLUMNS[11],
        rows.iter()
            .map(|r| r.eval.measures.clone())
            .collect::<Vec<_>>(),
    )?;
    Ok(d)
}
