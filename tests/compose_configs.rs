//! Configurations made without XML: a simulation written only by the wizard passes
//! `proleg check` and crawls in `proleg run`; the experiment-2 terrain is rebuilt with the
//! environment editor's operations and matches the hand-written file body for body.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use proleg::compose::env_edit::{EnvEditor, Selected};
use proleg::compose::library::LibraryItem;
use proleg::compose::robot_builder::PartSet;
use proleg::compose::wizard::{Page, Wizard};
use proleg::config::body::Shape;
use proleg::config::environment::parse_environment_file;
use proleg::config::resolve::environment::{EnvironmentModel, resolve_environment};
use proleg::config::source::FsSource;

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("proleg_compose_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn proleg(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(args)
        .current_dir(common::root())
        .output()
        .unwrap();
    (
        out.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

#[test]
fn wizard_made_simulation_checks_and_crawls() {
    let out = temp_dir("wizard");
    let root = common::root();
    let mut w = Wizard::new(&root.join("configs"), &out, "20261122_150000");
    w.set_robot_name("wizsnake").unwrap();
    w.set_topology("ppppp").unwrap();
    w.set_parts(PartSet::Touch);
    w.next_page().unwrap();
    w.set_simple_behaviour("PatternGenerator_sinusoidal")
        .unwrap();
    w.set_group_param(1, "PatternGenerator_sinusoidal", "Amplitude", &[40.0])
        .unwrap();
    w.next_page().unwrap();
    // Environment: a box ahead of the robot, dropped onto the default floor.
    w.env.add(&LibraryItem::Box, 0.0, 1.5);
    w.next_page().unwrap();
    w.props.duration = 4.0;
    w.next_page().unwrap();
    assert_eq!(w.page, Page::Summary);
    let sim = w.save().unwrap();
    let sim = sim.to_string_lossy().into_owned();
    let (ok, text) = proleg(&["check", &sim]);
    assert!(ok, "{text}");
    assert!(text.contains("joints 5 [PPPPP]"), "{text}");
    let (ok, text) = proleg(&["run", &sim]);
    assert!(ok, "{text}");
    let disp: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("displacement"))
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no displacement in:\n{text}"));
    assert!(
        disp > 0.2,
        "the wizard's snake crawled only {disp} m in 4 s"
    );
    std::fs::remove_dir_all(out).ok();
}

fn env_model(path: &Path) -> EnvironmentModel {
    let text = std::fs::read_to_string(path).unwrap();
    let file = parse_environment_file(&path.display().to_string(), &text).unwrap();
    resolve_environment(&FsSource, path, &file).unwrap()
}

#[test]
fn irregular_obstacle_terrain_is_rebuilt_in_the_editor() {
    let root = common::root();
    // Saved below the repository so `assets/meshes/...` is found as the original finds it
    // (not in configs/, which other tests list).
    let out = root.join(format!(
        "target/test-scratch/compose_irregular_{}",
        std::process::id()
    ));
    let path = out.join("rebuilt_irregular.env.xml");
    let mut e = EnvEditor::new(&path);
    // The default floor, doubled to 16 m x 16 m.
    e.select(Some(Selected::Object(0))).unwrap();
    e.scale([2.0, 2.0, 1.0]).unwrap();
    // The obstacle mesh, dropped at the origin: it lands on the floor.
    e.add(
        &LibraryItem::Mesh("assets/meshes/irregular_obstacle.obj".into()),
        0.0,
        0.0,
    );
    e.set_friction(1.0).unwrap();
    e.set_colour([0.6, 0.45, 0.3]).unwrap();
    // The scale beside the track: 1 m segments, yellow and red.
    for k in 0..6 {
        e.add(&LibraryItem::Box, 1.2, 0.5 + k as f64);
        e.scale([0.4, 5.0, 0.01]).unwrap();
        e.set_colour(if k % 2 == 0 {
            [1.0, 0.85, 0.1]
        } else {
            [0.9, 0.15, 0.1]
        })
        .unwrap();
    }
    e.save(&path).unwrap();
    let rebuilt = env_model(&path);
    std::fs::remove_dir_all(out).ok();
    let original = env_model(&root.join("configs/environments/irregular.env.xml"));
    assert_eq!(rebuilt.physics.gravity, original.physics.gravity);
    assert_eq!(
        rebuilt.physics.self_collision,
        original.physics.self_collision
    );
    assert_eq!(rebuilt.robot_pose, original.robot_pose);
    assert_eq!(rebuilt.bodies.len(), original.bodies.len());
    let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9);
    for o in &original.bodies {
        let og = &o.geoms[0];
        let found = rebuilt.bodies.iter().any(|r| {
            let rg = &r.geoms[0];
            let world = |b: &proleg::config::resolve::environment::EnvBody,
                         g: &proleg::config::body::Geom| {
                b.pose.mul(&g.pose).translation
            };
            let same_shape = match (&og.shape, &rg.shape) {
                (Shape::Box { extents: a }, Shape::Box { extents: b }) => close(a, b),
                (
                    Shape::Trimesh {
                        file: a,
                        scale: sa,
                        collision: ca,
                    },
                    Shape::Trimesh {
                        file: b,
                        scale: sb,
                        collision: cb,
                    },
                ) => a == b && (sa - sb).abs() < 1e-12 && ca == cb,
                _ => false,
            };
            same_shape
                && close(&world(o, og), &world(r, rg))
                && rg.diffuse_color == og.diffuse_color
                && (og.friction.is_none() || rg.friction == og.friction)
                && r.kind == o.kind
        });
        assert!(found, "no rebuilt body matches {} ({:?})", o.name, og.shape);
    }
}

#[test]
fn obstacle_pieces_from_the_library_make_the_whole_obstacle() {
    let root = common::root();
    let mut e = EnvEditor::new(root.join("configs/environments/_pieces.env.xml"));
    let whole = e.add(
        &LibraryItem::Mesh("assets/meshes/irregular_obstacle.obj".into()),
        0.0,
        0.0,
    );
    let whole = e.bounds(whole);
    let mut e = EnvEditor::new(root.join("configs/environments/_pieces.env.xml"));
    // Each piece is centred on its origin; the obstacle runs from y = 0.6 m over 3.6 m.
    let mut union: Option<proleg::compose::env_edit::Aabb> = None;
    for (name, s0, s1) in [
        ("hump", 0.0, 0.24),
        ("plateau_trough", 0.24, 0.80),
        ("hill", 0.80, 1.0),
    ] {
        let y = 0.6 + 3.6 * (s0 + s1) / 2.0;
        let i = e.add(
            &LibraryItem::Mesh(format!("assets/meshes/obstacle_{name}.obj")),
            0.0,
            y,
        );
        let b = e.bounds(i);
        assert!(b.min[2].abs() < 1e-9, "{name} does not stand on the floor");
        union = Some(match union {
            None => b,
            Some(u) => proleg::compose::env_edit::Aabb {
                min: [0, 1, 2].map(|k| u.min[k].min(b.min[k])),
                max: [0, 1, 2].map(|k| u.max[k].max(b.max[k])),
            },
        });
    }
    let union = union.unwrap();
    for k in 0..3 {
        assert!(
            (union.min[k] - whole.min[k]).abs() < 1e-4,
            "min {k}: {union:?} vs {whole:?}"
        );
        assert!(
            (union.max[k] - whole.max[k]).abs() < 1e-4,
            "max {k}: {union:?} vs {whole:?}"
        );
    }
}
