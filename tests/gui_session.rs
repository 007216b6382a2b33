//! The control window's runs as a user sees them: the speed
//! readouts are what the wall clock says even when frames are slow, and a run ends — at
//! its duration, or when the robot falls off the world — with a message instead of running
//! on forever. Under Xvfb with Mesa's software renderer, driven by scripts.
#![cfg(feature = "gui")]

mod common;

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use common::window::{get, scratch, state};

fn num(s: &[(String, String)], key: &str) -> f64 {
    get(s, key).parse().unwrap_or_else(|e| panic!("{key}: {e}"))
}

/// When `path` was last written (the kernel's wall clock, not the window's).
fn written(path: &Path) -> SystemTime {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .expect("state file written")
}

/// A copy of the demo simulation in `dir` with `duration` and, when given, the environment
/// file `env`; the other files are the repository's.
fn demo_variant(dir: &Path, duration: f64, env: Option<&Path>) -> PathBuf {
    let configs = common::root().join("configs");
    let env = env.map_or_else(
        || configs.join("environments/flat.env.xml"),
        Path::to_path_buf,
    );
    common::simulation_file(
        &dir.join("variant.simulation.xml"),
        [
            &configs.join("robots/snake5p.robot.xml"),
            &configs.join("actuation/snake5p_sine40.actuation.xml"),
            &env,
        ],
        duration,
    )
}

#[test]
fn readouts_match_the_wall_clock_when_frames_are_slow() {
    let dir = scratch("readouts");
    let script = dir.join("slow.script");
    // Every frame 350 ms longer than it takes: a window drawing about 1-2 frames a second,
    // asked to run at real time. Then a state file at each of the last frames: their
    // modification times are the wall clock of those frames.
    const FRAMES: usize = 7;
    let frame = |k: usize| dir.join(format!("f{k}.txt"));
    let mut text = String::from("slow-frames 350\nspeed 1\nstart\nwait 4\n");
    for k in 0..FRAMES {
        text.push_str(&format!("state {}\nwait 0\n", frame(k).display()));
    }
    text.push_str("quit\n");
    std::fs::write(&script, text).expect("script");
    let (ok, out) = common::window::run(&["gui", "configs/demo.simulation.xml"], &script);
    assert!(ok, "the window failed:\n{out}");
    let states: Vec<_> = (0..FRAMES).map(|k| state(&frame(k))).collect();
    let t: Vec<f64> = (0..FRAMES)
        .map(|k| {
            written(&frame(k))
                .duration_since(SystemTime::UNIX_EPOCH)
                .expect("a modification time")
                .as_secs_f64()
        })
        .collect();
    // The last state shows the readouts of the frames before it (the script runs before
    // the frame's simulation): over the last wall second of them, plus the frame before.
    let last = FRAMES - 2;
    let first = (0..=last)
        .find(|&k| t[k] >= t[last] - 1.0)
        .map_or(0, |k| k.saturating_sub(1));
    assert!(first < last, "the frames {t:?} span less than a second");
    let wall = t[last] - t[first];
    let fps = (last - first) as f64 / wall;
    let sim = |k: usize| num(&states[k + 1], "sim_time");
    let factor = (sim(last) - sim(first)) / wall;
    let shown = &states[FRAMES - 1];
    let close = |shown: f64, measured: f64| (shown / measured - 1.0).abs() < 0.1;
    assert!(
        close(num(shown, "fps"), fps),
        "window says {} fps, the clock {fps:.3} (frames at {t:?})",
        num(shown, "fps")
    );
    assert!(
        close(num(shown, "factor"), factor),
        "window says {}x, the clock {factor:.3}x",
        num(shown, "factor")
    );
    // Real time over all the frames written. Each state shows the readouts up to the frame
    // before it, so the two spans may differ by one frame: a frame that stalls (a shader
    // compiled, a loaded machine) at either end counts in one and not the other.
    let span = t[FRAMES - 1] - t[0];
    let real = num(shown, "real_time") - num(&states[0], "real_time");
    let longest_frame = t.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    assert!(
        (real - span).abs() <= 0.1 * span + longest_frame,
        "real time advanced {real} s in {span} s (longest frame {longest_frame:.3} s)"
    );
    // The machine keeps real time at these frame rates: slow frames do not slow the
    // simulation (each frame catches up on the wall time it took).
    let overall = (num(shown, "sim_time") - num(&states[0], "sim_time")) / span;
    assert!(overall > 0.9, "simulated at {overall}x of 1x requested");
    assert!(
        get(shown, "speed_readout").starts_with(&format!("{:.2}x", num(shown, "factor"))),
        "{}",
        get(shown, "speed_readout")
    );
}

#[test]
fn a_run_pauses_at_its_duration_and_continues_past_it() {
    let dir = scratch("duration");
    let config = demo_variant(&dir, 1.5, None);
    let (at_end, after) = (dir.join("end.txt"), dir.join("after.txt"));
    let script = dir.join("duration.script");
    std::fs::write(
        &script,
        format!(
            "speed 0\nstart\nwait-for paused 3000\nwait 3\nstate {}\ncontinue\nwait-for running 10\nwait 5\npause\nstate {}\nquit\n",
            at_end.display(),
            after.display()
        ),
    )
    .expect("script");
    let config = config.display().to_string();
    let (ok, out) = common::window::run(&["gui", &config], &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&at_end);
    assert_eq!(get(&s, "running"), "false");
    assert_eq!(
        num(&s, "sim_time"),
        1.5,
        "stopped at the duration, to the step"
    );
    assert!(
        get(&s, "halt").contains("duration, 1.5 s"),
        "{}",
        get(&s, "halt")
    );
    let s = state(&after);
    assert!(num(&s, "sim_time") > 1.5, "Continue ran past the duration");
    assert_eq!(get(&s, "halt"), "");
}

#[test]
fn a_robot_that_falls_off_the_world_pauses_the_run() {
    let dir = scratch("fall");
    // A floor the size of a coin under the snake's middle: it topples off at once.
    let env = dir.join("coin.env.xml");
    std::fs::write(
        &env,
        r#"<Environment>
  <KinBody name="coin">
    <Body type="static">
      <Translation>0 0 -0.003</Translation>
      <Geom type="box"><extents>0.02 0.02 0.003</extents></Geom>
    </Body>
  </KinBody>
</Environment>
"#,
    )
    .expect("environment");
    let config = demo_variant(&dir, 30.0, Some(&env));
    let st = dir.join("state.txt");
    let script = dir.join("fall.script");
    std::fs::write(
        &script,
        format!(
            "speed 0\nstart\nwait-for paused 3000\nstate {}\nquit\n",
            st.display()
        ),
    )
    .expect("script");
    let config = config.display().to_string();
    let (ok, out) = common::window::run(&["gui", &config], &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert!(
        get(&s, "halt").contains("left the world"),
        "{}",
        get(&s, "halt")
    );
    let z: f64 = get(&s, "com")
        .split(' ')
        .nth(2)
        .and_then(|v| v.parse().ok())
        .expect("com z");
    // Below the coin by the margin, and caught long before the duration.
    assert!((-3.0..-1.0).contains(&z), "centre of mass at z {z}");
    assert!(num(&s, "sim_time") < 2.0, "{}", num(&s, "sim_time"));
}

#[test]
fn a_policy_s_weights_file_loads_into_the_running_window_and_drives_the_robot() {
    // The demo's sine with a Policy module (output 0 from its start file); the window's
    // `weights` command (the assignment form's Load) gives it a network that bends the
    // joints, and the robot goes elsewhere; a file that is no network is an error naming
    // it (in the form; a script stops there).
    use proleg::control::policy::{Activation, Layer, PolicyNet};
    let dir = scratch("policy_weights");
    let configs = common::root().join("configs");
    let config = dir.join("policy.simulation.xml");
    std::fs::write(
        &config,
        std::fs::read_to_string(configs.join("demo_policy_es.simulation.xml"))
            .expect("demo policy")
            .replace(
                "robots/snake5p.robot.xml",
                &configs
                    .join("robots/snake5p.robot.xml")
                    .display()
                    .to_string(),
            )
            .replace(
                "actuation/snake5p_sine40_policy.actuation.xml",
                &configs
                    .join("actuation/snake5p_sine40_policy.actuation.xml")
                    .display()
                    .to_string(),
            )
            .replace(
                "environments/flat.env.xml",
                &configs
                    .join("environments/flat.env.xml")
                    .display()
                    .to_string(),
            )
            .replace("<optimizer>optimizer/demo_policy.es.xml</optimizer>", "")
            .replace("Evolution strategy optimization", "Single Run Simulation"),
    )
    .expect("simulation");
    let bent = dir.join("bent.safetensors");
    let inputs = 18;
    PolicyNet::new(
        vec![Layer {
            weight: vec![0.0; 5 * inputs],
            bias: vec![0.8, -0.8, 0.8, -0.8, 0.8],
        }],
        Activation::Tanh,
    )
    .expect("net")
    .write(&bent)
    .expect("weights");
    let junk = dir.join("junk.safetensors");
    std::fs::write(&junk, "no tensors").expect("junk");
    let (plain, loaded) = (dir.join("plain.txt"), dir.join("loaded.txt"));
    let script = dir.join("weights.script");
    std::fs::write(
        &script,
        format!(
            "speed 0\nstep-to 1\nstate {}\nweights 1 {}\nstep-to 1\nstate {}\nweights 1 {}\nquit\n",
            plain.display(),
            bent.display(),
            loaded.display(),
            junk.display(),
        ),
    )
    .expect("script");
    let config = config.display().to_string();
    let (ok, out) = common::window::run(&["gui", &config], &script);
    assert!(!ok, "the junk file stops the script:\n{out}");
    let (a, b) = (state(&plain), state(&loaded));
    assert_eq!(num(&a, "sim_time"), 1.0);
    assert_eq!(num(&b, "sim_time"), 1.0);
    assert_ne!(
        get(&a, "com"),
        get(&b, "com"),
        "the network moved the robot"
    );
    assert_eq!(get(&b, "module_failures"), "");
    assert!(
        out.contains("junk.safetensors"),
        "the refusal names the file:\n{out}"
    );
}
