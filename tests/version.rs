//! One version everywhere: the workspace's in Cargo.toml is the program's `--version`, the
//! one a store records with every run it starts, and CHANGELOG.md's newest release (the
//! Python package's `__version__` is checked against `--version` in python/tests).

mod common;

/// The `version = "..."` under `[workspace.package]` in Cargo.toml.
fn workspace_version() -> String {
    let toml = std::fs::read_to_string(common::root().join("Cargo.toml")).unwrap();
    let section = toml.split("[workspace.package]").nth(1).unwrap();
    let line = section
        .lines()
        .find_map(|l| l.trim().strip_prefix("version = "))
        .unwrap();
    line.trim_matches('"').to_string()
}

#[test]
fn the_program_its_stores_and_the_changelog_carry_cargo_tomls_version() {
    let version = workspace_version();
    assert_eq!(proleg::VERSION, version);

    let (ok, out, err) = common::proleg(&["--version"]);
    assert!(ok, "{err}");
    assert_eq!(out.trim(), format!("proleg {version}"));

    let store = common::scratch("version").join("store.sqlite");
    let (ok, _, err) = common::proleg(&[
        "optimize",
        "configs/experiment1_ga.simulation.xml",
        "--max-evals",
        "25",
        "--duration",
        "0.5",
        "--quiet",
        "--store",
        store.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let db = rusqlite::Connection::open(&store).unwrap();
    let programs: Vec<String> = db
        .prepare("SELECT program FROM runs")
        .unwrap()
        .query_map([], |r| r.get(0))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(programs, [format!("proleg {version}")]);

    let changelog = std::fs::read_to_string(common::root().join("CHANGELOG.md")).unwrap();
    let newest = changelog
        .lines()
        .filter_map(|l| l.strip_prefix("## ["))
        .find(|l| !l.starts_with("Unreleased"))
        .and_then(|l| l.split(']').next());
    assert_eq!(
        newest,
        Some(version.as_str()),
        "CHANGELOG.md's newest release"
    );
}
