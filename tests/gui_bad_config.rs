//! Bad input in the windows: a configuration that does not load (here: an included
//! actuation file with a word for a number) gives the control window's Load and the
//! expert dialog's Open the same located error `proleg check` gives, shown in the window,
//! and the previous simulation (or composition) stays. Runs under Xvfb.
#![cfg(feature = "gui")]

mod common;

use std::path::{Path, PathBuf};

use common::window::{get, png_colours, state};

/// A broken simulation below the repository: the demo's files, its actuation with
/// `value="forty"` on line 7; returns the simulation file.
fn broken(name: &str) -> PathBuf {
    let dir = common::root().join(format!(
        "target/test-scratch/bad-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let actuation = std::fs::read_to_string(
        common::root().join("configs/actuation/snake5p_sine40.actuation.xml"),
    )
    .unwrap()
    .replace(
        r#"name="Amplitude" value="40""#,
        r#"name="Amplitude" value="forty""#,
    );
    std::fs::write(dir.join("broken.actuation.xml"), actuation).unwrap();
    let sim = std::fs::read_to_string(common::root().join("configs/demo.simulation.xml"))
        .unwrap()
        .replace("robots/", "../../../configs/robots/")
        .replace("environments/", "../../../configs/environments/")
        .replace(
            "actuation/snake5p_sine40.actuation.xml",
            "broken.actuation.xml",
        );
    let file = dir.join("broken.simulation.xml");
    std::fs::write(&file, sim).unwrap();
    file
}

/// What `proleg check` says of it (the windows load with the same registry), one line.
fn expected(file: &Path) -> String {
    let e = proleg::control::load_simulation_in(file, &proleg::control::ModuleRegistry::standard())
        .unwrap_err()
        .to_string();
    assert!(e.contains("broken.actuation.xml:7:"), "{e}");
    e.replace('\n', "\\n")
}

#[test]
fn the_control_window_shows_the_located_error_and_keeps_running() {
    let file = broken("control");
    let dir = file.parent().unwrap().to_path_buf();
    let (st, shot, script) = (
        dir.join("state.txt"),
        dir.join("error.png"),
        dir.join("load.script"),
    );
    std::fs::write(
        &script,
        format!(
            "wait 2\nstart\nrun-until 0.5\nload {}\nrun-until 1.0\nstart\nstate {}\nscreenshot {}\nquit\n",
            file.display(),
            st.display(),
            shot.display()
        ),
    )
    .unwrap();
    let (ok, out) = common::window::run(&["gui", "configs/demo.simulation.xml"], &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert_eq!(
        get(&s, "error"),
        format!(
            "{}\\n(still showing configs/demo.simulation.xml)",
            expected(&file)
        )
    );
    assert_eq!(get(&s, "config"), "configs/demo.simulation.xml");
    assert_eq!(get(&s, "running"), "true", "the demo runs on");
    let t: f64 = get(&s, "sim_time").parse().unwrap();
    assert!(t >= 1.0, "the demo went on to {t} s");
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50);
}

#[test]
fn a_broken_file_on_the_command_line_opens_the_window_with_its_error() {
    let file = broken("cmdline");
    let dir = file.parent().unwrap().to_path_buf();
    let (st, script) = (dir.join("state.txt"), dir.join("open.script"));
    std::fs::write(&script, format!("wait 2\nstate {}\nquit\n", st.display())).unwrap();
    let path = file.display().to_string();
    let (ok, out) = common::window::run(&["gui", &path], &script);
    assert!(ok, "the window must open:\n{out}");
    let s = state(&st);
    assert_eq!(
        get(&s, "error"),
        format!(
            "{}\\n(showing configs/demo.simulation.xml instead)",
            expected(&file)
        )
    );
    assert_eq!(get(&s, "config"), "configs/demo.simulation.xml");
    assert_eq!(get(&s, "config_field"), path, "kept to fix and load again");
}

#[test]
fn the_expert_dialog_shows_the_same_error_and_keeps_its_composition() {
    let file = broken("expert");
    let dir = file.parent().unwrap().to_path_buf();
    let (before, after, script) = (
        dir.join("before.txt"),
        dir.join("after.txt"),
        dir.join("open.script"),
    );
    std::fs::write(
        &script,
        format!(
            "wait 2\ntool expert\nstate {}\nexpert-open {}\nwait 2\nstate {}\nquit\n",
            before.display(),
            file.display(),
            after.display()
        ),
    )
    .unwrap();
    let (ok, out) = common::window::run(&["wizard", "--out", dir.to_str().unwrap()], &script);
    assert!(ok, "the window failed:\n{out}");
    let (b, a) = (state(&before), state(&after));
    let e = expected(&file);
    assert_eq!(get(&a, "status"), format!("error: {e}"));
    assert_eq!(get(&a, "expert_check"), format!("error: {e}"));
    assert_eq!(
        get(&a, "expert_robot"),
        get(&b, "expert_robot"),
        "the composition is kept"
    );
}
