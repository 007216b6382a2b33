//! The 3D replay's pose stream against the simulation: every moving body's pose in every
//! frame is the simulated one (quantized within a micrometre and a hundredth of a degree),
//! `proleg run --html` writes a page whose stream agrees with the same run's data file
//! (head orientation, joint angles), a label with markup stays inside a JSON string, and
//! two engines go side by side on one page.

mod common;

use proleg::cli::run::{RunRequest, run};
use proleg::config::simulation::EngineKind;
use proleg::control::{ModuleRegistry, load_simulation};
use proleg::data::read::{DataEvent, read_file};
use proleg::playback::encode::{self, QUATERNION_SCALE};
use proleg::playback::{Recording, record_episode};
use proleg::sim::{BuildOptions, Episode, EpisodeSettings, Simulator};

fn demo() -> std::path::PathBuf {
    common::root().join("configs/demo.simulation.xml")
}

/// The angle (degrees) between two rotations given as x, y, z, w.
fn angle_between(a: [f64; 4], b: [f64; 4]) -> f64 {
    let n = |q: [f64; 4]| q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let dot: f64 = (0..4).map(|i| a[i] * b[i]).sum::<f64>() / (n(a) * n(b));
    2.0 * dot.abs().clamp(0.0, 1.0).acos().to_degrees()
}

#[test]
fn every_frame_holds_each_bodys_simulated_pose() {
    let sim = load_simulation(demo()).unwrap();
    let opts = BuildOptions {
        robots: 1,
        seed: 7,
        ..Default::default()
    };
    let registry = ModuleRegistry::standard();
    let mut recorded = Simulator::with_registry(&sim, &opts, &registry).unwrap();
    let settings = EpisodeSettings::new(
        &recorded,
        2.0,
        proleg::config::fitness::Fitness::Displacement,
    );
    let total = settings.steps.unwrap();
    let mut episode = Episode::begin(&recorded, settings).unwrap();
    let recording = Recording {
        fps: 30.0,
        label: "demo".into(),
    };
    let out = record_episode(&sim, &mut recorded, &mut episode, &recording, None).unwrap();
    let stream = out.stream;
    let dt = recorded.clock().dt;
    let every = (stream.frame_seconds / dt).round() as u64;
    assert!(every >= 1 && (every as f64 * dt - stream.frame_seconds).abs() < 1e-12);
    assert_eq!(stream.frames as u64, total.div_ceil(every) + 1);

    // The same world run again, read between the same steps.
    let mut again = Simulator::with_registry(&sim, &opts, &registry).unwrap();
    let bodies = again.robot_bodies(0).unwrap();
    let moving = stream.scene.bodies.iter().filter(|b| b.moves).count();
    assert_eq!(moving, bodies.len(), "the demo has no dynamic objects");
    let mut worst = (0.0f64, 0.0f64);
    for frame in 0..stream.frames {
        if frame > 0 {
            let left = total - again.clock().step;
            again.run_steps(every.min(left));
        }
        for (k, b) in bodies.iter().enumerate() {
            let truth = again.body_state(*b).unwrap().pose;
            let (p, q) = stream.pose_at(frame, k).unwrap();
            let d = (0..3)
                .map(|i| (p[i] - truth.translation[i]).powi(2))
                .sum::<f64>()
                .sqrt();
            let [w, x, y, z] = truth.rotation;
            let a = angle_between(q, [x, y, z, w]);
            worst = (worst.0.max(d), worst.1.max(a));
        }
    }
    assert!(worst.0 < 1e-5, "position off by {} m", worst.0);
    assert!(worst.1 < 0.01, "rotation off by {}°", worst.1);
    // The robot moved: the replay is not of a still world.
    let (first, _) = stream.pose_at(0, 0).unwrap();
    let (last, _) = stream.pose_at(stream.frames - 1, 0).unwrap();
    assert!((last[0] - first[0]).abs() + (last[1] - first[1]).abs() > 0.01);
}

fn array<const N: usize, T>(v: &serde_json::Value, key: &str, from: fn([u8; N]) -> T) -> Vec<T> {
    encode::decode(v[key].as_str().expect(key), from).expect(key)
}

/// Roll, pitch, yaw (degrees) as the data file's robot series has them.
fn euler([x, y, z, w]: [f64; 4]) -> [f64; 3] {
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    [roll, pitch, yaw].map(f64::to_degrees)
}

#[test]
fn the_run_page_agrees_with_the_runs_data_file() {
    let dir = common::scratch("playback_run_page");
    let (page, data) = (dir.join("run.html"), dir.join("run.data.xml"));
    let sim = load_simulation(demo()).unwrap();
    let dt = sim.files.simulation.properties.step_width;
    let every = (1.0 / (30.0 * dt)).round() as u32;
    let req = RunRequest {
        duration: Some(3.0),
        html: Some(page.clone()),
        data: Some(data.clone()),
        every: Some(every),
        ..RunRequest::of(demo())
    };
    let report = run(&req, &ModuleRegistry::standard()).unwrap();
    let html = report.html.as_ref().expect("a page");
    let text = std::fs::read_to_string(&page).unwrap();
    assert_eq!(html.bytes, text.len() as u64);
    let streams = common::page_streams(&text);
    assert_eq!(streams.len(), 1);
    let s = &streams[0];
    assert_eq!(s["format"], "proleg-replay 1");
    let frames = s["frames"].as_u64().unwrap() as usize;
    assert_eq!(html.frames, vec![frames]);
    let joints = s["scene"]["joints"].as_array().unwrap().len();
    let moving = common::moving_bodies(s);
    let angles = array(s, "angles", i16::from_le_bytes);
    let rotations = array(s, "rotations", i16::from_le_bytes);
    let score = array(s, "score", f32::from_le_bytes);
    assert_eq!(angles.len(), frames * joints);
    // The last score is the run's displacement.
    let last = f64::from(*score.last().unwrap());
    assert!(
        (last - report.summary.displacement).abs() < 1e-5,
        "{last} vs {}",
        report.summary.displacement
    );

    // Data sample n is taken after (n + 1) * every steps: the stream's frame n + 1.
    let mut robot = None;
    let mut checked = 0;
    read_file(&data, |e| match e {
        DataEvent::Header(h) => robot = h.iter().position(|h| h.name == "Robot_Data"),
        DataEvent::Frame(f) if Some(f.handler) == robot => {
            let frame = f.meta.index as usize + 1;
            if frame >= frames {
                return;
            }
            let head = (frame * moving + moving - 1) * 4;
            let q: [f64; 4] =
                std::array::from_fn(|i| f64::from(rotations[head + i]) / QUATERNION_SCALE);
            let e = euler(q);
            for (i, name) in [(4, "alpha"), (5, "beta"), (6, "gamma")] {
                let d = (e[i - 4] - f.values[i] + 540.0).rem_euclid(360.0) - 180.0;
                assert!(
                    d.abs() < 0.1,
                    "frame {frame} {name}: {} vs {}",
                    e[i - 4],
                    f.values[i]
                );
            }
            // The per-joint series: desired, then real angles.
            for j in 0..joints {
                let real = f.values[11 + joints + j];
                let got = f64::from(angles[frame * joints + j]) / 100.0;
                assert!(
                    (got - real).abs() <= 0.006,
                    "frame {frame} joint {j}: {got} vs {real}"
                );
            }
            checked += 1;
        }
        _ => {}
    })
    .unwrap();
    assert!(
        checked + 2 >= frames,
        "{checked} of {frames} frames checked"
    );
}

#[test]
fn a_label_with_markup_stays_in_a_string() {
    let dir = common::scratch("playback_markup");
    let sim = load_simulation(demo()).unwrap();
    let registry = ModuleRegistry::standard();
    let mut simulator =
        Simulator::with_registry(&sim, &BuildOptions::default(), &registry).unwrap();
    let settings = EpisodeSettings::new(
        &simulator,
        0.2,
        proleg::config::fitness::Fitness::Displacement,
    );
    let mut episode = Episode::begin(&simulator, settings).unwrap();
    let label = "</script><script>window.owned = 1</script> & <b>bold</b>";
    let recording = Recording {
        fps: 30.0,
        label: label.into(),
    };
    let out = record_episode(&sim, &mut simulator, &mut episode, &recording, None).unwrap();
    let file = dir.join("markup.html");
    proleg::playback::page::write_standalone(&file, &[&out.stream]).unwrap();
    let page = std::fs::read_to_string(&file).unwrap();
    assert!(
        !page.contains("<script>window.owned") && !page.contains("<b>bold"),
        "the label's markup is in the page as markup"
    );
    assert_eq!(common::page_streams(&page)[0]["label"], label);
}

#[test]
fn two_engines_go_side_by_side() {
    if !common::mujoco_here("two_engines_go_side_by_side") {
        return;
    }
    let dir = common::scratch("playback_engines");
    let page = dir.join("engines.html");
    let req = RunRequest {
        duration: Some(1.0),
        html: Some(page.clone()),
        engine: Some(EngineKind::Rapier),
        compare_engine: Some(EngineKind::Mujoco),
        ..RunRequest::of(demo())
    };
    let report = run(&req, &ModuleRegistry::standard()).unwrap();
    let html = report.html.unwrap();
    assert_eq!(html.frames.len(), 2);
    let streams = common::page_streams(&std::fs::read_to_string(&page).unwrap());
    assert_eq!(streams.len(), 2);
    assert!(
        streams[0]["engine"].as_str().unwrap().starts_with("rapier"),
        "{}",
        streams[0]["engine"]
    );
    assert!(
        streams[1]["engine"].as_str().unwrap().starts_with("mujoco"),
        "{}",
        streams[1]["engine"]
    );
    assert_eq!(streams[0]["frames"], streams[1]["frames"]);
    assert!(html.beside.unwrap().contains("mujoco"));
}

#[test]
fn proleg_results_writes_a_stored_evaluation_as_the_optimizer_scored_it() {
    let dir = common::scratch("playback_results");
    let store = dir.join("runs.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/experiment1_ga.simulation.xml",
        ("6", "1"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let page = dir.join("best.html");
    let options = proleg::cli::results::ResultsOptions {
        stores: vec![store.display().to_string()],
        runs: Vec::new(),
        curve: None,
        export: None,
        map: None,
        export_robot: None,
        html: Some((proleg::optimize::replay::Which::Best, page.clone())),
    };
    let report = proleg::cli::results::run(&options, &ModuleRegistry::standard()).unwrap();
    let (number, file, bytes) = report.html.clone().expect("a page");
    assert_eq!(file, page);
    let text = std::fs::read_to_string(&page).unwrap();
    assert_eq!(bytes, text.len() as u64);
    let best = report.stores[0].1[0].best_score.expect("a best score");
    let streams = common::page_streams(&text);
    let score = array(&streams[0], "score", f32::from_le_bytes);
    let last = f64::from(*score.last().unwrap());
    assert!(
        (last - best).abs() < 1e-4,
        "evaluation {number} replayed {last}, stored {best}"
    );
}

/// Every moving body's pose in `world` now (position, rotation x, y, z, w).
fn poses(world: &Simulator) -> Vec<([f64; 3], [f64; 4])> {
    let bodies = world.robot_bodies(0).unwrap();
    bodies
        .iter()
        .map(|b| {
            let pose = world.body_state(*b).unwrap().pose;
            let [w, x, y, z] = pose.rotation;
            (pose.translation, [x, y, z, w])
        })
        .collect()
}

#[test]
fn an_environments_stepped_episode_replays_as_it_was_stepped() {
    use proleg::gym::{Env, EnvOptions, GymError};
    let sim = std::sync::Arc::new(load_simulation(demo()).unwrap());
    let registry = ModuleRegistry::standard();
    let opts = EnvOptions {
        replay_fps: 25.0,
        duration: Some(1.0),
        ..Default::default()
    };
    let mut env = Env::new(sim.clone(), registry.clone(), opts.clone()).unwrap();
    assert!(matches!(env.replay(None), Err(GymError::State(_))));
    let mut obs = vec![0.0; env.layout().len()];
    env.reset(Some(3), &mut obs).unwrap();
    // What the caller saw: the world at the reset and after every second step (25 frames
    // per second at 50 steps per second).
    let mut seen = vec![poses(env.world())];
    let mut steps = 0u64;
    let running = loop {
        let action: Vec<f64> = (0..env.action_len())
            .map(|j| (0.3 * steps as f64 + j as f64).sin())
            .collect();
        let t = env.step(&action, &mut obs).unwrap();
        steps += 1;
        if steps.is_multiple_of(2) || t.truncated || t.terminated {
            seen.push(poses(env.world()));
        }
        if steps == 10 {
            let so_far = env.replay(None).unwrap();
            assert_eq!(so_far.frames, 6);
            assert!(so_far.end.contains("goes on"), "{}", so_far.end);
        }
        if t.truncated || t.terminated {
            break t;
        }
    };
    assert!(running.truncated && steps == 50);
    let stream = env.replay(Some("the <b>stepped</b> episode")).unwrap();
    assert_eq!((stream.frames, stream.frame_seconds), (seen.len(), 0.04));
    assert_eq!(stream.label, "the <b>stepped</b> episode");
    assert!(stream.end.contains("duration"), "{}", stream.end);
    let mut worst = (0.0f64, 0.0f64);
    for (frame, bodies) in seen.iter().enumerate() {
        for (k, (p0, q0)) in bodies.iter().enumerate() {
            let (p, q) = stream.pose_at(frame, k).unwrap();
            let d = (0..3).map(|i| (p[i] - p0[i]).powi(2)).sum::<f64>().sqrt();
            worst = (worst.0.max(d), worst.1.max(angle_between(q, *q0)));
        }
    }
    assert!(worst.0 < 1e-5 && worst.1 < 0.01, "off by {worst:?}");
    let (first, _) = stream.pose_at(0, 0).unwrap();
    let (last, _) = stream.pose_at(stream.frames - 1, 0).unwrap();
    assert!(
        (0..3).any(|i| (last[i] - first[i]).abs() > 1e-3),
        "the robot moved"
    );

    // The next episode is a recording of its own.
    env.reset(None, &mut obs).unwrap();
    let next = env.replay(None).unwrap();
    assert_eq!(next.frames, 1);
    assert!(next.label.contains("episode 2"), "{}", next.label);

    let quiet = Env::new(sim, registry, EnvOptions::default()).unwrap();
    assert!(
        matches!(quiet.replay(None), Err(GymError::State(m)) if m.contains("replay_fps")),
        "an environment made without replay_fps says how to get one"
    );
}
