//! One conformance suite for both experiment stores: the embedded SQLite store and the shared
//! PostgreSQL one (on the private server `scripts/test` starts) must do the same through
//! `ExperimentStore`: runs registered with their files and episodes, evaluations stored once
//! and read back by number, unfinished runs found, the best of each run, and a stored
//! evaluation that cannot be read back is an error naming its run and evaluation, never a
//! genome silently cut short.

mod common;

use std::path::PathBuf;

use proleg::config::simulation::EngineKind;
use proleg::optimize::store::{
    EpisodeRecord, ExperimentStore, PgStore, RunInfo, SqliteStore, StoreError, StoredEval,
};

fn info(seed: u64) -> RunInfo {
    RunInfo {
        config: "configs/demo.simulation.xml".into(),
        algorithm: "genetic algorithm".into(),
        seed,
        fitness: "displacement".into(),
        duration: 2.0,
        genes: vec!["Amplitude[0]".into(), "Phase_Difference[0]".into()],
    }
}

fn eval(number: u64, score: f64) -> StoredEval {
    StoredEval {
        number,
        round: number / 2,
        genome: vec![number as u32, 7],
        values: vec![10.0 + number as f64, 45.5],
        score,
        engines: vec![
            (EngineKind::Rapier, score),
            (EngineKind::Mujoco, score / 2.0),
        ],
        // A co-design body rejected unrun keeps its reason.
        measures: vec![number as f64 * 0.01, 45.5],
        rejected: (score == f64::NEG_INFINITY)
            .then(|| "self-intersecting start pose: links A and B overlap by 5 mm".into()),
        wall: 0.25,
    }
}

/// What every store must do, the same way.
fn conformance(store: &mut dyn ExperimentStore) {
    let files = vec![("a.xml".to_string(), "<a/>".to_string())];
    let episodes = vec![EpisodeRecord {
        episode: 0,
        seed: 99,
        draws: "friction 0.8".into(),
    }];
    let run = store
        .start_run(&info(1), "proleg test", &files, &episodes)
        .expect("start");
    let other = store
        .start_run(&info(2), "proleg test", &[], &[])
        .expect("start");
    assert_ne!(run, other);
    assert_eq!(store.find_unfinished(&info(1)).expect("find"), Some(run));
    assert_eq!(store.find_unfinished(&info(3)).expect("find"), None);

    let spec = store.run_spec(run).expect("spec");
    assert_eq!(
        (spec.info, spec.program.as_str(), spec.files, spec.episodes),
        (info(1), "proleg test", files, episodes)
    );
    assert!(!spec.finished);

    // Out of order, in two transactions, a failed episode (NaN) and a rejected body
    // (-inf, with its reason) among them.
    let first = [eval(2, 1.5), eval(0, 0.5), eval(4, f64::NEG_INFINITY)];
    let second = [eval(1, f64::NAN), eval(3, 3.25)];
    store.record(run, 5, &first).expect("record");
    store.record(run, 5, &second).expect("record");
    let back = store.evaluations(run).expect("evaluations");
    assert_eq!(
        back.iter().map(|e| e.number).collect::<Vec<_>>(),
        [0, 1, 2, 3, 4]
    );
    assert_eq!(back[0], eval(0, 0.5));
    assert!(back[1].score.is_nan());
    assert_eq!(back[3], eval(3, 3.25));
    assert_eq!(back[4], eval(4, f64::NEG_INFINITY));
    assert!(back[4].rejected.is_some());
    assert_eq!(store.evaluations_from(run, 2).expect("from").len(), 3);
    assert!(store.evaluations(other).expect("none").is_empty());

    let rows = store.runs().expect("runs");
    let row = rows
        .iter()
        .find(|r| r.id == run)
        .expect("the run is listed");
    assert_eq!((row.evaluations, row.best_score), (5, Some(3.25)));
    assert_eq!(row.best_values.as_deref(), Some(&[13.0, 45.5][..]));
    assert_eq!(row.best_engines, eval(3, 3.25).engines);

    assert!(!store.run_finished(run).expect("finished?"));
    store.finish_run(run).expect("finish");
    assert!(store.run_finished(run).expect("finished?"));
    assert_eq!(store.find_unfinished(&info(1)).expect("find"), None);

    match store.run_spec(run + 100) {
        Err(StoreError::NoRun { run: r, .. }) => assert_eq!(r, run + 100),
        other => panic!("expected NoRun, got {other:?}"),
    }
}

/// The evaluation `corrupt` damaged in its genome column (run, number) must be named.
fn corrupt_genome_is_named(store: &mut dyn ExperimentStore, run: i64) {
    match store.evaluations(run) {
        Err(StoreError::Corrupt {
            run: r,
            evaluation,
            column,
            text,
            ..
        }) => {
            assert_eq!(
                (r, evaluation.as_str(), column, text.as_str()),
                (run, "evaluation 1", "genome", "4 x 2")
            );
        }
        other => panic!("expected a corrupt-row error, got {other:?}"),
    }
}

fn sqlite_file(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("proleg_conformance_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join(format!("{tag}.sqlite"));
    for f in [&file, &file.with_extension("sqlite-wal")] {
        if f.exists() {
            std::fs::remove_file(f).expect("remove an old store");
        }
    }
    file
}

fn pg_store(db: &str) -> PgStore {
    let pg = common::pg::server();
    pg.database(db);
    pg.open_store(db)
}

#[test]
fn the_sqlite_store_conforms() {
    let mut store = SqliteStore::open(&sqlite_file("conforms")).expect("open");
    conformance(&mut store);
}

#[test]
fn the_postgres_store_conforms() {
    let mut store = pg_store("conformance_suite");
    conformance(&mut store);
}

#[test]
fn a_corrupt_genome_in_sqlite_is_an_error_naming_run_and_evaluation() {
    let file = sqlite_file("corrupt");
    let mut store = SqliteStore::open(&file).expect("open");
    let run = store.start_run(&info(1), "t", &[], &[]).expect("start");
    store
        .record(run, 1, &[eval(0, 1.0), eval(1, 2.0)])
        .expect("record");
    let conn = rusqlite::Connection::open(&file).expect("open the file");
    conn.execute(
        "UPDATE evaluations SET genome = '4 x 2' WHERE run = ?1 AND number = 1",
        [run],
    )
    .expect("damage");
    corrupt_genome_is_named(&mut store, run);
}

#[test]
fn a_corrupt_genome_in_postgres_is_an_error_naming_run_and_evaluation() {
    let mut store = pg_store("conformance_corrupt");
    let run = store.start_run(&info(1), "t", &[], &[]).expect("start");
    store
        .record(run, 1, &[eval(0, 1.0), eval(1, 2.0)])
        .expect("record");
    common::pg::server()
        .connect("conformance_corrupt")
        .execute(
            "UPDATE evaluations SET genome = '4 x 2' WHERE run = $1 AND number = 1",
            &[&run],
        )
        .expect("damage");
    corrupt_genome_is_named(&mut store, run);
}
