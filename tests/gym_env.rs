//! The environments from Rust (`proleg::gym`): a vector environment gives the same arrays
//! on one, two and three threads; a residual policy with zero action runs the file's own
//! gait, its return the optimizers' score; the policy's targets reach the joints; the lanes
//! of a vector environment on a suite task draw train courses and hold each once; a
//! randomized environment's reset draws its physics as the robustness check does.

mod common;

use std::sync::Arc;

use proleg::config::fitness::Fitness;
use proleg::control::{ModuleRegistry, load_simulation};
use proleg::gym::{ActionMode, Autoreset, Env, EnvOptions, GymError, VecEnv, VecOptions};
use proleg::sim::episode::{RobotStart, robot_score};
use proleg::sim::{BuildOptions, Simulator};

fn demo() -> Arc<proleg::config::Simulation> {
    Arc::new(load_simulation(common::root().join("configs/demo.simulation.xml")).expect("demo"))
}

/// `n` demo environments with `opts` on `threads`, resetting on the next step.
fn next_step_vec(opts: &EnvOptions, n: usize, threads: usize) -> VecEnv {
    VecEnv::new(
        demo(),
        &ModuleRegistry::standard(),
        opts,
        n,
        VecOptions {
            threads,
            autoreset: Autoreset::NextStep,
        },
    )
    .expect("vector env")
}

/// Observations, rewards and flags of `steps` steps of 5 environments on `threads`.
fn run(threads: usize, steps: usize) -> (Vec<f64>, Vec<f64>) {
    let opts = EnvOptions {
        duration: Some(0.1),
        ..EnvOptions::default()
    };
    let mut v = next_step_vec(&opts, 5, threads);
    v.reset(Some(3), None).expect("reset");
    let (mut obs, mut rewards) = (v.observations().to_vec(), Vec::new());
    for k in 0..steps {
        let actions: Vec<f64> = (0..25)
            .map(|i| ((i * 7 + k * 3) % 11) as f64 / 5.0 - 1.0)
            .collect();
        v.step(&actions).expect("step");
        obs.extend_from_slice(v.observations());
        rewards.extend(v.lanes().iter().map(|l| l.reward));
    }
    (obs, rewards)
}

#[test]
fn a_vector_env_gives_the_same_arrays_on_one_two_and_three_threads() {
    let one = run(1, 12);
    assert_eq!(one, run(2, 12));
    assert_eq!(one, run(3, 12));
    assert!(one.1.iter().any(|r| *r != 0.0));
}

/// The return of a residual episode with zero action from reset `seed`, run to its
/// duration, and the centre of mass where it ended.
fn zero_residual_return(env: &mut Env, seed: u64) -> (f64, [f64; 3]) {
    let mut obs = vec![0.0; env.layout().len()];
    env.reset(Some(seed), &mut obs).expect("reset");
    let mut total = 0.0;
    loop {
        let t = env.step(&[0.0; 5], &mut obs).expect("step");
        total += t.reward;
        if t.truncated || t.terminated {
            assert!(t.truncated, "the episode ran to its duration");
            return (total, env.world().com(0).expect("com"));
        }
    }
}

#[test]
fn a_residual_with_zero_action_runs_the_files_gait_and_returns_its_score() {
    let sim = demo();
    let opts = EnvOptions {
        mode: ActionMode::Residual,
        duration: Some(1.0),
        ..EnvOptions::default()
    };
    let mut env = Env::new(sim.clone(), ModuleRegistry::standard(), opts).expect("env");
    let (total, com) = zero_residual_return(&mut env, 1);
    let mut plain = Simulator::new(&sim, &BuildOptions::default()).expect("world");
    let start = RobotStart::of(&plain, 0).expect("start");
    plain.run_steps(1000);
    assert_eq!(com, plain.com(0).expect("com"));
    let score = robot_score(&plain, 0, start, 1.0, Fitness::Distance).expect("score");
    assert!((total - score).abs() < 1e-12, "{total} against {score}");
    assert!(score > 0.03, "the demo crawls forward: {score}");
}

#[test]
fn the_policys_targets_reach_the_joints() {
    let mut env = Env::new(demo(), ModuleRegistry::standard(), EnvOptions::default()).expect("env");
    let mut obs = vec![0.0; env.layout().len()];
    env.reset(Some(1), &mut obs).expect("reset");
    for _ in 0..50 {
        env.step(&[0.5, -0.5, 0.0, 0.25, 1.5], &mut obs)
            .expect("step");
    }
    let limits = env.world().kernel(0).expect("kernel").limits().to_vec();
    let want: Vec<f64> = [0.5, -0.5, 0.0, 0.25, 1.0]
        .iter()
        .zip(&limits)
        .map(|(a, [lo, hi])| 0.5 * (lo + hi) + a * 0.5 * (hi - lo))
        .collect();
    let angles: Vec<f64> = obs[..5].iter().map(|a| a.to_degrees()).collect();
    for (a, w) in angles.iter().zip(&want) {
        assert!((a - w).abs() < 3.0, "{angles:?} against {want:?}");
    }
    assert!(matches!(
        env.step(&[f64::NAN; 5], &mut obs),
        Err(GymError::NotFinite { index: 0, .. })
    ));
    assert!(matches!(
        env.step(&[0.0; 4], &mut obs),
        Err(GymError::Shape {
            given: 4,
            want: 5,
            ..
        })
    ));
}

#[test]
fn options_are_set_by_name_with_their_defaults_documented_once() {
    use proleg::gym::OptionValue;
    let docs = proleg::gym::options::documented();
    let names: Vec<&str> = docs.iter().map(|d| d.name).collect();
    assert_eq!(
        names,
        [
            "engine",
            "control_period",
            "mode",
            "action_scale",
            "fitness",
            "energy_weight",
            "duration",
            "terrain",
            "difficulty",
            "suite",
            "split",
            "terrain_seed",
            "randomize",
            "replay_fps",
            "threads",
            "autoreset"
        ]
    );
    let default = |n: &str| docs.iter().find(|d| d.name == n).map(|d| d.default.clone());
    assert_eq!(default("control_period").as_deref(), Some("0.02"));
    assert_eq!(default("mode").as_deref(), Some("\"alone\""));
    assert_eq!(default("duration").as_deref(), Some("None"));
    assert_eq!(default("autoreset").as_deref(), Some("\"next_step\""));
    assert_eq!(default("randomize").as_deref(), Some("False"));
    assert_eq!(default("replay_fps").as_deref(), Some("0.0"));
    let (mut env, mut vec) = (EnvOptions::default(), VecOptions::default());
    vec.set(&mut env, "control_period", &OptionValue::Number(0.05))
        .expect("a number");
    vec.set(&mut env, "mode", &OptionValue::Text("residual".into()))
        .expect("a name");
    vec.set(&mut env, "threads", &OptionValue::Number(3.0))
        .expect("threads");
    assert_eq!(
        (env.control_period, env.mode, vec.threads),
        (0.05, ActionMode::Residual, 3)
    );
    assert!(matches!(
        vec.set(&mut env, "wobble", &OptionValue::Number(1.0)),
        Err(GymError::UnknownOption { name, .. }) if name == "wobble"
    ));
    assert!(matches!(
        vec.set(&mut env, "threads", &OptionValue::Number(1.5)),
        Err(GymError::Option {
            option: "threads",
            ..
        })
    ));
    assert!(matches!(
        vec.set(&mut env, "mode", &OptionValue::Number(1.0)),
        Err(GymError::Option { option: "mode", .. })
    ));
    assert!(
        matches!(
            vec.set(&mut env, "replay_fps", &OptionValue::Number(30.0)),
            Err(GymError::Option { option: "replay_fps", want, .. }) if want.contains("ProlegEnv")
        ),
        "a vector environment records no replay, and says where one is recorded"
    );
    vec.set(&mut env, "replay_fps", &OptionValue::Number(0.0))
        .expect("0 is the vector environments' own value");
    vec.set(&mut env, "randomize", &OptionValue::Number(1.0))
        .expect("True");
    assert!(env.randomize);
    assert!(matches!(
        vec.set(&mut env, "randomize", &OptionValue::Number(0.5)),
        Err(GymError::Option {
            option: "randomize",
            ..
        })
    ));
}

#[test]
fn a_randomized_environment_draws_each_resets_physics_as_the_robustness_check_does() {
    use proleg::config::robustness::Robustness;
    use proleg::sim::randomize::randomize;
    let sim = demo();
    let opts = EnvOptions {
        mode: ActionMode::Residual,
        duration: Some(1.0),
        randomize: true,
        ..EnvOptions::default()
    };
    let mut env = Env::new(sim.clone(), ModuleRegistry::standard(), opts.clone()).expect("env");
    let (first, com) = zero_residual_return(&mut env, 5);
    assert_eq!(
        zero_residual_return(&mut env, 5),
        (first, com),
        "same seed, same world"
    );
    let (other, _) = zero_residual_return(&mut env, 6);
    assert_ne!(first, other, "another seed draws other physics");
    // The world is the robustness draw of the reset's seed, built as the check builds it.
    let drawn = randomize(&sim, &Robustness::typical(), 5);
    let options = BuildOptions {
        seed: drawn.seed,
        noise: drawn.noise,
        record: false,
        ..BuildOptions::default()
    };
    let mut plain = Simulator::new(&drawn.sim, &options).expect("world");
    plain.run_steps(1000);
    assert_eq!(plain.com(0).expect("com"), com);
    let nominal = EnvOptions {
        randomize: false,
        ..opts
    };
    let mut env = Env::new(sim, ModuleRegistry::standard(), nominal).expect("env");
    assert_ne!(
        zero_residual_return(&mut env, 5).0,
        first,
        "the nominal world differs"
    );
}

#[test]
fn a_vector_environment_on_a_task_draws_train_courses_and_holds_each_once() {
    let opts = EnvOptions {
        duration: Some(0.1),
        terrain: Some(proleg::config::terrain::Family::Pegs),
        suite: Some(common::root().join("configs/suites/locomotion.suite.xml")),
        ..EnvOptions::default()
    };
    let mut v = next_step_vec(&opts, 6, 2);
    let mut met = std::collections::BTreeSet::new();
    for round in 0..3 {
        v.reset(Some(10 * round), None).expect("reset");
        for lane in v.lanes() {
            let seed = lane.info.terrain_seed.expect("a course");
            assert!((1..=20).contains(&seed), "a train seed: {seed}");
            met.insert(seed);
        }
    }
    assert!(met.len() > 3, "{met:?}");
    // One cache for all lanes: every course met is held once, whichever lane met it.
    for env in v.envs() {
        let kept = env.courses().expect("courses").cache().len();
        assert_eq!(kept, met.len());
    }
}
