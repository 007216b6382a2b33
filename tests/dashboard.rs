//! `proleg dashboard` for real: the program serving a real store, read over HTTP and in
//! Debian's Chromium (headless, driven through chromedriver). The page follows a live
//! PostgreSQL run without reloading, shows a run named with markup as text, and a remote
//! bind refuses requests without its token; bad requests get 400/404 with a message.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::browser::Browser;
use common::pg::{server, spawn, text};
use common::shared_run::driver_on_fresh_database;
use proleg::optimize::store::{RunInfo, Store, StoreLocation, StoredEval};

/// A running `proleg dashboard`, stopped when dropped.
struct Dashboard {
    child: Child,
    /// The address it printed (with the token for a remote bind).
    url: String,
}

impl Dashboard {
    fn start(store: &str, bind: &str, password: Option<&str>) -> Dashboard {
        // Each dashboard of this process its own cache folder.
        static STARTED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let cache = common::scratch(&format!(
            "dashboard_cache_{}",
            STARTED.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
        ));
        let mut c = Command::new(env!("CARGO_BIN_EXE_proleg"));
        c.args(["dashboard", store, "--bind", bind, "--cache"])
            .arg(&cache)
            .current_dir(common::root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .env_remove("PGPASSFILE");
        if let Some(p) = password {
            c.env("PGPASSWORD", p);
        }
        let mut child = c.spawn().expect("proleg dashboard starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut line)
            .expect("the dashboard says where it listens");
        let url = line
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("no address in: {line}"))
            .to_string();
        Dashboard { child, url }
    }

    /// `http://ADDR` without path or token.
    fn base(&self) -> String {
        let rest = self.url.trim_start_matches("http://");
        format!("http://{}", rest.split('/').next().unwrap_or(rest))
    }
}

impl Drop for Dashboard {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `GET url` (plain HTTP/1.1): status and body.
fn get(url: &str) -> (u16, String) {
    request("GET", url, "")
}

/// `METHOD url` with `headers` (each ending in CRLF): status and body.
fn request(method: &str, url: &str, headers: &str) -> (u16, String) {
    let rest = url.trim_start_matches("http://");
    let (host, path) = rest.split_once('/').unwrap_or((rest, ""));
    let mut s = TcpStream::connect(host).expect("the dashboard answers");
    write!(
        s,
        "{method} /{path} HTTP/1.1\r\nHost: {host}\r\n{headers}Content-Length: 0\r\nConnection: close\r\n\r\n"
    )
    .expect("request");
    let mut all = String::new();
    s.read_to_string(&mut all).expect("response");
    let status = all
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let body = all
        .split_once("\r\n\r\n")
        .map_or("", |(_, b)| b)
        .to_string();
    (status, body)
}

/// The name of the run the page must show as text.
const MARKUP: &str =
    "<img src=x onerror=\"document.title='owned'\"><script>document.title='owned'</script>";

/// A SQLite store with a finished GA run and a run named with markup.
fn sqlite_store(name: &str) -> String {
    let dir = common::scratch(name);
    let path = dir.join("runs.sqlite").display().to_string();
    let (ok, _, err) = common::proleg(&[
        "optimize",
        "configs/experiment1_ga.simulation.xml",
        "--max-evals",
        "30",
        "--duration",
        "0.5",
        "--quiet",
        "--store",
        &path,
    ]);
    assert!(ok, "{err}");
    let mut store = Store::open(&StoreLocation::sqlite(&path)).expect("store");
    let info = RunInfo {
        config: MARKUP.into(),
        algorithm: "<b>bold</b>".into(),
        seed: 1,
        fitness: "displacement".into(),
        duration: 1.0,
        genes: vec!["<i>gene</i>".into()],
    };
    let run = store.start_run(&info, &[], &[]).expect("run");
    let eval = StoredEval {
        number: 0,
        round: 0,
        genome: vec![1],
        values: vec![1.0],
        score: 0.5,
        engines: Vec::new(),
        rejected: None,
        measures: Vec::new(),
        wall: 0.1,
    };
    store.record(run, 1, &[eval]).expect("record");
    path
}

#[test]
fn the_api_answers_bad_requests_with_their_status_and_a_remote_bind_needs_its_token() {
    let store = sqlite_store("dashboard_http");
    let d = Dashboard::start(&store, "127.0.0.1:0", None);
    assert!(!d.url.contains("token"), "loopback: no token: {}", d.url);
    let (status, body) = get(&format!("{}/api/runs", d.base()));
    assert_eq!(status, 200, "{body}");
    let runs: serde_json::Value = serde_json::from_str(&body).expect("JSON");
    assert_eq!(runs["runs"].as_array().map(Vec::len), Some(2));
    assert_eq!(runs["runs"][0]["config"], MARKUP, "names come as data");
    assert_eq!(runs["runs"][1]["evaluations"], 30);
    let (status, body) = get(&format!("{}/api/runs/x1", d.base()));
    assert_eq!(
        (status, body.as_str()),
        (400, "run id \"x1\" is not a number")
    );
    let (status, body) = get(&format!("{}/api/runs/99", d.base()));
    assert_eq!((status, body.as_str()), (404, "the store holds no run 99"));
    let (status, body) = get(&format!("{}/api/runs/1?from=minus", d.base()));
    assert_eq!(status, 400, "{body}");
    let (status, body) = get(&format!("{}/api/runs/1/evaluations.csv", d.base()));
    assert_eq!(status, 200);
    assert_eq!(body.lines().count(), 31, "a header and 30 evaluations");
    assert!(
        body.starts_with("store,run,evaluation,round,score,best,wall_s,genome,values,"),
        "the table of `proleg results --export`, as CSV: {body}"
    );
    let (status, _) = get(&format!("{}/no/such/page", d.base()));
    assert_eq!(status, 404);

    // Any address but loopback: a token, printed once, that every request must present.
    let remote = Dashboard::start(&store, "0.0.0.0:0", None);
    let port = remote.base().rsplit(':').next().unwrap_or("").to_string();
    let token = remote
        .url
        .split("token=")
        .nth(1)
        .unwrap_or_else(|| panic!("no token in {}", remote.url))
        .to_string();
    assert!(token.len() >= 32, "{token}");
    let local = format!("http://127.0.0.1:{port}");
    assert_eq!(get(&format!("{local}/api/runs")).0, 401);
    assert_eq!(get(&format!("{local}/")).0, 401);
    assert_eq!(get(&format!("{local}/api/runs?token=wrong{token}")).0, 401);
    assert_eq!(get(&format!("{local}/api/runs?token={token}")).0, 200);
}

#[test]
fn a_run_named_with_markup_shows_as_text_in_the_browser() {
    let store = sqlite_store("dashboard_markup");
    let d = Dashboard::start(&store, "127.0.0.1:0", None);
    let b = Browser::start("dashboard_markup");
    b.goto(&d.url);
    b.wait_for("document.querySelectorAll('#runs tbody tr').length === 2");
    let first = b.eval("document.querySelector('#runs tbody tr td:nth-child(3)').textContent");
    assert_eq!(first, MARKUP, "the name is text");
    assert_eq!(
        b.eval("document.querySelectorAll('main img, main b, main i').length"),
        0
    );
    assert_eq!(
        b.eval("document.scripts.length"),
        2,
        "only the page's own scripts"
    );
    assert_eq!(b.eval("document.title"), "proleg dashboard");
    // The finished run, opened: its 30 evaluations in the curve and the table.
    b.goto(&format!("{}#run=1", d.base()));
    b.wait_for("window.proleg.evaluations.length === 30");
    assert_eq!(
        b.eval("window.proleg.evaluations.every((e, i) => e.number === i)"),
        true,
        "each evaluation once, in order"
    );
    assert_eq!(b.eval("window.proleg.curve.data[0].length"), 30);
    assert_eq!(
        b.eval("document.querySelectorAll('#evaluations tbody tr').length"),
        30
    );
    // Readable in both schemes: text against its background, and the plots' axes.
    let light = b.eval(CONTRAST).as_f64().unwrap_or(0.0);
    assert!(light >= 7.0, "light scheme contrast {light}");
    // Two runs compared on one plot.
    b.eval("(document.querySelectorAll('#runs tbody input[type=checkbox]').forEach((c) => c.click()), true)");
    b.wait_for("window.proleg.comparePlot !== null && !document.querySelector('#compare').hidden");
    assert_eq!(b.eval("window.proleg.comparePlot.series.length"), 3);
    let dark = Browser::dark("dashboard_dark");
    dark.goto(&format!("{}#run=1", d.base()));
    dark.wait_for("window.proleg.evaluations.length === 30");
    assert_eq!(
        dark.eval("matchMedia('(prefers-color-scheme: dark)').matches"),
        true
    );
    let contrast = dark.eval(CONTRAST).as_f64().unwrap_or(0.0);
    assert!(contrast >= 7.0, "dark scheme contrast {contrast}");
    dark.screenshot(&common::scratch("dashboard_dark_shot").join("dashboard_dark.png"));
}

/// The contrast ratio (WCAG) of the page's text against its background, and of the
/// learning curve's axis labels against it: the smaller.
const CONTRAST: &str = "(() => { \
    const rgb = (c) => c.match(/[0-9.]+/g).slice(0, 3).map(Number); \
    const lum = (c) => { const [r, g, b] = rgb(c).map((v) => { v /= 255; \
        return v <= 0.03928 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4); }); \
        return 0.2126 * r + 0.7152 * g + 0.0722 * b; }; \
    const ratio = (a, b) => { const [x, y] = [lum(a), lum(b)].sort((p, q) => q - p); return (x + 0.05) / (y + 0.05); }; \
    const bg = getComputedStyle(document.body).backgroundColor; \
    const text = getComputedStyle(document.body).color; \
    const axis = window.proleg.curve.axes[1].stroke(window.proleg.curve, 1); \
    return Math.min(ratio(text, bg), ratio(axis, bg)); })()";

/// The evaluations of run 1 done in order (those the page can show).
fn done_in_order(pg: &common::pg::Pg, db: &str) -> i64 {
    pg.connect(db)
        .query_one(
            "SELECT COALESCE((SELECT MIN(number) FROM evaluations WHERE run = 1 AND state <> 'done'),
                             (SELECT COUNT(*) FROM evaluations WHERE run = 1))",
            &[],
        )
        .map(|r| r.get::<_, i64>(0))
        .expect("count")
}

#[test]
fn the_page_follows_a_live_postgres_run_within_two_seconds_without_reloading() {
    let pg = server();
    let (url, mut driver) = driver_on_fresh_database(&pg, "dashboard_live", "300", "2");
    let worker = spawn(pg.proleg(&[
        "worker",
        "--store",
        &url,
        "--threads",
        "1",
        "--idle-exit",
        "3",
    ]));
    let d = Dashboard::start(&url, "127.0.0.1:0", Some(&pg.password));
    let b = Browser::start("dashboard_live");
    b.goto(&format!("{}#run=1", d.base()));
    b.wait_for("window.proleg.version > 0 && window.proleg.run === 1");
    b.eval("(window.loadedOnce = window.loadedOnce || 'first load', true)");
    let mut seen = Vec::new();
    for _ in 0..4 {
        let in_store = done_in_order(&pg, "dashboard_live");
        let asked = Instant::now();
        b.wait_for(&format!("window.proleg.evaluations.length >= {in_store}"));
        let lag = asked.elapsed();
        assert!(
            lag < Duration::from_secs(2),
            "the page showed {in_store} evaluations {lag:?} after the store had them"
        );
        seen.push(in_store);
        // The next sample once the store has grown.
        pg.wait_until(
            "dashboard_live",
            &format!(
                "SELECT COALESCE((SELECT MIN(number) FROM evaluations WHERE run = 1 AND state <> 'done'), 300) > {in_store}"
            ),
            &mut driver,
        );
    }
    assert!(
        seen.windows(2).any(|w| w[1] > w[0]),
        "the run grew: {seen:?}"
    );
    assert_eq!(b.eval("window.loadedOnce"), "first load", "no reload");
    // The run's queue and its worker, live while it holds evaluations.
    b.wait_for(
        "!document.querySelector('#workers-box').hidden && \
         [...document.querySelectorAll('#workers tbody tr')].some((r) => r.lastChild.textContent === 'live')",
    );
    let counts = b.eval("document.querySelector('#runs tbody tr td.evaluations').textContent");
    assert!(
        counts
            .as_str()
            .is_some_and(|c| c.contains(" pending, ") && c.contains(" claimed")),
        "{counts}"
    );
    b.screenshot(&common::scratch("dashboard_live_shot").join("dashboard_live.png"));
    assert_eq!(
        b.eval("window.proleg.evaluations.every((e, i) => e.number === i)"),
        true,
        "each evaluation once, in order"
    );
    assert_eq!(
        b.eval("window.proleg.curve.data[0].length === window.proleg.evaluations.length"),
        true
    );
    let out = driver.wait_with_output().expect("driver");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let w = worker.wait_with_output().expect("worker");
    assert!(w.status.success(), "{}", text(&w.stderr));
    b.wait_for("window.proleg.evaluations.length === 300");
    // The password never reached the page.
    let page = b.eval("document.documentElement.outerHTML");
    assert!(!page.to_string().contains(&pg.password));
}

#[test]
fn a_map_elites_run_shows_the_archive_proleg_results_shows() {
    let dir = common::scratch("dashboard_map");
    let store = dir.join("map.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/experiment1_mapelites.simulation.xml",
        ("60", "1"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let line = common::archive_line(&store);
    let d = Dashboard::start(store.to_str().unwrap(), "127.0.0.1:0", None);
    let (status, body) = get(&format!("{}/api/runs/1/map", d.base()));
    assert_eq!(status, 200, "{body}");
    let map: serde_json::Value = serde_json::from_str(&body).expect("JSON");
    assert_eq!(
        map["summary"],
        line.trim(),
        "the page's archive is `proleg results`' archive"
    );
    let filled: usize = line
        .split(" archive: ")
        .nth(1)
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no cell count in {line}"));
    assert_eq!(map["cells"].as_array().map(Vec::len), Some(filled));
    let (status, _) = get(&format!("{}/api/runs/7/map", d.base()));
    assert_eq!(status, 404);
    let b = Browser::start("dashboard_map");
    b.goto(&format!("{}#run=1", d.base()));
    b.wait_for("window.proleg.map !== null && !document.querySelector('#map-box').hidden");
    assert_eq!(
        b.eval("window.proleg.map.cells.length"),
        serde_json::json!(filled)
    );
    let summary = b.eval("document.querySelector('#map-summary').textContent");
    assert!(
        summary.as_str().is_some_and(|s| s.starts_with(line.trim())),
        "{summary}"
    );
    assert_eq!(
        b.eval("window.proleg.evaluations.length === 60 && window.proleg.evaluations.every((e, i) => e.number === i)"),
        true,
        "each evaluation once, in order"
    );
    b.screenshot_of("#map-box", &dir.join("dashboard_map.png"));
}

/// A picture of the page's video now, 160x90 RGBA, kept in the page as `window[name]`;
/// returns the share of its pixels that are the robot's blue modules.
const GRAB: &str = "((name) => { const v = document.querySelector('#eval-video'); \
    const c = document.createElement('canvas'); c.width = 160; c.height = 90; \
    const g = c.getContext('2d'); g.drawImage(v, 0, 0, 160, 90); \
    const d = g.getImageData(0, 0, 160, 90).data; window[name] = d; let blue = 0; \
    for (let i = 0; i < d.length; i += 4) if (d[i + 2] > d[i] + 40 && d[i + 2] > d[i + 1] + 20) blue++; \
    let r = 0, gr = 0, bl = 0; for (let i = 0; i < d.length; i += 4) { r += d[i]; gr += d[i + 1]; bl += d[i + 2]; } \
    window[name + 'Mean'] = [r, gr, bl].map((x) => x / (d.length / 4)); \
    return blue / (d.length / 4); })";

/// The elements that reach past the window's right edge (the page must fit a laptop's
/// window without scrolling sideways).
const FITS: &str = "[...document.querySelectorAll('body *')].filter((e) => \
    e.getBoundingClientRect().right > document.documentElement.clientWidth + 1 && e.offsetParent !== null) \
    .map((e) => `${e.tagName}#${e.id}.${e.className} ${Math.round(e.getBoundingClientRect().right)}`) \
    .concat(document.documentElement.scrollWidth > document.documentElement.clientWidth \
        ? [`page ${document.documentElement.scrollWidth} > ${document.documentElement.clientWidth}`] : [])";

/// A store of twelve 2-s evaluations of experiment 1's GA in a scratch folder `name`,
/// served by a dashboard on loopback.
fn small_run(name: &str) -> (std::path::PathBuf, Dashboard) {
    let dir = common::scratch(name);
    let store = dir.join("runs.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/experiment1_ga.simulation.xml",
        ("12", "2"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let d = Dashboard::start(store.to_str().unwrap(), "127.0.0.1:0", None);
    (dir, d)
}

#[test]
fn an_evaluation_replays_in_the_page_as_a_video_of_the_robot_with_its_data_plots() {
    let (dir, d) = small_run("dashboard_video");
    let media = |n: u32| format!("{}/api/runs/1/evaluations/{n}/media", d.base());
    let (status, _) = get(&format!("{}/api/runs/1/evaluations/3/video.webm", d.base()));
    assert_eq!(status, 404, "no video before it is asked for");
    // Asked for without the page's header (another site's form): refused, nothing queued.
    let (status, body) = request("POST", &media(3), "");
    assert_eq!(status, 400, "{body}");
    assert_eq!(
        get(&media(3)).1,
        r#"{"video":{"state":"absent"},"data":{"state":"absent"}}"#
    );
    let b = Browser::start("dashboard_video");
    b.goto(&format!("{}#run=1", d.base()));
    b.wait_for("document.querySelector('#evaluations button.replay[data-number=\"3\"]') !== null");
    b.eval(
        "(document.querySelector('#evaluations button.replay[data-number=\"3\"]').click(), true)",
    );
    // The data file comes first (a headless replay), then the video (the renderer).
    b.wait_up_to(
        "window.proleg.data !== null && window.proleg.dataPlot !== null",
        Duration::from_secs(120),
    );
    assert_eq!(
        b.eval("window.proleg.data.titles.length > 0 && window.proleg.data.time.length > 10"),
        true
    );
    let video = "document.querySelector('#eval-video')";
    b.wait_up_to(
        &format!("!{video}.hidden && !{video}.paused && {video}.readyState >= 3"),
        Duration::from_secs(300),
    );
    // A frame is shown a moment after the video starts playing.
    b.wait_for(&format!("{GRAB}('frameA') > 0.002"));
    let first = b.eval(&format!("{GRAB}('frameA')"));
    assert!(
        first.as_f64().is_some_and(|share| share > 0.002),
        "the robot's blue modules in the picture: {first} (mean colour {})",
        b.eval("window.frameAMean")
    );
    let t0 = b
        .eval(&format!("{video}.currentTime"))
        .as_f64()
        .unwrap_or(0.0);
    b.wait_for(&format!("Math.abs({video}.currentTime - {t0}) > 0.6"));
    b.eval(&format!("{GRAB}('frameB')"));
    let changed = b.eval(
        "(() => { let n = 0; for (let i = 0; i < window.frameA.length; i += 4) \
         if (Math.abs(window.frameA[i] - window.frameB[i]) + Math.abs(window.frameA[i + 1] - window.frameB[i + 1]) \
             + Math.abs(window.frameA[i + 2] - window.frameB[i + 2]) > 30) n++; return n; })()",
    );
    assert!(
        changed.as_u64().is_some_and(|n| n > 20),
        "pixels that changed between two moments of the video: {changed}"
    );
    b.screenshot_of("#eval", &dir.join("dashboard_video.png"));
    assert_eq!(
        b.eval(FITS),
        serde_json::json!([]),
        "elements wider than the window"
    );
    // Made once: asked again, it is ready at once, from the cache.
    let (status, body) = request("POST", &media(3), "X-Proleg: 1\r\n");
    assert_eq!(status, 200);
    assert_eq!(
        body,
        r#"{"video":{"state":"ready"},"data":{"state":"ready"}}"#
    );
    let (status, body) = request("POST", &media(30), "X-Proleg: 1\r\n");
    assert_eq!(status, 404, "{body}");
}

#[test]
fn a_store_that_goes_away_shows_reconnecting_and_the_page_recovers_with_it() {
    // The server on host 0 of a set of the test's own: its link cut is the store gone.
    let mut hosts = common::hosts::Hosts::up("dashre", 2, 0.5);
    let pg = hosts.postgres(0);
    let db = "dashboard_reconnect";
    let url = pg.database(db);
    let out =
        common::pg::output(hosts.proleg(1, &pg, &common::shared_run::ga_args("30", "0.5", &url)));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let d = Dashboard::start(&url, "127.0.0.1:0", Some(&pg.password));
    let b = Browser::start("dashboard_reconnect");
    b.goto(&format!("{}#run=1", d.base()));
    b.wait_for("window.proleg.evaluations.length === 30");
    let status = "document.querySelector('#status').textContent";
    hosts.link(0, false);
    // A query on a cut link fails after the connection's 20-s user timeout.
    b.wait_up_to(
        &format!("{status}.startsWith('reconnecting to the store')"),
        Duration::from_secs(90),
    );
    assert_eq!(
        b.eval("window.proleg.evaluations.length === 30 && window.proleg.runs.length === 1"),
        true,
        "what was read stays shown"
    );
    let shown = b.eval(status);
    assert!(
        !shown.to_string().contains(&pg.password),
        "no password in: {shown}"
    );
    hosts.link(0, true);
    // A run started while the page was reconnecting appears once the store is back.
    let mut store = pg.open_store(db);
    let info = RunInfo {
        config: "after the outage".into(),
        algorithm: "genetic algorithm".into(),
        seed: 2,
        fitness: "displacement".into(),
        duration: 1.0,
        genes: vec!["g".into()],
    };
    proleg::optimize::store::ExperimentStore::start_run(&mut store, &info, "test", &[], &[])
        .expect("a second run");
    b.wait_up_to(
        &format!("{status}.startsWith('live') && window.proleg.runs.length === 2"),
        Duration::from_secs(90),
    );
    assert_eq!(b.eval("window.proleg.evaluations.length"), 30);
}

#[test]
fn an_evaluation_replays_in_3d_beside_the_runs_best() {
    let (_, d) = small_run("dashboard_replay3d");
    let base = format!("{}/api/runs/1/evaluations/3/replay/rapier", d.base());
    // Not before it is asked for, not from another site's form, not on an unknown engine.
    assert_eq!(get(&format!("{base}/stream.json")).0, 404);
    assert_eq!(request("POST", &base, "").0, 400);
    let (status, body) = get(&format!(
        "{}/api/runs/1/evaluations/3/replay/bullet",
        d.base()
    ));
    assert_eq!(status, 400, "{body}");
    assert!(body.contains("unknown physics engine"), "{body}");

    let b = Browser::start("dashboard_replay3d");
    b.goto(&format!("{}/replay?a=1/3&b=1/best", d.base()));
    b.wait_up_to(
        "!!(window.prolegReplay && (window.prolegReplay.ready || window.prolegReplay.error))",
        Duration::from_secs(120),
    );
    assert_eq!(
        b.eval("window.prolegReplay.error || null"),
        serde_json::Value::Null
    );
    assert_eq!(b.eval("window.prolegReplay.replays"), 2);
    assert_eq!(b.eval("window.prolegReplay.views()"), 2);
    assert!(b.eval("window.prolegReplay.pose(1, 0)").is_object());

    // The stream is the episode the optimizer scored: its last score is the stored one.
    let (status, body) = get(&format!("{base}/stream.json"));
    assert_eq!(status, 200);
    let stream: serde_json::Value = serde_json::from_str(&body).expect("JSON");
    let scores = proleg::playback::encode::decode(
        stream["score"].as_str().expect("scores"),
        f32::from_le_bytes,
    )
    .expect("base64");
    let (_, run) = get(&format!("{}/api/runs/1", d.base()));
    let run: serde_json::Value = serde_json::from_str(&run).expect("JSON");
    let stored = run["evaluations"][3]["score"].as_f64().expect("a score");
    let last = f64::from(*scores.last().expect("frames"));
    assert!(
        (last - stored).abs() < 1e-4,
        "replayed {last}, stored {stored}"
    );
}

/// The time from asking for an uncached 90-s evaluation's 3D replay to its first frame
/// drawn, for docs/replay.md.
#[test]
#[ignore = "a figure: cargo test --release --test dashboard -- --ignored --nocapture replay_first_frame"]
fn replay_first_frame_figure() {
    let dir = common::scratch("dashboard_replay_figure");
    let store = dir.join("runs.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/experiment1_ga.simulation.xml",
        ("2", "90"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let d = Dashboard::start(store.to_str().unwrap(), "127.0.0.1:0", None);
    let b = Browser::start("dashboard_replay_figure");
    b.goto(&format!("{}/", d.base()));
    let asked = Instant::now();
    b.goto(&format!("{}/replay?a=1/1", d.base()));
    b.wait_up_to(
        "!!(window.prolegReplay && window.prolegReplay.ready && window.prolegReplay.framesDrawn() > 0)",
        Duration::from_secs(120),
    );
    eprintln!(
        "uncached 90-s evaluation: first frame {:.2} s after the request",
        asked.elapsed().as_secs_f64()
    );
}
