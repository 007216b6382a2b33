//! The configuration window for real (`proleg wizard` under Xvfb with Mesa's software
//! renderer, driven by scripts): the wizard through every page to saved files that
//! `proleg check` accepts, the environment editor adding, dropping (ray cast from the
//! view), moving, rotating, scaling, giving friction, undoing and saving, and the expert
//! composition; the XML written is read back and checked.
#![cfg(feature = "gui")]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::window::{get, png_colours, state};
use proleg::config::body::{BodyKind, Shape};
use proleg::config::environment::{EnvObject, parse_environment_file};
use proleg::config::kinbody::KinBody;

/// A folder below the repository (so `assets/meshes/...` resolves as from configs/).
fn scratch(name: &str) -> PathBuf {
    let dir = common::root().join(format!(
        "target/test-scratch/setup-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// Runs `proleg wizard --out OUT --script` with these commands; returns the state file.
fn scripted(name: &str, out: &Path, commands: &str) -> Vec<(String, String)> {
    let script = out.join(format!("{name}.script"));
    let st = out.join(format!("{name}.state"));
    std::fs::write(
        &script,
        format!("{commands}\nstate {}\nquit\n", st.display()),
    )
    .expect("script");
    let (ok, text) = common::window::run(&["wizard", "--out", &out.display().to_string()], &script);
    assert!(ok, "the configuration window failed:\n{text}");
    state(&st)
}

fn inline(o: &EnvObject) -> &KinBody {
    match o {
        EnvObject::Inline(kb) => kb,
        EnvObject::Include(i) => panic!("an include: {}", i.file),
        EnvObject::Terrain(t) => panic!("a terrain: {}", t.label()),
    }
}

#[test]
fn wizard_walks_every_page_and_writes_a_checked_configuration() {
    let out = scratch("wizard");
    let shot = out.join("summary.png");
    let previewed = out.join("preview.state");
    let s = scripted(
        "wizard",
        &out,
        &format!(
            "wait 2\n\
             set robot.name wizsnake\nset robot.topology pypypyp\nset robot.parts touch\nnext\n\
             set behaviour.clear\n\
             set behaviour.group 1010101 PatternGenerator_sinusoidal\n\
             set behaviour.group 0101010 DirectJointAccess\n\
             set behaviour.param 1 PatternGenerator_sinusoidal Amplitude 35\nnext\n\
             add stairs 0 1.2\nfriction 0.8\nselect robot\nyaw 10\npreview\nstate {}\nnext\n\
             set sim.mode ga\nset sim.duration 20\nback\nnext\nnext\n\
             set opt.register PatternGenerator_sinusoidal Amplitude all individual 0 40 0.25\n\
             set opt.popsize 10\nnext\nsave\nwait 2\nscreenshot {}",
            previewed.display(),
            shot.display()
        ),
    );
    // "Preview" ran the robot in the edited scene: it crawled.
    let moved: f64 = get(&state(&previewed), "preview_displacement")
        .parse()
        .expect("a preview distance");
    assert!(moved > 0.05, "the preview robot crawled {moved} m");
    // Its path is kept to draw: the start and one point per 0.1 s of the 5-s run.
    assert_eq!(get(&state(&previewed), "preview_track"), "51");
    assert_eq!(get(&s, "page"), "Summary and save");
    assert_eq!(get(&s, "page_number"), "6/6");
    let sim = PathBuf::from(get(&s, "saved"));
    assert!(sim.is_file(), "{}", sim.display());
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50, "a blank screenshot ({colours} colours)");
    // The written files, as proleg reads them.
    let loaded = proleg::control::load_simulation(&sim).expect("the wizard's files load");
    assert_eq!(loaded.robot.pattern(), "PYPYPYP");
    assert_eq!(loaded.robot.joints.len(), 7);
    let masks: Vec<String> = loaded
        .files
        .actuation
        .modules
        .iter()
        .map(|m| format!("{} {}", m.name, m.joints))
        .collect();
    assert_eq!(
        masks,
        [
            "PatternGenerator_sinusoidal 1010101",
            "DirectJointAccess 0101010"
        ]
    );
    let opt = loaded.optimizer.as_ref().expect("the GA settings");
    assert_eq!(
        opt.parameters[0].genes, 4,
        "one amplitude gene per pitch joint"
    );
    let yaw = proleg::compose::env_edit::yaw_of(loaded.environment.robot_pose.rotation);
    assert!((yaw - 10.0).abs() < 1e-6, "robot heading {yaw}");
    let stairs: Vec<_> = loaded
        .environment
        .bodies
        .iter()
        .filter(|b| b.name.starts_with("stairs1_step"))
        .collect();
    assert_eq!(stairs.len(), 5);
    assert!(stairs.iter().all(|b| b.geoms[0].friction == Some(0.8)));
    // And `proleg check` says the same.
    let check = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .arg("check")
        .arg(&sim)
        .output()
        .expect("proleg check");
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    std::fs::remove_dir_all(out).ok();
}

#[test]
fn wizard_sets_up_a_co_design_map_elites_run_that_optimizes() {
    let out = scratch("wizard-codesign");
    let shot = out.join("optimization.png");
    let s = scripted(
        "codesign",
        &out,
        &format!(
            "wait 2\n\
             set robot.name cosnake\nset robot.topology ppp\nnext\n\
             set behaviour.simple PatternGenerator_sinusoidal\nnext\nnext\n\
             set sim.mode mapelites\nset sim.duration 1\nnext\n\
             set opt.register PatternGenerator_sinusoidal Amplitude all uniform 0 60 5\n\
             set opt.register PatternGenerator_sinusoidal Phase_Difference all uniform -180 180 30\n\
             set opt.morphology 3 6 pitch,yaw plain --motif 2\nset opt.max-evals 30\n\
             wait 1\nscreenshot {}\nnext\nsave\nwait 1",
            shot.display()
        ),
    );
    let sim = PathBuf::from(get(&s, "saved"));
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50, "a blank screenshot ({colours} colours)");
    // The files hold MAP-Elites over module count and share of yaw joints, and the
    // morphology ranges.
    let loaded = proleg::control::load_simulation(&sim).expect("the wizard's files load");
    let model = loaded.optimizer.as_ref().expect("an optimizer file");
    let m = model.spec.morphology.as_ref().expect("a morphology");
    assert_eq!(
        (m.modules, m.motif, m.orientations.len()),
        ([3, 6], Some(2), 2)
    );
    let proleg::config::optimizer::Algorithm::MapElites(me) = &model.spec.algorithm else {
        panic!("{:?}", model.spec.algorithm)
    };
    assert_eq!(me.descriptors[0].bins, 4, "one cell per module count 3..6");
    assert!(me.descriptors[1].yaw_share);
    // And the run it sets up searches bodies: its archive lists the best body.
    let store = out.join("codesign.sqlite");
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_proleg"))
            .args(args)
            .output()
            .expect("proleg");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let store_arg = store.display().to_string();
    run(&[
        "optimize",
        sim.to_str().unwrap(),
        "--quiet",
        "--store",
        &store_arg,
    ]);
    let results = run(&["results", &store_arg]);
    assert!(results.contains("30 evaluations"), "{results}");
    assert!(
        results.contains("share of yaw joints; best body"),
        "{results}"
    );
    std::fs::remove_dir_all(out).ok();
}

#[test]
fn wizard_refuses_to_leave_an_invalid_page_and_names_the_script_line() {
    let out = scratch("wizard-bad");
    let script = out.join("bad.script");
    std::fs::write(
        &script,
        "set robot.topology ppp\nset behaviour.group 11 DirectJointAccess\nquit\n",
    )
    .expect("script");
    let (ok, text) = common::window::run(&["wizard", "--out", &out.display().to_string()], &script);
    assert!(
        !ok,
        "a mask of 2 joints for a 3-joint robot was accepted:\n{text}"
    );
    assert!(
        text.contains("bad.script:2:") && text.contains("3 joints"),
        "{text}"
    );
    std::fs::remove_dir_all(out).ok();
}

#[test]
fn editor_adds_drops_moves_turns_scales_and_saves() {
    let out = scratch("editor");
    let env = out.join("edited.env.xml");
    let dropped = out.join("dropped.state");
    let shot = out.join("editor.png");
    let s = scripted(
        "editor",
        &out,
        &format!(
            "tool editor\nwait 2\n\
             add box 0.5 1\nmove-to 0.5 1.5 0.1\nrotate 30\nrotate 15\nscale 2 1 0.5\nfriction 0.9\n\
             add cylinder 0.5 1.5\n\
             add irregular_obstacle 0 0\nfriction 1\npreview\n\
             drop sphere 430 520\nstate {}\nundo\nredo\nselect 4\ndelete\n\
             select robot\nmove-by 0 -0.2 0\n\
             select 1\ndrag-to -1.5 2\nwait 2\nscreenshot {}\nenv-save {}",
            dropped.display(),
            shot.display(),
            env.display()
        ),
    );
    // The dropped ball landed on the floor (radius 0.1 m) where the ray met the ground.
    let d = state(&dropped);
    assert_eq!(get(&d, "selected_name"), "sphere1");
    let p: Vec<f64> = get(&d, "selected_position")
        .split(' ')
        .map(|v| v.parse().expect("position"))
        .collect();
    assert!((p[2] - 0.1).abs() < 1e-6, "the ball floats at {}", p[2]);
    assert!(p[0].abs() < 4.0 && p[1].abs() < 4.0, "off the floor: {p:?}");
    assert_eq!(
        get(&s, "env_objects"),
        "4",
        "floor, box, cylinder, obstacle"
    );
    let (_, _, colours) = png_colours(&shot);
    assert!(colours > 50, "a blank editor ({colours} colours)");
    // The saved file.
    let text = std::fs::read_to_string(&env).expect("saved");
    let file = parse_environment_file("edited.env.xml", &text).expect("valid XML");
    assert_eq!(file.objects.len(), 4);
    let pose = file.robot_pose.expect("robot pose");
    assert!(
        (pose.translation[1] + 0.2).abs() < 1e-9,
        "{:?}",
        pose.translation
    );
    let b = inline(&file.objects[1]);
    assert_eq!(b.name.as_deref(), Some("box1"));
    assert!(
        (b.pose.translation[0] + 1.5).abs() < 1e-9 && (b.pose.translation[1] - 2.0).abs() < 1e-9
    );
    let yaw = proleg::compose::env_edit::yaw_of(b.pose.rotation);
    assert!((yaw - 45.0).abs() < 1e-9, "box heading {yaw}");
    let g = &b.bodies[0].geoms[0];
    assert_eq!(
        g.shape,
        Shape::Box {
            extents: [0.2, 0.1, 0.05]
        }
    );
    assert_eq!(g.friction, Some(0.9));
    // Scaled to 0.1 m high and dragged beside the obstacle, it rests on the floor.
    assert!(
        (b.pose.translation[2] - 0.05).abs() < 1e-9,
        "{}",
        b.pose.translation[2]
    );
    assert_eq!(b.bodies[0].kind, BodyKind::Static);
    let mesh = inline(&file.objects[3]);
    assert_eq!(mesh.bodies[0].geoms[0].friction, Some(1.0));
    assert!(
        matches!(&mesh.bodies[0].geoms[0].shape, Shape::Trimesh { file, .. } if file == "assets/meshes/irregular_obstacle.obj")
    );
    std::fs::remove_dir_all(out).ok();
}

#[test]
fn expert_composes_existing_files() {
    let out = scratch("expert");
    let sim = out.join("tactile_stairs.simulation.xml");
    let s = scripted(
        "expert",
        &out,
        &format!(
            "tool expert\n\
             expert robot configs/robots/tactile5p.robot.xml\n\
             expert actuation configs/actuation/tactile5p_sine30_adaptive.actuation.xml\n\
             expert environment configs/environments/stairs.env.xml\n\
             expert-save {}",
            sim.display()
        ),
    );
    assert!(
        get(&s, "expert_check").starts_with("tactile5p: 5 joints, 2 modules"),
        "{s:?}"
    );
    let loaded = proleg::control::load_simulation(&sim).expect("composed file loads");
    assert!(loaded.environment.bodies.iter().any(|b| b.name == "step5"));
    std::fs::remove_dir_all(out).ok();
}

#[test]
fn a_module_compiled_in_the_library_is_offered_by_the_wizard() {
    let out = scratch("modules");
    let ws = out.join("plugins");
    common::plugin_workspace(&ws);
    // The generated crate builds as it is; a line of the step is filled in, as a user would.
    let shot = out.join("modules.png");
    let s = scripted(
        "modules",
        &out,
        &format!(
            "wait 2\nmodules open\nmodule-workspace {ws}\n\
             module-declare WizWave Amplitude=30:0..90 Period=2:0.1..10 data=Phase helpers=smooth\n\
             module-compile\n\
             set robot.topology ppppp\nnext\nset behaviour.simple WizWave\nnext\n\
             wait 3\nscreenshot {shot}",
            ws = ws.display(),
            shot = shot.display()
        ),
    );
    assert_eq!(get(&s, "module_loaded"), "WizWave", "{s:?}");
    assert!(get(&s, "registry_modules").contains("WizWave"), "{s:?}");
    // The behaviour page accepted the new module (the wizard went on to the next page).
    assert_eq!(get(&s, "page"), "Environment", "{s:?}");
    assert!(ws.join("wiz_wave/src/lib.rs").is_file());
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50);
}
