//! Exports that travel: `proleg results --export-robot`, the wizard's save and
//! `proleg import -o` write a folder that runs on its own (`proleg calibrate -o`: in
//! `tests/calibrate.rs`). Written far from `configs/` (a temporary folder: no folder above
//! it holds the shipped environments or parts), moved elsewhere, and run there, a
//! candidate scores what the store says, on each engine that scored it; a design or an
//! imported robot goes as far as it did before the move.

mod common;

use std::path::{Path, PathBuf};

use proleg::compose::library::LibraryItem;
use proleg::compose::robot_builder::PartSet;
use proleg::compose::wizard::Wizard;
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

/// Every file the simulation `file` reads is inside `dir`: nothing names a file elsewhere.
fn reads_only_inside(file: &Path, dir: &Path) {
    use proleg::config::{FsSource, RecordingSource, load_simulation_with};
    let source = RecordingSource::new(&FsSource);
    load_simulation_with(&source, file, &proleg::control::ModuleRegistry::standard())
        .expect("it loads");
    let files = source.files();
    assert!(files.len() >= 4, "{files:?}");
    for (path, _) in files {
        assert!(
            Path::new(&path).starts_with(dir),
            "{path} is outside {}",
            dir.display()
        );
    }
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
    reads_only_inside(&file, &far.join("moved elsewhere"));
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
    reads_only_inside(&file, &far.join("moved elsewhere"));
    for (engine, score) in engines {
        assert_eq!(
            displacement(&file, &engine),
            format!("{score:.4}"),
            "on {engine}"
        );
    }
    let _ = std::fs::remove_dir_all(&far);
}

#[test]
fn wizard_designs_run_from_a_moved_folder_as_before() {
    let far = far_folder("wizard");
    let out = far.join("my designs");
    let configs = common::root().join("configs");
    // A robot built of touch parts (their sensors are files of their own) on a floor with
    // the library's mesh obstacle, and the shipped 8-module snake chosen as it is.
    let mut built = Wizard::new(&configs, &out, "1");
    built.set_robot_name("travel").expect("a name");
    built.set_topology("ppppp").expect("a topology");
    built.set_parts(PartSet::Touch);
    built
        .set_simple_behaviour("PatternGenerator_sinusoidal")
        .expect("a module");
    built.env.add(
        &LibraryItem::Mesh("assets/meshes/irregular_obstacle.obj".into()),
        0.0,
        1.0,
    );
    built.props.duration = 3.0;
    let mut chosen = Wizard::new(&configs, &out, "2");
    chosen
        .use_existing_robot(Path::new("robots/snake8py.robot.xml"))
        .expect("the shipped robot");
    chosen
        .set_simple_behaviour("PatternGenerator_sinusoidal")
        .expect("a module");
    chosen.props.duration = 3.0;
    let files: Vec<PathBuf> = [built, chosen]
        .iter_mut()
        .map(|w| w.save().expect("saved"))
        .collect();
    let before: Vec<String> = files.iter().map(|f| displacement(f, "rapier")).collect();
    let moved = far.join("moved elsewhere");
    std::fs::rename(&out, &moved).expect("the folder moves");
    for (file, before) in files.iter().zip(before) {
        let file = moved.join(file.file_name().expect("a file name"));
        reads_only_inside(&file, &moved);
        assert_eq!(displacement(&file, "rapier"), before, "{}", file.display());
        if common::mujoco_here("a moved wizard design on MuJoCo") {
            let on_mujoco: f64 = displacement(&file, "mujoco").parse().expect("a number");
            assert!(on_mujoco.is_finite(), "{on_mujoco}");
        }
    }
    let _ = std::fs::remove_dir_all(&far);
}

#[test]
fn an_imported_robot_with_a_mesh_runs_from_a_moved_folder_as_before() {
    let far = far_folder("import");
    // A URDF whose first link is a mesh of a package elsewhere.
    let package = far.join("workspace/src/mypkg");
    std::fs::create_dir_all(package.join("meshes")).expect("a folder");
    std::fs::write(
        package.join("meshes/tet.obj"),
        "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .expect("the mesh");
    let link = |name: &str, geom: &str| {
        format!(
            "<link name=\"{name}\"><inertial><mass value=\"0.2\"/><inertia ixx=\"1e-4\" ixy=\"0\" \
             ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" izz=\"1e-4\"/></inertial><collision><geometry>{geom}\
             </geometry></collision></link>"
        )
    };
    let urdf = far.join("tet.urdf");
    std::fs::write(
        &urdf,
        format!(
            "<robot name=\"tet\">{}{}<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>\
             <child link=\"b\"/><origin xyz=\"0 0.12 0\"/><axis xyz=\"1 0 0\"/>\
             <limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"3\"/></joint></robot>",
            link("a", "<mesh filename=\"package://mypkg/meshes/tet.obj\"/>"),
            link("b", "<box size=\"0.1 0.1 0.1\"/>")
        ),
    )
    .expect("the URDF");
    let out = far.join("imported");
    let given = format!("mypkg={}", package.display());
    let (ok, text, err) = common::proleg(&[
        "import",
        urdf.to_str().expect("a path"),
        "-o",
        out.to_str().expect("a path"),
        "--package-path",
        &given,
    ]);
    assert!(ok, "{err}");
    let file = out.join("tet.simulation.xml");
    assert!(text.contains("tet.simulation.xml"), "{text}");
    let before = displacement(&file, "rapier");
    // The package and the URDF gone, the folder moved: it runs as before.
    std::fs::remove_dir_all(far.join("workspace")).expect("removed");
    std::fs::remove_file(&urdf).expect("removed");
    let moved = far.join("moved elsewhere");
    std::fs::rename(&out, &moved).expect("the folder moves");
    assert_eq!(
        displacement(&moved.join("tet.simulation.xml"), "rapier"),
        before
    );
    reads_only_inside(&moved.join("tet.simulation.xml"), &moved);
    if common::mujoco_here("a moved imported robot on MuJoCo") {
        let on_mujoco: f64 = displacement(&moved.join("tet.simulation.xml"), "mujoco")
            .parse()
            .expect("a number");
        assert!(on_mujoco.is_finite(), "{on_mujoco}");
    }
    let _ = std::fs::remove_dir_all(&far);
}
