//! Exports that travel (issue 52): `proleg results --export-robot` writes a folder that
//! runs on its own. Exported far from `configs/` (a temporary folder: no folder above it
//! holds the shipped environments or parts), moved elsewhere, and run there, the candidate
//! scores what the store says, on each engine that scored it.

mod common;

use std::path::{Path, PathBuf};

use proleg::optimize::store::{Store, StoreLocation};

/// A folder of this test's own under the system's temporary folder, empty.
fn far_folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("proleg-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// `proleg results STORE --export-robot best -o DIR`, then DIR moved to a new name: the
/// simulation file the command wrote, at its new place.
fn export_and_move(store: &Path, far: &Path, file: &str) -> PathBuf {
    let out = far.join("exported");
    let (ok, text, err) = common::proleg(&[
        "results",
        store.to_str().expect("a path"),
        "--export-robot",
        "best",
        "-o",
        out.to_str().expect("a path"),
    ]);
    assert!(ok, "{err}");
    let written = out.join(file);
    assert!(
        text.contains(&format!("candidate written: {}", written.display())),
        "{text}"
    );
    let moved = far.join("moved elsewhere");
    std::fs::rename(&out, &moved).expect("the folder moves");
    moved.join(file)
}

/// `proleg run FILE --engine ENGINE` from the system's temporary folder: the displacement
/// it prints.
fn displacement(file: &Path, engine: &str) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["run", file.to_str().expect("a path"), "--engine", engine])
        .current_dir(std::env::temp_dir())
        .output()
        .expect("proleg runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text.lines()
        .find_map(|l| l.strip_prefix("displacement"))
        .and_then(|l| l.split_whitespace().next())
        .unwrap_or_else(|| panic!("no displacement in {text}"))
        .to_string()
}

/// The best evaluation's score, and its score on each engine, as stored.
fn stored_best(store: &Path) -> (f64, Vec<(String, f64)>) {
    let mut s = Store::open_existing(&StoreLocation::sqlite(store)).expect("the store");
    let run = s.runs().expect("runs")[0].id;
    let best = s
        .evaluations(run)
        .expect("evaluations")
        .into_iter()
        .filter(|e| e.score.is_finite())
        .max_by(|a, b| a.score.total_cmp(&b.score))
        .expect("a scored evaluation");
    let engines = best
        .engines
        .iter()
        .map(|(k, v)| (k.to_string(), *v))
        .collect();
    (best.score, engines)
}

#[test]
fn an_exported_body_runs_from_a_moved_folder_to_its_stored_score() {
    let far = far_folder("export_codesign");
    let store = far.join("codesign.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/codesign_flat.simulation.xml",
        ("24", "1"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let (score, _) = stored_best(&store);
    let file = export_and_move(&store, &far, "design.simulation.xml");
    assert_eq!(displacement(&file, "rapier"), format!("{score:.4}"));
    if common::mujoco_here("an exported body on MuJoCo") {
        let on_mujoco: f64 = displacement(&file, "mujoco").parse().expect("a number");
        assert!(on_mujoco.is_finite(), "{on_mujoco}");
    }
    let _ = std::fs::remove_dir_all(&far);
}

#[test]
fn an_exported_gait_runs_from_a_moved_folder_to_each_engines_stored_score() {
    if !common::mujoco_here("an exported gait scored on both engines") {
        return;
    }
    let far = far_folder("export_gait");
    let store = far.join("gait.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/gait_from_scratch_engines.simulation.xml",
        ("12", "2"),
        &store,
        &["--workers", "2"],
    );
    assert!(ok, "{err}");
    let (_, engines) = stored_best(&store);
    assert_eq!(engines.len(), 2, "{engines:?}");
    let file = export_and_move(&store, &far, "candidate.simulation.xml");
    for (engine, score) in engines {
        assert_eq!(
            displacement(&file, &engine),
            format!("{score:.4}"),
            "on {engine}"
        );
    }
    let _ = std::fs::remove_dir_all(&far);
}
