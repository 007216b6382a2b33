//! A stop that answers: Ctrl-C (a real SIGINT) during `proleg optimize` of 90-s episodes on
//! two engines ends the process at once — the episode runner sees the stop between chunks
//! of steps, so the round in flight is abandoned instead of finished — with the shell's
//! status 130 and a line saying what it keeps; `--resume` then runs the abandoned episodes
//! again and reaches the evaluations of an uninterrupted run.

mod common;

use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use proleg::optimize::store::{ExperimentStore, SqliteStore};

/// The experiment-2 learned residual: OpenAI-ES, 90-s episodes, each candidate scored on
/// rapier and MuJoCo.
const CONFIG: &str = "configs/experiment2_policy_es.simulation.xml";

/// `proleg optimize CONFIG` into `store` with a budget of `evals`, then `extra`.
fn optimize(store: &Path, table: &Path, evals: &str, extra: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_proleg"));
    c.args(["optimize", CONFIG, "--max-evals", evals, "--workers", "2"])
        .args(["--store", &store.display().to_string()])
        .args(["--evaluations", &table.display().to_string()])
        .args(extra)
        .current_dir(common::root());
    c
}

/// Evaluations stored in the one run of `store` (0 while it holds none).
fn stored(store: &Path) -> u64 {
    if !store.exists() {
        return 0;
    }
    let Ok(mut s) = SqliteStore::open(store) else {
        return 0;
    };
    s.runs()
        .map(|runs| runs.iter().map(|r| r.evaluations).sum())
        .unwrap_or(0)
}

/// Waits (polling the store) until `child` has stored at least one evaluation.
fn wait_for_a_stored_evaluation(child: &mut Child, store: &Path) {
    let deadline = Instant::now() + Duration::from_secs(600);
    while stored(store) == 0 {
        assert!(
            child.try_wait().expect("child state").is_none(),
            "the run ended before storing an evaluation"
        );
        assert!(
            Instant::now() < deadline,
            "no evaluation stored in 10 minutes"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Everything left in a child's pipe.
fn all_of(pipe: Option<impl Read>) -> String {
    let mut text = String::new();
    pipe.expect("a piped stream")
        .read_to_string(&mut text)
        .expect("read the pipe");
    text
}

fn signal(child: &Child, name: &str) {
    let sent = Command::new("kill")
        .args([name, &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(sent.success());
}

/// The rows of an evaluations table, number and score only (the time and order of writing
/// differ between an interrupted and a whole run).
fn table_rows(path: &Path) -> Vec<(u64, String)> {
    let text = std::fs::read_to_string(path).expect("evaluations table");
    let mut rows: Vec<(u64, String)> = text
        .lines()
        .filter_map(|l| {
            let mut f = l.split('\t');
            let number = f.next()?.parse().ok()?;
            let score = f.nth(1)?.to_string();
            Some((number, score))
        })
        .collect();
    rows.sort();
    rows
}

#[test]
fn ctrl_c_stops_an_optimization_of_long_episodes_at_once_and_resume_reaches_the_same_evaluations() {
    if !common::mujoco_here("ctrl_c_stops_an_optimization") {
        return;
    }
    let dir = common::scratch("cli_stop");
    // The start and a generation of 16, each 2 x 90 s of simulated time.
    let evals = "17";
    let (whole, whole_table) = (dir.join("whole.sqlite"), dir.join("whole.tsv"));
    let out = optimize(&whole, &whole_table, evals, &["--quiet"])
        .output()
        .expect("whole run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let (stopped, stopped_table) = (dir.join("stopped.sqlite"), dir.join("stopped.tsv"));
    let mut child = optimize(&stopped, &stopped_table, evals, &[])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run to stop");
    // The start candidate is stored; the generation's episodes are in flight.
    wait_for_a_stored_evaluation(&mut child, &stopped);
    let sent = Instant::now();
    signal(&child, "-INT");
    let status = child.wait().expect("exit");
    let took = sent.elapsed();
    let err = all_of(child.stderr.take());
    let report = all_of(child.stdout.take());
    eprintln!("exited {took:?} after SIGINT");
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(
        took < Duration::from_secs(2),
        "took {took:?} to stop: {err}"
    );
    assert!(
        err.contains("stopping: the episodes in flight are abandoned")
            && err.contains("--resume runs the rest"),
        "{err}"
    );
    assert!(
        stored(&stopped) < 17,
        "the generation in flight was abandoned, not finished"
    );
    assert_counts_add_up(&report);

    let out = optimize(&stopped, &stopped_table, evals, &["--quiet", "--resume"])
        .output()
        .expect("resumed run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(stored(&stopped), 17);
    // Every evaluation the resumed run reports, stored or run again, is the whole run's.
    assert_eq!(table_rows(&stopped_table), table_rows(&whole_table));
}

/// The report's first line, "N evaluations in R rounds (S simulated, F from the store)",
/// counts only finished rounds: S + F = N (the abandoned generation is in neither).
fn assert_counts_add_up(report: &str) {
    let line = report
        .lines()
        .find(|l| l.contains(" evaluations in "))
        .unwrap_or_else(|| panic!("no report line in {report}"));
    let numbers: Vec<u64> = line
        .split(|c: char| !c.is_ascii_digit() && c != '.')
        .filter_map(|w| w.parse().ok())
        .collect();
    let [n, _rounds, simulated, from_store, ..] = numbers[..] else {
        panic!("{line}");
    };
    assert!(
        simulated <= n && from_store <= n && simulated + from_store == n,
        "{line}"
    );
}

#[test]
fn sigterm_ends_a_paced_run_at_its_next_step_with_status_143_and_its_report() {
    // Ten minutes paced at real time: without the stop it would run on.
    let mut child = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args([
            "run",
            "configs/demo.simulation.xml",
            "--duration",
            "600",
            "--realtime",
            "1",
        ])
        .current_dir(common::root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run");
    wait_for_the_signal_thread(&mut child);
    let sent = Instant::now();
    signal(&child, "-TERM");
    let status = child.wait().expect("exit");
    let took = sent.elapsed();
    let text = all_of(child.stdout.take());
    assert_eq!(status.code(), Some(143), "{text}");
    assert!(took < Duration::from_secs(2), "took {took:?}");
    assert!(
        text.contains("interrupted     stopped early by a signal"),
        "{text}"
    );
}

/// Waits until the child runs proleg's signal thread (`proleg-signals`): from then on a
/// signal asks it to stop instead of killing it.
fn wait_for_the_signal_thread(child: &mut Child) {
    let deadline = Instant::now() + Duration::from_secs(120);
    let tasks = format!("/proc/{}/task", child.id());
    let has_it = || {
        std::fs::read_dir(&tasks).is_ok_and(|d| {
            d.flatten().any(|t| {
                std::fs::read_to_string(t.path().join("comm"))
                    .is_ok_and(|c| c.trim() == "proleg-signals")
            })
        })
    };
    while !has_it() {
        assert!(
            child.try_wait().expect("child state").is_none(),
            "the run ended first"
        );
        assert!(Instant::now() < deadline, "no signal thread in 2 minutes");
        std::thread::sleep(Duration::from_millis(20));
    }
}
