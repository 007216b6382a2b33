//! An experiment store (SQLite) from raw bytes, as handed around with its runs: opened,
//! its runs listed, and each run's stored specification, evaluations (genomes, values,
//! engine scores, measures, rejection reasons) and state read, as `proleg results`,
//! `--resume` and the dashboard read them. Corrupt pages, wrong schemas and malformed
//! columns are errors naming the store, never a panic.

use proleg::optimize::store::{ExperimentStore, SqliteStore};

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let path =
        std::env::temp_dir().join(format!("proleg-fuzz-store-{}.sqlite", std::process::id()));
    // A journal left by the input before must not be applied to this one.
    for side in ["-wal", "-shm", "-journal"] {
        let mut p = path.clone().into_os_string();
        p.push(side);
        if std::fs::remove_file(&p).is_err() && std::path::Path::new(&p).exists() {
            return;
        }
    }
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let Ok(mut store) = SqliteStore::open(&path) else {
        return;
    };
    let Ok(runs) = store.runs() else {
        return;
    };
    let mut read = 0_usize;
    for run in runs.iter().take(4) {
        read += usize::from(store.run_spec(run.id).is_ok());
        read += store.evaluations(run.id).map_or(0, |e| e.len());
        read += usize::from(store.run_finished(run.id).is_ok());
        read += usize::from(store.find_unfinished(&run.info).is_ok());
    }
    std::hint::black_box(read);
}
