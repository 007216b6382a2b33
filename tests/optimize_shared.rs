//! The shared PostgreSQL store with real processes on a real server (`scripts/test` starts a
//! private one): a driver and worker processes find what one process finds on SQLite, and
//! a suite's episodes run by workers give the local table; a worker (of a run or of a
//! suite) or the driver killed with SIGKILL loses and duplicates nothing; bad stores are
//! one-line errors that never show the password. The faults across a network (a server
//! restarted, links cut or lossy) are `tests/shared_hosts.rs`.

mod common;

use std::path::Path;
use std::process::Child;
use std::time::Duration;

use common::pg::{Pg, output, server, spawn, text};
use common::shared_run::{
    GA, HAS_STORE, driver_on_fresh_database, evaluations, ga_args, result_lines, sqlite_run,
    worker_counts,
};
use proleg::config::{FsSource, RecordingSource, load_simulation_with};
use proleg::control::ModuleRegistry;
use proleg::optimize::evaluate::CandidateScore;
use proleg::optimize::shared::worker::{WorkerOptions, run_pool};
use proleg::optimize::store::pg_queue::Pending;
use proleg::optimize::store::{ExperimentStore, RunInfo, SCHEMA_VERSION, program_version};
use proleg::signal::StopFlag;

/// Runs `config` for `evals` evaluations of 1 s on SQLite, then as a driver without
/// local workers on database `name` with one least-privilege worker that has nothing but
/// the URL; both must succeed. Returns the server, the database's URL and the SQLite store.
fn one_worker_against_sqlite(name: &str, config: &str, evals: &str) -> (Pg, String, String) {
    let args = |store: &str| -> Vec<String> {
        [
            "optimize",
            config,
            "--max-evals",
            evals,
            "--duration",
            "1",
            "--quiet",
            "--store",
            store,
        ]
        .map(String::from)
        .to_vec()
    };
    let dir = common::scratch(name);
    let reference = dir.join("reference.sqlite").display().to_string();
    let a = args(&reference);
    let (ok, _, err) = common::proleg(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(ok, "{err}");
    let pg = server();
    let url = pg.database(name);
    let mut a = args(&url);
    a.extend(["--workers".into(), "0".into()]);
    let mut driver = spawn(pg.proleg(&a.iter().map(String::as_str).collect::<Vec<_>>()));
    pg.wait_until(name, HAS_STORE, &mut driver);
    let role = format!("proleg_worker_{name}");
    let password = format!("w-{name}");
    worker_role(&pg, name, &role, &password);
    let worker_url = url.replace("proleg_admin@", &format!("{role}@"));
    let worker = spawn(pg.proleg_as(
        &password,
        &[
            "worker",
            "--store",
            &worker_url,
            "--threads",
            "2",
            "--idle-exit",
            "1",
        ],
    ));
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let w = worker.wait_with_output().expect("worker");
    assert!(w.status.success(), "{}", text(&w.stderr));
    (pg, url, reference)
}

/// The least-privilege worker role of the README, on database `db`.
fn worker_role(pg: &Pg, db: &str, role: &str, password: &str) {
    let mut c = pg.connect(db);
    c.batch_execute(&format!(
        "DROP ROLE IF EXISTS {role};
         CREATE ROLE {role} LOGIN PASSWORD '{password}';
         GRANT CONNECT ON DATABASE {db} TO {role};
         GRANT USAGE ON SCHEMA public TO {role};
         GRANT SELECT ON proleg_meta, runs, run_files, run_episodes TO {role};
         GRANT SELECT, UPDATE (state, worker, attempt, lease_until, score, wall, engine_scores, rejected, measures) ON evaluations TO {role};"
    ))
    .expect("worker role");
}

#[test]
fn a_driver_and_three_workers_store_each_evaluation_once_and_find_the_sqlite_best() {
    let (expected, reference) = sqlite_run("optimize_shared_three", "75", "1");
    let pg = server();
    let (url, driver) = driver_on_fresh_database(&pg, "shared_three", "75", "1");
    worker_role(&pg, "shared_three", "proleg_worker_three", "w-three");
    let worker_url = url.replace("proleg_admin@", "proleg_worker_three@");
    let workers: Vec<Child> = (0..3)
        .map(|_| {
            spawn(pg.proleg_as(
                "w-three",
                &[
                    "worker",
                    "--store",
                    &worker_url,
                    "--threads",
                    "1",
                    "--idle-exit",
                    "1",
                ],
            ))
        })
        .collect();
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = text(&out.stdout);
    assert!(
        report.contains("75 evaluations in 3 rounds (75 simulated"),
        "{report}"
    );
    assert_eq!(result_lines(&report), expected, "{report}");
    // The same candidates with the same scores, evaluation by evaluation.
    assert_eq!(
        evaluations(&pg, &url, "optimize_shared_three_pg"),
        evaluations(&pg, &reference, "optimize_shared_three_sqlite")
    );

    let mut written = 0;
    for w in workers {
        let out = w.wait_with_output().expect("worker");
        assert!(out.status.success(), "{}", text(&out.stderr));
        let (n, discarded) = worker_counts(&text(&out.stdout));
        assert_eq!(discarded, 0);
        written += n;
    }
    assert_eq!(written, 75, "every evaluation computed exactly once");
    let mut c = pg.connect("shared_three");
    let row = c
        .query_one(
            "SELECT COUNT(*), COUNT(DISTINCT number), MIN(number), MAX(number),
                    COUNT(*) FILTER (WHERE state = 'done'), MAX(attempt), COUNT(DISTINCT worker)
             FROM evaluations",
            &[],
        )
        .unwrap();
    let get = |i: usize| row.get::<_, i64>(i);
    assert_eq!(
        (get(0), get(1), get(2), get(3), get(4)),
        (75, 75, 0, 74, 75)
    );
    assert_eq!(row.get::<_, i32>(5), 1, "no evaluation claimed twice");
    assert!(get(6) >= 2, "the workers shared the work: {}", get(6));
}

#[test]
fn a_robust_cma_es_run_scores_the_same_through_a_worker_as_in_one_process() {
    // CMA-ES through the queue, each candidate scored over 8 randomized episodes by a
    // least-privilege worker that has nothing but the URL: the same evaluations as SQLite.
    let (pg, url, reference) = one_worker_against_sqlite(
        "shared_robust",
        "configs/gait_from_scratch_robust.simulation.xml",
        "11",
    );
    assert_eq!(
        evaluations(&pg, &url, "shared_robust_pg"),
        evaluations(&pg, &reference, "shared_robust_sqlite")
    );
    let episodes: i64 = pg
        .connect("shared_robust")
        .query_one("SELECT COUNT(*) FROM run_episodes", &[])
        .unwrap()
        .get(0);
    assert_eq!(episodes, 8, "the episodes' seeds are stored with the run");
}

#[test]
fn an_es_run_trains_the_same_policy_through_a_worker_as_in_one_process() {
    // OpenAI-ES over a Policy module's 197 weights through the queue: the worker has nothing
    // but the URL, so the weights file comes from the store with the configuration; the
    // same evaluations (every weight of every candidate, every score) as SQLite.
    let (pg, url, reference) =
        one_worker_against_sqlite("shared_es", "configs/demo_policy_es.simulation.xml", "33");
    let shared = evaluations(&pg, &url, "shared_es_pg");
    assert_eq!(shared.len(), 33);
    assert_eq!(shared, evaluations(&pg, &reference, "shared_es_sqlite"));
}

#[test]
fn a_co_design_run_builds_the_same_bodies_through_a_worker_as_in_one_process() {
    // MAP-Elites over bodies and gaits through the queue: the worker builds every body
    // from the files stored with the run (the part files of every body the space holds
    // among them) and scores the same evaluations as one process on SQLite.
    let (pg, url, reference) = one_worker_against_sqlite(
        "shared_codesign",
        "configs/codesign_flat.simulation.xml",
        "30",
    );
    assert_eq!(
        evaluations(&pg, &url, "shared_codesign_pg"),
        evaluations(&pg, &reference, "shared_codesign_sqlite")
    );
    let parts: i64 = pg
        .connect("shared_codesign")
        .query_one(
            "SELECT COUNT(*) FROM run_files WHERE path LIKE '%parts/YY.kinbody.xml'",
            &[],
        )
        .unwrap()
        .get(0);
    assert_eq!(
        parts, 1,
        "the part no body of the run's own robot uses is stored"
    );
    let archive = |store: &str| {
        let out = output(pg.proleg(&["results", store]));
        assert!(out.status.success(), "{}", text(&out.stderr));
        text(&out.stdout)
            .lines()
            .find(|l| l.contains(" archive: "))
            .map(str::to_string)
            .expect("an archive line")
    };
    assert_eq!(archive(&url), archive(&reference));
}

#[test]
fn a_killed_worker_s_evaluation_is_claimed_again_and_nothing_is_lost() {
    let (expected, reference) = sqlite_run("optimize_shared_kill_worker", "30", "4");
    let pg = server();
    let url = pg.database("shared_kill_worker");
    let mut args = ga_args("30", "4", &url);
    args.extend(["--workers", "0"]);
    let mut driver = spawn(pg.proleg(&args));
    pg.wait_until("shared_kill_worker", HAS_STORE, &mut driver);
    let lost = kill_a_worker_holding_a_claim(&pg, "shared_kill_worker", &url);
    let survivor = lease_worker(&pg, &url, "6");
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    assert_eq!(
        evaluations(&pg, &url, "optimize_shared_kill_worker_pg"),
        evaluations(&pg, &reference, "optimize_shared_kill_worker_sqlite")
    );
    let out = survivor.wait_with_output().expect("worker");
    assert!(out.status.success(), "{}", text(&out.stderr));

    let mut c = pg.connect("shared_kill_worker");
    let row = c
        .query_one(
            "SELECT state, attempt, score IS NOT NULL FROM evaluations WHERE number = $1",
            &[&lost],
        )
        .unwrap();
    assert_eq!(row.get::<_, String>(0), "done");
    assert!(row.get::<_, i32>(1) >= 2, "claimed again after the kill");
    assert!(row.get::<_, bool>(2));
    let row = c
        .query_one(
            "SELECT COUNT(*), COUNT(*) FILTER (WHERE state = 'done') FROM evaluations",
            &[],
        )
        .unwrap();
    assert_eq!((row.get::<_, i64>(0), row.get::<_, i64>(1)), (30, 30));
}

#[test]
fn a_worker_started_before_its_driver_waits_for_the_store_and_evaluates_the_run() {
    let (expected, reference) = sqlite_run("optimize_shared_worker_first", "30", "1");
    let pg = server();
    let url = pg.database("shared_worker_first");
    let mut worker = spawn(pg.proleg(&[
        "worker",
        "--store",
        &url,
        "--threads",
        "2",
        "--idle-exit",
        "20",
    ]));
    // The worker says it waits (the database holds no store yet) before the driver starts.
    let stderr = worker.stderr.take().expect("piped");
    let (said, lines) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        use std::io::BufRead;
        let mut all = String::new();
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            let _ = said.send(line.clone());
            all.push_str(&line);
            all.push('\n');
        }
        all
    });
    let first = lines
        .recv_timeout(Duration::from_secs(60))
        .expect("the worker says something");
    assert!(
        first.contains("waiting for the store to appear") && first.contains("no proleg store"),
        "{first}"
    );
    let mut args = ga_args("30", "1", &url);
    args.extend(["--workers", "0"]);
    let out = output(pg.proleg(&args));
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    let w = worker.wait_with_output().expect("worker");
    assert!(w.status.success(), "{}", reader.join().unwrap_or_default());
    let (written, _) = worker_counts(&text(&w.stdout));
    assert_eq!(written, 30, "the driver evaluated nothing itself");
    assert_eq!(
        evaluations(&pg, &url, "optimize_shared_worker_first_pg"),
        evaluations(&pg, &reference, "optimize_shared_worker_first_sqlite")
    );
}

#[test]
fn a_worker_waiting_for_a_store_that_never_comes_gives_up_after_idle_exit() {
    let pg = server();
    let url = pg.database("shared_no_driver");
    let out = output(pg.proleg(&["worker", "--store", &url, "--idle-exit", "2"]));
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("waiting for the store to appear"), "{err}");
    assert!(err.contains("no proleg store in this database"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_killed_driver_resumes_to_the_same_best() {
    let (expected, reference) = sqlite_run("optimize_shared_kill_driver", "75", "1");
    let pg = server();
    let url = pg.database("shared_kill_driver");
    let mut args = ga_args("75", "1", &url);
    args.extend(["--workers", "1", "--lease", "2"]);
    let mut driver = spawn(pg.proleg(&args));
    pg.wait_until("shared_kill_driver", HAS_STORE, &mut driver);
    pg.wait_until(
        "shared_kill_driver",
        "SELECT COUNT(*) >= 35 FROM evaluations WHERE state = 'done'",
        &mut driver,
    );
    driver.kill().expect("SIGKILL");
    let _ = driver.wait();

    let mut args: Vec<&str> = ga_args("75", "1", &url)
        .into_iter()
        .filter(|a| *a != "--quiet")
        .collect();
    args.extend(["--workers", "2", "--lease", "2", "--resume"]);
    let out = output(pg.proleg(&args));
    let (report, err) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{err}");
    let stored: u64 = err
        .lines()
        .find_map(|l| {
            l.split(": ")
                .nth(1)
                .and_then(|t| t.strip_suffix(" evaluations stored"))
        })
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no resume line in {err}"));
    assert!((35..75).contains(&stored), "{err}");
    assert_eq!(result_lines(&report), expected, "{report}");
    assert_eq!(
        evaluations(&pg, &url, "optimize_shared_kill_driver_pg"),
        evaluations(&pg, &reference, "optimize_shared_kill_driver_sqlite")
    );
    let mut c = pg.connect("shared_kill_driver");
    let row = c
        .query_one(
            "SELECT COUNT(*), COUNT(*) FILTER (WHERE state = 'done'), (SELECT COUNT(*) FROM runs)
             FROM evaluations",
            &[],
        )
        .unwrap();
    let get = |i: usize| row.get::<_, i64>(i);
    assert_eq!((get(0), get(1), get(2)), (75, 75, 1));
}

/// A one-line error naming `cause`, exit code 1, no panic, and never `secret`.
fn refused(out: std::process::Output, cause: &str, secret: &str) {
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains(cause), "expected '{cause}' in: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!err.contains(secret) && !text(&out.stdout).contains(secret));
}

#[test]
fn bad_stores_are_one_line_errors_that_never_show_the_password() {
    let pg = server();
    let url = pg.database("shared_bad");
    let secret = "Wr0ng-pa55word-41";
    // A wrong password, in the URL and in PGPASSWORD.
    let with_password = url.replace("proleg_admin@", &format!("proleg_admin:{secret}@"));
    refused(
        output(pg.proleg(&["results", &with_password])),
        "password authentication failed",
        secret,
    );
    refused(
        output(pg.proleg_as(secret, &ga_args("2", "0.1", &url))),
        "password authentication failed",
        secret,
    );
    // Nothing answers on the port.
    let closed = url.replace(&url[url.rfind(':').unwrap()..url.rfind('/').unwrap()], ":1");
    refused(
        output(pg.proleg(&["worker", "--store", &closed])),
        "error connecting to server",
        &pg.password,
    );
    // With --idle-exit a worker waits that long for a server to come up, then says why not.
    let out = output(pg.proleg(&["worker", "--store", &closed, "--idle-exit", "1"]));
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("waiting for the store to appear"), "{err}");
    assert!(err.contains("no server answers"), "{err}");
    assert!(
        !err.contains("panicked") && !err.contains(&pg.password),
        "{err}"
    );
    // Typos in the URL.
    let typo = url.replace("postgres://", "postgress://");
    refused(
        output(pg.proleg(&ga_args("2", "0.1", &typo))),
        "unknown URL scheme \"postgress://\"",
        &pg.password,
    );
    let port = url.replace("127.0.0.1:", "127.0.0.1:x");
    refused(
        output(pg.proleg(&["results", &port])),
        "not a valid PostgreSQL URL",
        &pg.password,
    );
    // A choice a shared store cannot honour: refused before the store is opened.
    let mut args = ga_args("2", "0.1", &url);
    args.extend(["--batch", "4"]);
    refused(
        output(pg.proleg(&args)),
        "--batch 4: a shared store evaluates one robot per world",
        &pg.password,
    );
    let mut c = pg.connect("shared_bad");
    let tables = |c: &mut postgres::Client| -> i64 {
        c.query_one(
            "SELECT COUNT(*) FROM pg_tables WHERE schemaname = 'public'",
            &[],
        )
        .unwrap()
        .get(0)
    };
    assert_eq!(tables(&mut c), 0, "nothing written");
    // A store of another schema version: refused, nothing written.
    c.batch_execute(
        "CREATE TABLE proleg_meta (schema_version INTEGER NOT NULL);
         INSERT INTO proleg_meta VALUES (99);",
    )
    .unwrap();
    refused(
        output(pg.proleg(&ga_args("2", "0.1", &url))),
        &format!("the store has schema version 99; this proleg reads version {SCHEMA_VERSION}"),
        &pg.password,
    );
    assert_eq!(
        tables(&mut c),
        1,
        "nothing written beside the foreign version table"
    );
}

#[test]
fn a_store_of_version_2_is_brought_to_the_current_version_by_the_driver() {
    let pg = server();
    let url = pg.database("shared_v2");
    let out = output(pg.proleg(&ga_args("2", "0.1", &url)));
    assert!(out.status.success(), "{}", text(&out.stderr));
    // What a version-2 store looks like: no run_episodes.
    let mut c = pg.connect("shared_v2");
    c.batch_execute(
        "DROP TABLE run_episodes; ALTER TABLE evaluations DROP COLUMN engine_scores;
         ALTER TABLE evaluations DROP COLUMN rejected;
         ALTER TABLE evaluations DROP COLUMN measures;
         UPDATE proleg_meta SET schema_version = 2;",
    )
    .unwrap();
    let out = output(pg.proleg(&ga_args("2", "0.1", &url)));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let version: i32 = c
        .query_one("SELECT schema_version FROM proleg_meta", &[])
        .unwrap()
        .get(0);
    assert_eq!(i64::from(version), SCHEMA_VERSION);
    let runs: i64 = c
        .query_one("SELECT COUNT(*) FROM runs", &[])
        .unwrap()
        .get(0);
    assert_eq!(runs, 2, "the old run kept, the new one added");
    assert!(
        c.query_one("SELECT to_regclass('run_episodes') IS NOT NULL", &[])
            .unwrap()
            .get::<_, bool>(0)
    );
}

#[test]
fn tls_is_used_when_the_url_requires_it() {
    let pg = server();
    let url = pg.database("shared_tls");
    let (ok, _, err) = {
        let out = output(pg.proleg(&ga_args("2", "0.1", &url)));
        (out.status.success(), text(&out.stdout), text(&out.stderr))
    };
    assert!(ok, "{err}");
    for (mode, shown) in [("require", "TLS"), ("disable", "unencrypted")] {
        let out = output(pg.proleg(&[
            "worker",
            "--store",
            &format!("{url}?sslmode={mode}"),
            "--idle-exit",
            "0.2",
        ]));
        assert!(out.status.success(), "{}", text(&out.stderr));
        let report = text(&out.stdout);
        assert!(
            report.contains(&format!("?sslmode={mode} ({shown},")),
            "{report}"
        );
    }
}

fn info(config: &str) -> RunInfo {
    RunInfo {
        config: config.into(),
        algorithm: "genetic algorithm".into(),
        seed: 1,
        fitness: "displacement".into(),
        duration: 0.5,
        genes: vec!["PatternGenerator_sinusoidal.Amplitude[0]".into()],
    }
}

fn pending(number: u64) -> Pending {
    Pending {
        number,
        round: 0,
        genome: vec![3],
        values: vec![30.0],
    }
}

#[test]
fn a_result_after_the_lease_ran_out_is_discarded() {
    let pg = server();
    pg.database("shared_late");
    let mut store = pg.open_store("shared_late");
    let run = store.start_run(&info(GA), "proleg test", &[], &[]).unwrap();
    store.enqueue(run, 1, &[pending(0)]).unwrap();
    // Worker a's lease runs out at once; b claims the evaluation again.
    let a = store.claim("a", Duration::ZERO, None, &[], 5).unwrap();
    assert_eq!(a.len(), 1);
    assert_eq!(a[0].attempt, 1);
    let b = store
        .claim("b", Duration::from_secs(60), None, &[], 5)
        .unwrap();
    assert_eq!((b.len(), b[0].attempt), (1, 2));
    assert!(
        store
            .claim("c", Duration::from_secs(60), None, &[], 5)
            .unwrap()
            .is_empty()
    );
    assert!(
        !store
            .submit("a", &a[0], &CandidateScore::single(1.0), 0.1)
            .unwrap(),
        "a's late result is discarded"
    );
    assert!(
        store
            .submit("b", &b[0], &CandidateScore::single(2.0), 0.1)
            .unwrap()
    );
    assert!(
        !store
            .submit("b", &b[0], &CandidateScore::single(3.0), 0.1)
            .unwrap(),
        "written once"
    );
    let stored = store.evaluations(run).unwrap();
    assert_eq!(stored.len(), 1);
    assert_eq!(stored[0].score, 2.0);
}

#[test]
fn a_worker_refuses_runs_it_cannot_evaluate_and_leaves_them_pending() {
    let pg = server();
    pg.database("shared_refuse");
    let mut store = pg.open_store("shared_refuse");
    // A run of another program version, and one whose module this host lacks.
    let other = store
        .start_run(&info(GA), "proleg 0.0.0", &[], &[])
        .unwrap();
    let source = RecordingSource::new(&FsSource);
    load_simulation_with(&source, Path::new(GA), &ModuleRegistry::standard()).unwrap();
    let files: Vec<(String, String)> = source
        .files()
        .into_iter()
        .map(|(p, t)| {
            (
                p,
                t.replace("PatternGenerator_sinusoidal", "Plugin_not_here"),
            )
        })
        .collect();
    let missing = store
        .start_run(&info(GA), &program_version(), &files, &[])
        .unwrap();
    store.enqueue(other, 1, &[pending(0)]).unwrap();
    store.enqueue(missing, 1, &[pending(0)]).unwrap();
    let options = WorkerOptions {
        threads: 1,
        lease: Duration::from_secs(60),
        idle_exit: Some(Duration::from_millis(300)),
        only_run: None,
    };
    let target = store.target().clone();
    let report = run_pool(
        &target,
        &ModuleRegistry::standard(),
        &options,
        &StopFlag::default(),
        None,
        &|_| {},
    )
    .unwrap();
    assert_eq!(report.evaluated, 0);
    assert_eq!(report.refused.len(), 2, "{:?}", report.refused);
    assert!(
        report.refused[0].contains("started by proleg 0.0.0"),
        "{:?}",
        report.refused
    );
    assert!(
        report.refused[1].contains("does not load on this host")
            && report.refused[1].contains("Plugin_not_here"),
        "{:?}",
        report.refused
    );
    for run in [other, missing] {
        assert_eq!(
            store.queue_counts(run).unwrap(),
            (1, 0, 0),
            "left pending for others"
        );
    }
}

#[test]
fn a_mujoco_run_scores_the_same_through_workers_as_in_one_process_and_a_host_without_mujoco_refuses_it()
 {
    if !common::mujoco_here("shared MuJoCo run") {
        return;
    }
    let dir = common::scratch("optimize_shared_mujoco");
    let reference = dir.join("reference.sqlite").display().to_string();
    let mut args = ga_args("30", "1", &reference);
    args.extend(["--engine", "mujoco"]);
    let (ok, out, err) = common::proleg(&args);
    assert!(ok, "{err}");
    let expected = result_lines(&out);
    assert_eq!(expected.len(), 6, "{out}");

    let pg = server();
    let url = pg.database("shared_mujoco");
    let mut args = ga_args("30", "1", &url);
    args.extend(["--workers", "0", "--engine", "mujoco"]);
    let mut driver = spawn(pg.proleg(&args));
    pg.wait_until("shared_mujoco", HAS_STORE, &mut driver);
    let queued = "SELECT EXISTS (SELECT 1 FROM evaluations WHERE state = 'pending')";
    pg.wait_until("shared_mujoco", queued, &mut driver);
    // A host without the library refuses the run and leaves it to the others.
    let mut lacking = pg.proleg(&[
        "worker",
        "--store",
        &url,
        "--threads",
        "1",
        "--idle-exit",
        "1",
    ]);
    lacking.env("PROLEG_MUJOCO", "/nonexistent/libmujoco.so.4.0.0");
    let lacking = output(lacking);
    assert!(lacking.status.success(), "{}", text(&lacking.stderr));
    let said = format!("{}{}", text(&lacking.stdout), text(&lacking.stderr));
    assert!(
        said.contains("runs on MuJoCo, which this host lacks"),
        "{said}"
    );
    assert_eq!(worker_counts(&text(&lacking.stdout)).0, 0, "{said}");
    let workers: Vec<Child> = (0..2)
        .map(|_| {
            spawn(pg.proleg(&[
                "worker",
                "--store",
                &url,
                "--threads",
                "1",
                "--idle-exit",
                "1",
            ]))
        })
        .collect();
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    assert_eq!(
        evaluations(&pg, &url, "optimize_shared_mujoco_pg"),
        evaluations(&pg, &reference, "optimize_shared_mujoco_sqlite")
    );
    for w in workers {
        let out = w.wait_with_output().expect("worker");
        assert!(out.status.success(), "{}", text(&out.stderr));
    }
}

#[test]
fn a_cross_engine_run_through_least_privileged_workers_stores_what_one_process_stores() {
    if !common::mujoco_here("shared cross-engine run") {
        return;
    }
    let both = "configs/gait_from_scratch_engines.simulation.xml";
    let args = |store: &'static str| -> Vec<String> {
        [
            "optimize",
            both,
            "--max-evals",
            "10",
            "--duration",
            "1",
            "--quiet",
            "--store",
            store,
        ]
        .iter()
        .map(|a| a.to_string())
        .collect()
    };
    let dir = common::scratch("optimize_shared_cross");
    let reference = dir.join("reference.sqlite").display().to_string();
    let mut local = args("");
    local[8] = reference.clone();
    let local: Vec<&str> = local.iter().map(String::as_str).collect();
    let (ok, out, err) = common::proleg(&local);
    assert!(ok, "{err}");
    assert!(out.contains("  on mujoco "), "{out}");

    let pg = server();
    let url = pg.database("shared_cross");
    let mut shared = args("");
    shared[8] = url.clone();
    shared.extend(["--workers".to_string(), "0".to_string()]);
    let shared: Vec<&str> = shared.iter().map(String::as_str).collect();
    let mut driver = spawn(pg.proleg(&shared));
    pg.wait_until("shared_cross", HAS_STORE, &mut driver);
    worker_role(&pg, "shared_cross", "proleg_worker_cross", "w-cross");
    let worker_url = url.replace("proleg_admin@", "proleg_worker_cross@");
    let workers: Vec<Child> = (0..2)
        .map(|_| {
            spawn(pg.proleg_as(
                "w-cross",
                &[
                    "worker",
                    "--store",
                    &worker_url,
                    "--threads",
                    "1",
                    "--idle-exit",
                    "1",
                ],
            ))
        })
        .collect();
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let rows = evaluations(&pg, &url, "optimize_shared_cross_pg");
    assert!(
        rows.iter()
            .all(|r| r.contains("rapier=") && r.contains("mujoco=")),
        "{rows:?}"
    );
    assert_eq!(
        rows,
        evaluations(&pg, &reference, "optimize_shared_cross_sqlite")
    );
    for w in workers {
        let out = w.wait_with_output().expect("worker");
        assert!(out.status.success(), "{}", text(&out.stderr));
    }
}

#[test]
fn the_coordinator_benchmark_hands_out_and_takes_back_every_evaluation_once() {
    let pg = server();
    let url = pg.database("shared_ceiling");
    let out = output(pg.proleg(&[
        "bench",
        "--store",
        &url,
        "--clients",
        "3",
        "--evaluations",
        "500",
        "--round",
        "120",
        "--claim-batch",
        "16",
    ]));
    let report = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        report.contains("500 evaluations in") && report.contains("evaluations/s"),
        "{report}"
    );
    let mut c = pg.connect("shared_ceiling");
    let row = c
        .query_one(
            "SELECT COUNT(*), COUNT(DISTINCT number), COUNT(*) FILTER (WHERE state = 'done'),
                    COUNT(DISTINCT round), bool_and(attempt = 1)
             FROM evaluations",
            &[],
        )
        .unwrap();
    assert_eq!(
        (
            row.get::<_, i64>(0),
            row.get::<_, i64>(1),
            row.get::<_, i64>(2),
            row.get::<_, i64>(3)
        ),
        (500, 500, 500, 5),
        "every evaluation once, in rounds of 120"
    );
    assert!(row.get::<_, bool>(4), "each claimed once");
}

/// Two tasks of two test courses each, 4-s episodes.
const SMALL_SUITE: &str = r#"<Suite name="small">
  <Task name="rough-easy" family="rough" difficulty="easy" duration="4" goal="0.3" train="1-4" test="101-102"/>
  <Task name="pegs-hard" family="pegs" difficulty="hard" duration="4" goal="0.3" test="101-102"/>
</Suite>"#;

#[test]
fn a_suite_runs_on_a_worker_of_the_store_to_the_local_table_and_resumes_from_the_store() {
    let pg = server();
    let url = pg.database("shared_suite");
    let dir = common::scratch("shared_suite");
    let suite = dir.join("small.suite.xml");
    std::fs::write(&suite, SMALL_SUITE).unwrap();
    let engines = if common::mujoco_here("suite on a store's workers") {
        "rapier,mujoco"
    } else {
        "rapier"
    };
    let total = 4 * engines.split(',').count() as i64;
    let (suite, demo) = (suite.to_str().unwrap(), "configs/demo.simulation.xml");
    let out = |name: &str| dir.join(name).display().to_string();
    let args = |o: &str, more: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = [
            "suite",
            suite,
            demo,
            "--engines",
            engines,
            "-o",
            o,
            "--quiet",
        ]
        .map(String::from)
        .to_vec();
        a.extend(more.iter().map(|s| s.to_string()));
        a
    };
    let run = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        pg.proleg(&refs)
    };
    let here = output(run(args(&out("here"), &[])));
    assert!(here.status.success(), "{}", text(&here.stderr));
    // Every episode on one worker: the driver runs none itself.
    let mut driver = spawn(run(args(
        &out("shared"),
        &["--store", &url, "--threads", "0"],
    )));
    pg.wait_until(
        "shared_suite",
        "SELECT EXISTS (SELECT 1 FROM evaluations)",
        &mut driver,
    );
    let worker = spawn(pg.proleg(&["worker", "--store", &url, "--idle-exit", "2"]));
    let shared = driver.wait_with_output().expect("driver");
    assert!(shared.status.success(), "{}", text(&shared.stderr));
    let worker = worker.wait_with_output().expect("worker");
    assert!(worker.status.success(), "{}", text(&worker.stderr));
    assert_eq!(worker_counts(&text(&worker.stdout)), (total as u64, 0));
    let table = |o: &str| std::fs::read_to_string(Path::new(o).join("suite.csv")).unwrap();
    assert_eq!(table(&out("shared")), table(&out("here")));
    // A new output folder: every episode comes from the store, none is run again.
    let again = output(run(args(
        &out("again"),
        &["--store", &url, "--threads", "1"],
    )));
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert_eq!(table(&out("again")), table(&out("here")));
    each_episode_once_and_no_export(&pg, &url, total, &out("export"));
    // A file is no shared store.
    let file = output(run(args(&out("file"), &["--store", "x.sqlite"])));
    assert!(!file.status.success());
    assert!(
        text(&file.stderr).contains("PostgreSQL"),
        "{}",
        text(&file.stderr)
    );
}

/// The suite run's store holds each of its `total` episodes once, each claimed once, and
/// refuses to export one as a candidate.
fn each_episode_once_and_no_export(pg: &Pg, url: &str, total: i64, out: &str) {
    let row = pg
        .connect("shared_suite")
        .query_one(
            "SELECT COUNT(*), MAX(attempt)::BIGINT, COUNT(*) FILTER (WHERE state = 'done') FROM evaluations",
            &[],
        )
        .unwrap();
    let get = |i: usize| row.get::<_, i64>(i);
    assert_eq!((get(0), get(1), get(2)), (total, 1, total));
    // Its evaluations are episodes, not candidates: no export.
    let export = output(pg.proleg(&["results", url, "--export-robot", "best", "-o", out]));
    assert!(!export.status.success());
    assert!(
        text(&export.stderr).contains("it is a suite run"),
        "{}",
        text(&export.stderr)
    );
}

#[test]
fn a_killed_worker_s_suite_episode_runs_again_and_the_table_is_the_local_one() {
    let pg = server();
    let url = pg.database("shared_suite_kill");
    let dir = common::scratch("shared_suite_kill");
    let suite = dir.join("long.suite.xml");
    // 20-s episodes: about half a second each, long enough to be killed in.
    std::fs::write(
        &suite,
        SMALL_SUITE.replace("duration=\"4\"", "duration=\"20\""),
    )
    .unwrap();
    let suite = suite.display().to_string();
    let out = |name: &str| dir.join(name).display().to_string();
    let args = |o: &str, more: &[&str]| -> Vec<String> {
        let base = [
            "suite",
            &suite,
            "configs/demo.simulation.xml",
            "--engines",
            "rapier",
        ];
        let tail = ["-o", o, "--quiet"];
        base.iter()
            .chain(&tail)
            .chain(more)
            .map(|s| s.to_string())
            .collect()
    };
    let run = |a: Vec<String>| pg.proleg(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let here = output(run(args(&out("here"), &[])));
    assert!(here.status.success(), "{}", text(&here.stderr));
    let mut driver = spawn(run(args(
        &out("shared"),
        &["--store", &url, "--threads", "0"],
    )));
    pg.wait_until("shared_suite_kill", HAS_STORE, &mut driver);
    let lost = kill_a_worker_holding_a_claim(&pg, "shared_suite_kill", &url);
    let survivor = lease_worker(&pg, &url, "6");
    let shared = driver.wait_with_output().expect("driver");
    assert!(shared.status.success(), "{}", text(&shared.stderr));
    let table = |o: &str| std::fs::read_to_string(Path::new(o).join("suite.csv")).unwrap();
    assert_eq!(table(&out("shared")), table(&out("here")));
    let survived = survivor.wait_with_output().expect("worker");
    assert!(survived.status.success(), "{}", text(&survived.stderr));
    let row = pg
        .connect("shared_suite_kill")
        .query_one(
            "SELECT state, attempt FROM evaluations WHERE number = $1",
            &[&lost],
        )
        .unwrap();
    assert_eq!(row.get::<_, String>(0), "done");
    assert!(row.get::<_, i32>(1) >= 2, "claimed again after the kill");
}

/// A worker of one thread on `url` with a 3-s lease that exits after `idle` s without work
/// (longer than the lease: a survivor is there when a killed worker's lease runs out).
fn lease_worker(pg: &Pg, url: &str, idle: &str) -> Child {
    let args = ["worker", "--store", url, "--threads", "1", "--lease", "3"];
    spawn(pg.proleg(&[&args[..], &["--idle-exit", idle]].concat()))
}

/// Starts a [`lease_worker`] on database `db` at `url`, waits until it holds a claim and
/// kills it with SIGKILL; the number of the evaluation it held.
fn kill_a_worker_holding_a_claim(pg: &Pg, db: &str, url: &str) -> i64 {
    let mut doomed = lease_worker(pg, url, "60");
    let held = format!(
        "FROM evaluations WHERE state = 'running' AND worker LIKE '%/{}/%'",
        doomed.id()
    );
    pg.wait_until(db, &format!("SELECT EXISTS (SELECT 1 {held})"), &mut doomed);
    let lost: i64 = pg
        .connect(db)
        .query_one(&format!("SELECT number {held}"), &[])
        .unwrap()
        .get(0);
    doomed.kill().expect("SIGKILL");
    let _ = doomed.wait();
    lost
}
