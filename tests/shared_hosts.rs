//! The shared store across a network, on hosts of the test's own (`scripts/hosts`: network
//! namespaces on a bridge, each host with its share of the cores): the PostgreSQL server on
//! host 0, the driver and the workers on others. Each fault ends with every evaluation
//! stored exactly once and the best of the one-process SQLite run: a worker host's link cut
//! mid-run (its late result discarded, the worker going on when the link returns), the
//! database restarted, the driver's host killed and the run resumed from another host, and
//! links that lose packets with a relay that delays them.

mod common;

use std::process::Child;

use common::hosts::Hosts;
use common::pg::{Pg, output, spawn, text};
use common::shared_run::{
    HAS_STORE, evaluations, ga_args, result_lines, sqlite_run, worker_counts,
};

/// Core share of each host: four hosts fill the machine's two cores.
const SHARE: f64 = 0.5;

/// `proleg worker` on host `i` with one thread, a 3-s lease, leaving after `idle` s idle.
fn worker(hosts: &Hosts, pg: &Pg, i: usize, url: &str, idle: &str) -> Child {
    spawn(hosts.proleg(
        i,
        pg,
        &[
            "worker",
            "--store",
            url,
            "--threads",
            "1",
            "--lease",
            "3",
            "--idle-exit",
            idle,
        ],
    ))
}

/// A set `name` of `n` hosts with the server on host 0, a database `hosts_NAME` and the
/// driver of experiment 1's GA (`evals` evaluations of `duration` s, no threads of its own,
/// `--lease LEASE`) running on host 1 once the store exists: (hosts, server, database URL,
/// driver).
fn driven(
    name: &str,
    n: usize,
    (evals, duration, lease): (&str, &str, &str),
) -> (Hosts, Pg, String, Child) {
    let mut hosts = Hosts::up(name, n, SHARE);
    let pg = hosts.postgres(0);
    let db = format!("hosts_{name}");
    let url = pg.database(&db);
    let mut args = ga_args(evals, duration, &url);
    args.extend(["--workers", "0", "--lease", lease]);
    let mut driver = spawn(hosts.proleg(1, &pg, &args));
    pg.wait_until(&db, HAS_STORE, &mut driver);
    (hosts, pg, url, driver)
}

/// One number from the store.
fn count(pg: &Pg, db: &str, query: &str) -> i64 {
    pg.connect(db)
        .query_one(query, &[])
        .map(|r| r.get::<_, i64>(0))
        .unwrap_or_else(|e| panic!("{query}: {e}"))
}

/// Every evaluation of `db`'s single run is stored once and done: `n` rows, one run.
fn stored_once(pg: &Pg, db: &str, n: i64) {
    let rows = count(pg, db, "SELECT COUNT(*) FROM evaluations");
    let done = count(
        pg,
        db,
        "SELECT COUNT(*) FROM evaluations WHERE state = 'done' AND score IS NOT NULL",
    );
    let runs = count(pg, db, "SELECT COUNT(*) FROM runs");
    assert_eq!((rows, done, runs), (n, n, 1));
}

#[test]
fn a_worker_host_cut_off_mid_run_loses_nothing_and_goes_on_when_its_link_returns() {
    let (expected, reference) = sqlite_run("hosts_cut", "90", "3");
    let (hosts, pg, url, driver) = driven("cut", 4, ("90", "3", "3"));
    let mut cut = worker(&hosts, &pg, 2, &url, "30");
    let mine = format!("worker LIKE '%/{}/%'", cut.id());
    pg.wait_until(
        "hosts_cut",
        &format!("SELECT EXISTS (SELECT 1 FROM evaluations WHERE state = 'running' AND {mine})"),
        &mut cut,
    );
    hosts.link(2, false);
    let lost = count(
        &pg,
        "hosts_cut",
        &format!("SELECT MIN(number) FROM evaluations WHERE state = 'running' AND {mine}"),
    );
    // The other host does the cut one's evaluation once its lease has run out.
    let mut other = worker(&hosts, &pg, 3, &url, "30");
    pg.wait_until(
        "hosts_cut",
        &format!("SELECT state = 'done' AND attempt >= 2 FROM evaluations WHERE number = {lost}"),
        &mut other,
    );
    let done_before = count(
        &pg,
        "hosts_cut",
        &format!("SELECT COUNT(*) FROM evaluations WHERE state = 'done' AND {mine}"),
    );
    hosts.link(2, true);
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    let out = cut.wait_with_output().expect("worker");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (written, discarded) = worker_counts(&text(&out.stdout));
    assert!(
        discarded >= 1,
        "the late result of the lost claim is discarded: {}",
        text(&out.stdout)
    );
    let done_after = count(
        &pg,
        "hosts_cut",
        &format!("SELECT COUNT(*) FROM evaluations WHERE state = 'done' AND {mine}"),
    );
    assert!(
        done_after > done_before && written as i64 >= done_after,
        "the worker went on after its link returned: {done_before} -> {done_after} ({} written)",
        written
    );
    let out = other.wait_with_output().expect("worker");
    assert!(out.status.success(), "{}", text(&out.stderr));
    stored_once(&pg, "hosts_cut", 90);
    assert_eq!(
        evaluations(&pg, &url, "hosts_cut_pg"),
        evaluations(&pg, &reference, "hosts_cut_sqlite")
    );
}

#[test]
fn the_database_host_restarted_mid_run_costs_nothing() {
    let (expected, reference) = sqlite_run("hosts_restart", "90", "2");
    let (hosts, pg, url, driver) = driven("restart", 3, ("90", "2", "5"));
    let mut w = worker(&hosts, &pg, 2, &url, "10");
    pg.wait_until(
        "hosts_restart",
        "SELECT COUNT(*) >= 20 FROM evaluations WHERE state = 'done'",
        &mut w,
    );
    hosts.restart_postgres();
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    let out = w.wait_with_output().expect("worker");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("connected again"),
        "{}",
        text(&out.stderr)
    );
    stored_once(&pg, "hosts_restart", 90);
    assert_eq!(
        evaluations(&pg, &url, "hosts_restart_pg"),
        evaluations(&pg, &reference, "hosts_restart_sqlite")
    );
}

#[test]
fn a_killed_driver_host_s_run_is_resumed_from_another_host() {
    let (expected, reference) = sqlite_run("hosts_driver", "75", "1");
    let (hosts, pg, url, mut driver) = driven("driver", 4, ("75", "1", "3"));
    let w = worker(&hosts, &pg, 2, &url, "20");
    pg.wait_until(
        "hosts_driver",
        "SELECT COUNT(*) >= 30 FROM evaluations WHERE state = 'done'",
        &mut driver,
    );
    driver.kill().expect("SIGKILL");
    let _ = driver.wait();
    let mut args: Vec<&str> = ga_args("75", "1", &url);
    args.extend(["--workers", "0", "--lease", "3", "--resume"]);
    let out = output(hosts.proleg(3, &pg, &args));
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    let out = w.wait_with_output().expect("worker");
    assert!(out.status.success(), "{}", text(&out.stderr));
    stored_once(&pg, "hosts_driver", 75);
    assert_eq!(
        evaluations(&pg, &url, "hosts_driver_pg"),
        evaluations(&pg, &reference, "hosts_driver_sqlite")
    );
}

#[test]
fn links_that_lose_one_packet_in_a_hundred_and_delay_each_by_50_ms_change_nothing() {
    let (expected, reference) = sqlite_run("hosts_lossy", "45", "1");
    let mut hosts = Hosts::up("lossy", 3, SHARE);
    let pg = hosts.postgres(0);
    let url = pg.database("hosts_lossy");
    // Driver and worker reach the server through a relay on its host that delays every
    // packet by 50 ms each way; their own hosts drop 1 % of their packets each way.
    let relay_at = format!("{}:6432", hosts.addr(0));
    let mut relay = spawn(hosts.command(
        0,
        "scripts/delay-relay",
        &[&relay_at, &format!("{}:5432", hosts.addr(0)), "50"],
    ));
    let slow = url.replace(&format!("{}:5432", hosts.addr(0)), &relay_at);
    hosts.loss(1, 1.0);
    hosts.loss(2, 1.0);
    let mut args = ga_args("45", "1", &slow);
    args.extend(["--workers", "0", "--lease", "10"]);
    let mut driver = spawn(hosts.proleg(1, &pg, &args));
    pg.wait_until("hosts_lossy", HAS_STORE, &mut driver);
    let w = spawn(hosts.proleg(
        2,
        &pg,
        &[
            "worker",
            "--store",
            &slow,
            "--threads",
            "1",
            "--lease",
            "10",
            "--idle-exit",
            "5",
        ],
    ));
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(result_lines(&text(&out.stdout)), expected);
    let out = w.wait_with_output().expect("worker");
    assert!(out.status.success(), "{}", text(&out.stderr));
    // The throughput over such links, for the record (`--nocapture` shows it).
    eprintln!("lossy, delayed links: {}", text(&out.stdout));
    assert_eq!(worker_counts(&text(&out.stdout)).0, 45);
    stored_once(&pg, "hosts_lossy", 45);
    assert_eq!(
        evaluations(&pg, &url, "hosts_lossy_pg"),
        evaluations(&pg, &reference, "hosts_lossy_sqlite")
    );
    relay.kill().expect("the relay stops");
    let _ = relay.wait();
}
