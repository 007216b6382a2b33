//! The control window for real: `proleg gui` on the demo under Xvfb with Mesa's software
//! renderer, driven by a script (start, change a parameter, add a live plot, pause), with a
//! screenshot and the app state checked afterwards. Needs the `gui` feature, and a display
//! or `xvfb-run` (the test command installs `xvfb` and `mesa-vulkan-drivers`).
#![cfg(feature = "gui")]

mod common;

use std::path::Path;
use std::process::Command;

use common::window::{get, png_colours, scratch, state};

/// Runs `proleg gui CONFIG --script SCRIPT`.
fn run_window(config: &str, script: &Path) -> (bool, String) {
    common::window::run(&["gui", config], script)
}

#[test]
fn window_runs_the_demo_changes_a_parameter_and_plots() {
    let dir = scratch("control");
    let (shot, st) = (dir.join("control.png"), dir.join("state.txt"));
    let script = dir.join("control.script");
    std::fs::write(
        &script,
        format!(
            "wait 2\npanel all\nstart\nrun-until 1.0\n\
             set PatternGenerator_sinusoidal Amplitude 20\n\
             plot Robot_Data/y_pos PatternGenerator_sinusoidal/Angle[0] PatternGenerator_sinusoidal/Angle[2]\n\
             run-until 3.0\npause\nwait 4\nscreenshot {}\nstate {}\nquit\n",
            shot.display(),
            st.display()
        ),
    )
    .expect("script");
    let (ok, out) = run_window("configs/demo.simulation.xml", &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert_eq!(get(&s, "running"), "false");
    let t: f64 = get(&s, "sim_time").parse().expect("time");
    assert!((3.0..3.5).contains(&t), "paused at {t} s");
    assert_eq!(get(&s, "plots"), "1");
    // The slider API set every joint's amplitude; the others kept theirs.
    let params = get(&s, "parameters");
    assert!(
        params.contains("PatternGenerator_sinusoidal:Amplitude=20,20,20,20,20;"),
        "{params}"
    );
    assert!(
        params.contains("Phase_Difference=55,55,55,55,55;"),
        "{params}"
    );
    // The snake crawled forward (+y) in its 3 s.
    let com: Vec<f64> = get(&s, "com")
        .split(' ')
        .map(|v| v.parse().expect("com"))
        .collect();
    assert!(com[1] > 0.03, "centre of mass {com:?}");
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50, "screenshot has only {colours} colours");
}

#[test]
fn restart_says_it_set_the_files_values_and_keeps_the_tuned_ones_on_request() {
    let dir = scratch("restart_tuned");
    let (aside, kept, script) = (
        dir.join("aside.txt"),
        dir.join("kept.txt"),
        dir.join("restart.script"),
    );
    std::fs::write(
        &script,
        format!(
            "wait 2\nset PatternGenerator_sinusoidal Amplitude 20\nrestart\nstate {}\nkeep-tuned\nstate {}\nquit\n",
            aside.display(),
            kept.display()
        ),
    )
    .expect("script");
    let (ok, out) = run_window("configs/demo.simulation.xml", &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&aside);
    assert_eq!(get(&s, "tuned_aside"), "true", "the restart says so");
    assert!(
        get(&s, "parameters").contains("PatternGenerator_sinusoidal:Amplitude=40,40,40,40,40;")
    );
    let s = state(&kept);
    assert_eq!(get(&s, "tuned_aside"), "false");
    assert!(
        get(&s, "parameters").contains("PatternGenerator_sinusoidal:Amplitude=20,20,20,20,20;")
    );
}

#[test]
fn a_bad_script_line_is_reported_with_file_and_line() {
    let dir = scratch("bad");
    let script = dir.join("bad.script");
    std::fs::write(&script, "wait 1\nset NoSuchModule Amplitude 3\nquit\n").expect("script");
    let (ok, out) = run_window("configs/demo.simulation.xml", &script);
    assert!(!ok, "a bad command must fail the window:\n{out}");
    assert!(
        out.contains("bad.script:2") && out.contains("NoSuchModule"),
        "{out}"
    );
}

#[test]
fn data_inspection_loads_a_recorded_file_and_graphs_it() {
    let dir = scratch("inspect");
    let data = dir.join("run.data.xml");
    let run = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args([
            "run",
            "configs/demo.simulation.xml",
            "--duration",
            "2",
            "--data",
        ])
        .arg(&data)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("proleg run");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (st, script) = (dir.join("state.txt"), dir.join("inspect.script"));
    std::fs::write(
        &script,
        format!(
            "wait 1\ninspect {d} Robot_Data/y_pos\ninspect {d} Robot_Data/real_joint_positions[0..2]\nstate {}\nquit\n",
            st.display(),
            d = data.display()
        ),
    )
    .expect("script");
    let (ok, out) = run_window("configs/demo.simulation.xml", &script);
    assert!(ok, "{out}");
    assert_eq!(get(&state(&st), "inspect_graphs"), "2");
    // A series the file does not have is an error naming the script line.
    std::fs::write(
        &script,
        format!(
            "inspect {} Robot_Data/no_such_series\nquit\n",
            data.display()
        ),
    )
    .expect("script");
    let (ok, out) = run_window("configs/demo.simulation.xml", &script);
    assert!(
        !ok && out.contains("inspect.script:1") && out.contains("no_such_series"),
        "{out}"
    );
}

/// Runs `commands` in the window on `config`, then writes the state and quits; returns it.
fn scripted_state(name: &str, config: &str, commands: &str) -> Vec<(String, String)> {
    let dir = scratch(name);
    let (st, script) = (dir.join("state.txt"), dir.join(format!("{name}.script")));
    let text = format!("{commands}state {}\nquit\n", st.display());
    std::fs::write(&script, text).expect("script");
    let (ok, out) = run_window(config, &script);
    assert!(ok, "the window failed:\n{out}");
    state(&st)
}

#[test]
fn optimization_view_runs_a_curriculum_stage_by_stage_and_shows_the_last_stages_best() {
    let dir = scratch("optimize_curriculum");
    let store = dir.join("c.sqlite");
    let s = scripted_state(
        "optimize_curriculum",
        "configs/suite_curriculum.simulation.xml",
        &format!("wait 1\noptimize 12 {}\n", store.display()),
    );
    assert_eq!(get(&s, "optimizer_evaluations"), "12");
    let status = get(&s, "optimizer_status");
    let best: f64 = get(&s, "optimizer_best").parse().expect("a best score");
    // The best shown is the last stage's, on its own courses, not an easier stage's.
    assert!(
        status.starts_with("finished: curriculum stages 1-")
            && status.contains(&format!("best {best:.4} m; stored as runs 1-")),
        "{status}"
    );
    let (ok, out, err) = common::proleg(&["results", store.to_str().unwrap()]);
    assert!(
        ok && out.contains("curriculum stage 1 of 3 (steps-easy)"),
        "{out}{err}"
    );
}

#[test]
fn optimization_view_runs_the_ga_and_replays_the_best() {
    let dir = scratch("optimize_files");
    let (store, best) = (dir.join("ga.sqlite"), dir.join("best.actuation.xml"));
    let s = scripted_state(
        "optimize",
        "configs/experiment1_ga.simulation.xml",
        &format!(
            "wait 1\noptimize 5 {}\nsave-best {}\nstate {}\nreplay-best\nwait 2\n",
            store.display(),
            best.display(),
            dir.join("before_replay.txt").display()
        ),
    );
    // The GA evaluates whole generations: at least the 5 asked for.
    let n: u64 = get(&s, "optimizer_evaluations").parse().expect("count");
    assert!(n >= 5, "{n} evaluations");
    let score: f64 = get(&s, "optimizer_best").parse().expect("a best score");
    assert!(score > 1.0, "best {score} m");
    // One clean status line: the run's end, its best with the unit, where it is stored.
    let status = get(&s, "optimizer_status");
    assert!(
        status.starts_with(&format!("finished: {n} evaluations in "))
            && status.contains(&format!("best {score:.4} m; stored as run 1 in "))
            && status.ends_with("ga.sqlite"),
        "{status}"
    );
    // Docked on the left below the toolbar, not floating over it.
    let panel: Vec<f64> = get(&s, "optimizer_panel")
        .split(' ')
        .map(|v| v.parse().expect("rect"))
        .collect();
    assert!(panel[0] <= 1.0 && panel[1] > 60.0, "{panel:?}");
    // The run is in the store `proleg results` reads, and Save best wrote an actuation
    // file `proleg check` accepts in the simulation.
    assert_eq!(get(&s, "stored_runs"), "1");
    let (ok, out, err) = common::proleg(&["results", store.to_str().unwrap()]);
    assert!(ok && out.contains("experiment1_ga"), "{out}{err}");
    let text = std::fs::read_to_string(&best).expect("best actuation written");
    proleg::config::actuation::parse_actuation_file(&best.display().to_string(), &text)
        .expect("a valid actuation file");
    // The replay built the world anew and runs it.
    let before = state(&dir.join("before_replay.txt"));
    let generation = |s: &[(String, String)]| -> u64 { get(s, "generation").parse().expect("n") };
    assert!(
        generation(&s) > generation(&before),
        "the replay rebuilt the world: generation {} -> {}",
        generation(&before),
        generation(&s)
    );
    assert_eq!(get(&s, "running"), "true");
}

#[test]
fn a_stored_evaluation_replays_in_the_window_to_its_stored_score() {
    let dir = scratch("replay_window");
    let store = dir.join("r.sqlite");
    let (ok, _, err) = common::proleg(&[
        "optimize",
        "configs/gait_from_scratch_cmaes.simulation.xml",
        "--max-evals",
        "8",
        "--duration",
        "3",
        "--quiet",
        "--evaluations",
        dir.join("evals.tsv").to_str().unwrap(),
        "--store",
        store.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let table = std::fs::read_to_string(dir.join("evals.tsv")).expect("table");
    let stored: f64 = table
        .lines()
        .find(|l| l.starts_with("5\t"))
        .and_then(|l| l.split('\t').nth(2))
        .and_then(|v| v.parse().ok())
        .expect("evaluation 5's score");
    let (st, script) = (dir.join("state.txt"), dir.join("replay.script"));
    let text = format!("wait 1\nstep-to 3\nstate {}\nquit\n", st.display());
    std::fs::write(&script, text).expect("script");
    let args = [
        "gui",
        "--replay",
        store.to_str().unwrap(),
        "--run",
        "1",
        "--eval",
        "5",
    ];
    let (ok, out) = common::window::run(&args, &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert_eq!(get(&s, "sim_time"), "3.000000");
    let replayed: f64 = get(&s, "replay_score").parse().expect("a score");
    assert!(
        (replayed - stored).abs() < 1e-8,
        "replayed {replayed}, stored {stored}"
    );
}

#[test]
fn optimization_view_attaches_to_a_shared_run_and_draws_its_curve() {
    let pg = common::pg::server();
    let url = pg.database("gui_attach");
    let mut driver = common::pg::spawn(pg.proleg(&[
        "optimize",
        "configs/experiment1_ga.simulation.xml",
        "--max-evals",
        "60",
        "--duration",
        "2",
        "--workers",
        "1",
        "--quiet",
        "--store",
        &url,
    ]));
    pg.wait_until(
        "gui_attach",
        "SELECT to_regclass('evaluations') IS NOT NULL",
        &mut driver,
    );
    let dir = scratch("attach");
    let (st, script) = (dir.join("state.txt"), dir.join("attach.script"));
    let text = format!(
        "wait 1\nattach {url} 30\nscreenshot {}\nstate {}\nquit\n",
        dir.join("attached.png").display(),
        st.display()
    );
    std::fs::write(&script, text).expect("script");
    let (ok, out) = common::window::run_env(
        &["gui", "configs/experiment1_ga.simulation.xml"],
        &script,
        &[("PGPASSWORD", pg.password.as_str())],
    );
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    let n: u64 = get(&s, "optimizer_evaluations").parse().expect("count");
    assert!(n >= 30, "{n} evaluations drawn");
    let best: f64 = get(&s, "optimizer_best").parse().expect("a best score");
    let driver = driver.wait_with_output().expect("driver");
    assert!(driver.status.success());
    // The view's best is the run's best over the evaluations it drew.
    let stored: f64 = pg
        .connect("gui_attach")
        .query_one(
            "SELECT MAX(score) FROM evaluations WHERE number < $1",
            &[&(n as i64)],
        )
        .expect("the run's evaluations")
        .get(0);
    assert!((best - stored).abs() < 1e-6, "view {best}, store {stored}");
    assert!(
        get(&s, "optimizer_followed").ends_with("experiment1_ga.simulation.xml this"),
        "{s:?}"
    );
    // A window of another configuration (4 genes, not the run's 5) follows the same run
    // but does not read its candidate as its own values.
    let (ok, out) = common::window::run_env(
        &["gui", "configs/gait_from_scratch_cmaes.simulation.xml"],
        &script,
        &[("PGPASSWORD", pg.password.as_str())],
    );
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert!(
        get(&s, "optimizer_followed").ends_with("experiment1_ga.simulation.xml other"),
        "{s:?}"
    );
}

#[test]
fn a_selected_robot_moves_with_the_drag_path_and_the_debug_view_draws() {
    let s = scripted_state(
        "pick",
        "configs/demo.simulation.xml",
        "wait 2\nselect-link 0\nmove-by 0.5 -0.25 0\nwait 1\ndebug on\nstart\nrun-until 0.5\npause\n",
    );
    assert_eq!(get(&s, "selected"), "true");
    assert_eq!(get(&s, "debug_view"), "true");
    // The whole robot moved (all links with the one selected) and kept crawling from there.
    let com: Vec<f64> = get(&s, "com")
        .split(' ')
        .map(|v| v.parse().expect("com"))
        .collect();
    assert!((com[0] - 0.5).abs() < 0.05, "centre of mass {com:?}");
    assert!(
        (com[1] - (0.144 - 0.25)).abs() < 0.1,
        "centre of mass {com:?}"
    );
    assert!(com[2] > 0.0 && com[2] < 0.1, "centre of mass {com:?}");
}

#[test]
fn remote_dialog_steers_the_robot_and_saves_bindings() {
    let dir = scratch("remote");
    let saved = dir.join("mine.remote.xml");
    let shot = dir.join("remote.png");
    let commands = format!(
        "wait 2\nremote open\nspeed 0\nstart\nremote-set LeftStickX 1\nrun-until 6\npause\n\
         remote-bind RightStickX rate PatternGenerator_sinusoidal Phase_Difference all 20\n\
         remote-save {}\nwait 2\nscreenshot {}\n",
        saved.display(),
        shot.display()
    );
    let s = scripted_state(
        "remote",
        "configs/snake8py_remote.simulation.xml",
        &commands,
    );
    assert_eq!(get(&s, "remote_open"), "true");
    assert_eq!(get(&s, "remote_error"), "");
    // The stick bent the yaw joints (through the same API as the properties dialog)...
    let params = get(&s, "parameters");
    assert!(
        params.contains("PatternGenerator_sinusoidal:Offset=0,-20,0,-20,0,-20,0;"),
        "{params}"
    );
    // ...and the robot turned right (heading falls from 90 deg).
    let heading: f64 = get(&s, "heading").parse().expect("heading");
    assert!(
        heading < 60.0,
        "heading after 6 s steering right: {heading}"
    );
    assert_eq!(get(&s, "remote_bindings"), "8");
    let text = std::fs::read_to_string(&saved).expect("bindings saved");
    let file = proleg::config::remote::parse_remote_file("mine.remote.xml", &text).expect("valid");
    assert_eq!(file.bindings[7].element, "RightStickX");
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50);
}

/// The step function a user writes in the module editor (a travelling sine).
const GUI_WAVE: &str = r#"//! GuiWave: written in the module editor.
use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module, helpers};

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;

#[derive(Clone)]
struct GuiWave {
    theta: f64,
}

impl Module for GuiWave {
    const NAME: &'static str = "GuiWave";
    const PARAMETERS: &'static [Param] = &[
        Param::new("Amplitude", 40.0, 0.0, 90.0),
        Param::new("Frequency", 1.0, 0.0, 5.0),
    ];
    const SERIES: &'static [&'static str] = &["Phase"];

    fn new(_joints: usize) -> Self {
        GuiWave { theta: 0.0 }
    }

    fn reset(&mut self, _seed: u64) {
        self.theta = 0.0;
    }

    fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {
        for (j, angle) in out.iter_mut().enumerate() {
            let phase = self.theta - (55.0f64).to_radians() * j as f64;
            *angle = p.get(AMPLITUDE, j) * phase.sin();
            data.set(0, j, phase);
        }
        self.theta = helpers::wrap_tau(
            self.theta + std::f64::consts::TAU * p.get(FREQUENCY, 0) * ctx.dt,
        );
    }
}

export_module!(GuiWave);
"#;

#[test]
fn module_library_declares_compiles_and_assigns_a_new_module() {
    let dir = scratch("modules-files");
    // A plugin workspace of its own: the API crate and the workspace manifest.
    let ws = dir.join("plugins");
    common::plugin_workspace(&ws);
    let (bad, good) = (dir.join("bad.rs"), dir.join("good.rs"));
    std::fs::write(&bad, GUI_WAVE.replace("*angle = p.get", "*angle = q.get")).expect("bad");
    std::fs::write(&good, GUI_WAVE).expect("good");
    let (first, shot) = (dir.join("first.txt"), dir.join("modules.png"));
    let commands = format!(
        "wait 2\nmodules open\nmodule-workspace {ws}\n\
         module-declare GuiWave Amplitude=40:0..90 Frequency=1:0..5 data=Phase helpers=smooth\n\
         module-source {bad}\nmodule-compile\nstate {first}\n\
         module-source {good}\nmodule-compile\nwait 3\nscreenshot {shot}\n\
         assign GuiWave 11111\nset PatternGenerator_sinusoidal Amplitude 0\n\
         speed 0\nrun-until 4\npause\n",
        ws = ws.display(),
        bad = bad.display(),
        good = good.display(),
        first = first.display(),
        shot = shot.display(),
    );
    let s = scripted_state("modules", "configs/demo.simulation.xml", &commands);
    // The declaration made a crate; the broken source failed with the compiler's errors.
    let f = state(&first);
    assert_eq!(get(&f, "module_crate"), "gui_wave");
    assert!(
        get(&f, "module_status").starts_with("error: the build failed"),
        "{f:?}"
    );
    let errors: usize = get(&f, "module_log_errors").parse().expect("count");
    assert!(errors >= 1, "{f:?}");
    // The fixed source compiled and loaded; assigned to the joints it drives the robot
    // (the built-in sine at amplitude 0), without restarting proleg.
    assert_eq!(get(&s, "module_builds"), "2");
    assert_eq!(get(&s, "module_loaded"), "GuiWave");
    assert!(
        get(&s, "module_status").starts_with("info: compiled"),
        "{s:?}"
    );
    let params = get(&s, "parameters");
    assert!(
        params.contains("1:GuiWave:Amplitude=40,40,40,40,40;"),
        "{params}"
    );
    assert!(
        params.contains("0:PatternGenerator_sinusoidal:Amplitude=0,0,0,0,0;"),
        "{params}"
    );
    assert_eq!(get(&s, "module_failures"), "");
    let com: Vec<f64> = get(&s, "com")
        .split(' ')
        .map(|v| v.parse().expect("number"))
        .collect();
    assert!(com[1] > 0.25, "the robot's centre after 4 s: {com:?}");
    assert!(ws.join("lib/libgui_wave.so").is_file());
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50);
}

#[test]
fn real_robot_tab_drives_the_emulated_servos_and_shows_the_twin() {
    let bus = proleg::robot_io::emulator::EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0)
        .expect("emulated bus");
    let shot = scratch("robot-files").join("robot.png");
    let commands = format!(
        "wait 2\nrobot open\nrobot-connect {}\nrobot-torque on\nrobot-drive on\n\
         speed 1\nstart\nrun-until 2\npause\nwait 2\nscreenshot {}\n",
        bus.path().display(),
        shot.display()
    );
    let s = scripted_state("robot", "configs/snake5p_real.simulation.xml", &commands);
    assert_eq!(get(&s, "robot_connected"), "true", "{s:?}");
    assert_eq!(get(&s, "robot_torque"), "true");
    assert_eq!(get(&s, "robot_error"), "");
    let reads: u64 = get(&s, "robot_reads").parse().expect("reads");
    let writes: u64 = get(&s, "robot_writes").parse().expect("writes");
    assert!(reads >= 3 && writes >= 2, "{reads} reads, {writes} writes");
    // The kernel's angles reached the servos, which moved; the tab saw them move.
    let servos = bus.servos();
    assert!(servos.iter().all(|s| s.goals_written >= 2));
    assert!(
        servos.iter().any(|s| (s.present() - 2048.0).abs() > 20.0),
        "{:?}",
        servos.iter().map(|s| s.present()).collect::<Vec<_>>()
    );
    let measured: Vec<f64> = get(&s, "robot_positions")
        .split(' ')
        .map(|v| v.parse().expect("angle"))
        .collect();
    assert!(measured.iter().any(|a| a.abs() > 2.0), "{measured:?}");
    // Closing the window switched the torque off.
    assert!(
        bus.servos().iter().all(|s| !s.torque()),
        "torque left on after the window closed"
    );
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50);
}

#[test]
fn the_physics_choice_rebuilds_the_world_on_mujoco_and_it_crawls() {
    if !common::mujoco_here("the window on MuJoCo") {
        return;
    }
    let dir = scratch("control_mujoco");
    let st = dir.join("state.txt");
    let script = dir.join("mujoco.script");
    std::fs::write(
        &script,
        format!(
            "wait 2\nengine mujoco\nstart\nrun-until 2.0\npause\nstate {}\nquit\n",
            st.display()
        ),
    )
    .expect("script");
    let (ok, out) = run_window("configs/demo.simulation.xml", &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert_eq!(get(&s, "engine"), "mujoco");
    let t: f64 = get(&s, "sim_time").parse().expect("time");
    assert!((2.0..2.5).contains(&t), "paused at {t} s");
    let com: Vec<f64> = get(&s, "com")
        .split(' ')
        .map(|v| v.parse().expect("com"))
        .collect();
    assert!(
        com[1] > 0.2,
        "centre of mass {com:?}: the snake crawls on MuJoCo"
    );
}

#[test]
fn real_robot_tab_calibrates_the_servos_on_a_recording() {
    // A 4-s recording of the calibration sweep on emulated servos with hidden dynamics.
    let dir = scratch("robot-calibrate");
    let config = "configs/calibration_sweep.simulation.xml";
    let sim = proleg::control::load_simulation(common::root().join(config)).expect("sweep");
    let dynamics = common::HIDDEN_SERVOS;
    let bus = proleg::robot_io::emulator::EmulatedBus::start_with(&[1, 2, 3, 4, 5], dynamics)
        .expect("emulated bus");
    let mut chain = proleg::robot_io::dynamixel::DynamixelChain::new(
        bus.path(),
        None,
        sim.robot.servos.clone(),
        &sim.robot.pattern(),
    );
    let data = dir.join("sweep.data.xml");
    let options = proleg::robot_io::real_mode::RealOptions {
        duration: Some(4.0),
        read_every: Some(10),
        every: Some(10),
        seed: 1,
    };
    let stop = std::sync::atomic::AtomicBool::new(false);
    let registry = proleg::control::ModuleRegistry::standard();
    proleg::robot_io::real_mode::run(&sim, &registry, &mut chain, &options, Some(&data), &stop)
        .expect("recorded");
    // The tab calibrates it and shows the fit and the before/after plot.
    let shot = dir.join("calibration.png");
    let commands = format!(
        "wait 2\nrobot-calibrate {}\nwait-for calibrated 3000\nwait 3\nscreenshot {}\n",
        data.display(),
        shot.display()
    );
    let s = scripted_state("calibrate", config, &commands);
    assert_eq!(get(&s, "calibration_error"), "", "{s:?}");
    let rms: Vec<f64> = get(&s, "calibration_rms")
        .split(' ')
        .map(|v| v.parse().expect("rms"))
        .collect();
    assert!(rms[1] * 3.0 < rms[0], "RMS before and after: {rms:?}");
    let (w, h, colours) = png_colours(&shot);
    assert_eq!((w, h), (1280, 800));
    assert!(colours > 50);
}
