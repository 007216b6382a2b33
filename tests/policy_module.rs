//! The `Policy` actuation module: a network named in the actuation file runs in the
//! simulation exactly as the Python environment runs it (same observation, same action
//! scaling: the same trajectory on rapier and MuJoCo), and bad weights files are errors
//! that name the file and the tensor.

mod common;

use std::path::Path;
use std::sync::Arc;

use proleg::config::Simulation;
use proleg::config::actuation::ParamValue;
use proleg::config::resolve::{ModuleInstance, ParamAssignment, WeightsFile};
use proleg::config::simulation::EngineKind;
use proleg::control::policy::{Activation, Layer, PolicyNet};
use proleg::control::{ModuleRegistry, load_simulation};
use proleg::gym::{ActionMode, Env, EnvOptions};
use proleg::rng::SimRng;
use proleg::sim::{BuildOptions, Simulator};

fn demo(engine: EngineKind) -> Simulation {
    load_simulation(common::root().join("configs/demo.simulation.xml"))
        .expect("demo")
        .with_engine(Some(engine))
}

/// A tanh network of 16 hidden units from the demo's residual observation to its joints,
/// its weights drawn from `seed`; inputs named in `blind` get zero weights (the pads and
/// lasers: the environment reads them one physics step earlier than the module).
fn network(names: &[String], joints: usize, seed: u64) -> PolicyNet {
    let mut rng = SimRng::new(seed);
    let mut draw = |n: usize, scale: f64| -> Vec<f64> {
        (0..n)
            .map(|_| (rng.next_u64() % 2001) as f64 / 1000.0 - 1.0)
            .map(|v| v * scale)
            .collect()
    };
    let inputs = names.len();
    let mut first = draw(16 * inputs, 0.6);
    for (i, name) in names.iter().enumerate() {
        if name.starts_with("pad") || name.starts_with("laser") {
            (0..16).for_each(|o| first[o * inputs + i] = 0.0);
        }
    }
    let layers = vec![
        Layer {
            weight: first,
            bias: draw(16, 0.2),
        },
        Layer {
            weight: draw(joints * 16, 0.8),
            bias: draw(joints, 0.2),
        },
    ];
    let mut net = PolicyNet::new(layers, Activation::Tanh).expect("a network");
    net.obs_mean = draw(inputs, 0.1);
    net.obs_std = vec![1.5; inputs];
    net
}

/// `sim` with a `Policy` on every joint after its own modules, reading `weights`, its
/// amplitude the environment's residual action scale.
fn with_policy(sim: &Simulation, weights: &Path, amplitude: &[f64]) -> Simulation {
    let registry = ModuleRegistry::standard();
    let mut sim = sim.clone();
    let joints = sim.robot.joints.len();
    sim.actuation.modules.push(ModuleInstance {
        descriptor: registry.get("Policy").expect("the Policy module").clone(),
        joints: proleg::config::mask::JointMask(vec![true; joints]),
        params: vec![ParamAssignment {
            name: "Amplitude",
            value: ParamValue::PerJoint(amplitude.to_vec()),
        }],
        weights: Some(WeightsFile {
            path: weights.to_path_buf(),
            bytes: std::fs::read(weights).expect("weights").into(),
        }),
        pos: Default::default(),
    });
    sim
}

/// The module's and the environment's centre-of-mass tracks over 0.6 s on `engine`.
fn module_against_environment(engine: EngineKind, name: &str) {
    let sim = demo(engine);
    let opts = EnvOptions {
        mode: ActionMode::Residual,
        duration: Some(0.6),
        ..EnvOptions::default()
    };
    let mut env = Env::new(
        Arc::new(sim.clone()),
        ModuleRegistry::standard(),
        opts.clone(),
    )
    .expect("env");
    let mut obs = vec![0.0; env.layout().len()];
    env.reset(Some(4), &mut obs).expect("reset");
    let joints = env.action_len();
    let net = network(&env.layout().names(), joints, 11);
    let dir = common::scratch(name);
    let weights = dir.join("policy.safetensors");
    net.write(&weights).expect("write");
    // The file holds F32: run the environment with the network as read back.
    let mut net = PolicyNet::read(&weights).expect("read");
    let amplitude: Vec<f64> = env
        .world()
        .kernel(0)
        .expect("kernel")
        .limits()
        .iter()
        .map(|[lo, hi]| 0.5 * (hi - lo) * opts.scale())
        .collect();
    let mut action = vec![0.0; joints];
    let mut through_env = Vec::new();
    loop {
        net.forward(&obs, &mut action);
        let t = env.step(&action, &mut obs).expect("step");
        through_env.push(env.world().com(0).expect("com"));
        if t.truncated || t.terminated {
            break;
        }
    }
    let mut world = Simulator::new(
        &with_policy(&sim, &weights, &amplitude),
        &BuildOptions {
            seed: 4,
            record: false,
            ..Default::default()
        },
    )
    .expect("world with a policy");
    let mut in_module = Vec::new();
    for _ in &through_env {
        world.run_steps(env.steps_per_action());
        in_module.push(world.com(0).expect("com"));
    }
    assert!(world.kernel(0).expect("kernel").failures().next().is_none());
    let moved = |track: &[[f64; 3]]| {
        let (a, b) = (track[0], track[track.len() - 1]);
        ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
    };
    assert!(moved(&in_module) > 1e-3, "the robot moves: {in_module:?}");
    for (k, (a, b)) in in_module.iter().zip(&through_env).enumerate() {
        let d = (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max);
        assert!(d < 1e-9, "period {k}: module {a:?}, environment {b:?}");
    }
    // Without the policy the robot goes elsewhere: the module really drives the joints.
    let mut plain = Simulator::new(
        &sim,
        &BuildOptions {
            seed: 4,
            record: false,
            ..Default::default()
        },
    )
    .expect("world");
    plain.run_steps(env.steps_per_action() * through_env.len() as u64);
    let last = in_module[in_module.len() - 1];
    let other = plain.com(0).expect("com");
    assert!((0..3).any(|i| (last[i] - other[i]).abs() > 1e-4));
}

#[test]
fn a_policy_module_runs_as_the_environment_runs_its_network_on_rapier() {
    module_against_environment(EngineKind::Rapier, "policy-module-rapier");
}

#[test]
fn a_policy_module_runs_as_the_environment_runs_its_network_on_mujoco() {
    if common::mujoco_here("policy module on MuJoCo") {
        module_against_environment(EngineKind::Mujoco, "policy-module-mujoco");
    }
}

fn build_error(sim: &Simulation) -> String {
    match Simulator::new(sim, &BuildOptions::default()) {
        Ok(_) => panic!("a bad weights file was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_weights_files_are_errors_naming_file_and_tensor() {
    let sim = demo(EngineKind::Rapier);
    let dir = common::scratch("policy-module-bad-weights");
    let joints = sim.robot.joints.len();
    // Three outputs for five joints.
    let narrow = dir.join("narrow.safetensors");
    PolicyNet::new(
        vec![Layer {
            weight: vec![0.0; 3 * 4],
            bias: vec![0.0; 3],
        }],
        Activation::Tanh,
    )
    .expect("net")
    .write(&narrow)
    .expect("write");
    let e = build_error(&with_policy(&sim, &narrow, &vec![10.0; joints]));
    assert!(
        e.contains("narrow.safetensors")
            && e.contains("layers.0.weight")
            && e.contains("3 outputs"),
        "{e}"
    );
    // Not a safetensors file at all.
    let junk = dir.join("junk.safetensors");
    std::fs::write(&junk, b"not tensors").expect("write");
    let e = build_error(&with_policy(&sim, &junk, &vec![10.0; joints]));
    assert!(e.contains("junk.safetensors"), "{e}");
    // A network whose inputs are not the observation's: refused before the first step,
    // naming the actuation file (this module was not written in one: no line).
    let wide = dir.join("wide.safetensors");
    PolicyNet::new(
        vec![Layer {
            weight: vec![0.1; joints * 7],
            bias: vec![0.0; joints],
        }],
        Activation::Tanh,
    )
    .expect("net")
    .write(&wide)
    .expect("write");
    let e = build_error(&with_policy(&sim, &wide, &vec![10.0; joints]));
    assert!(
        e.contains("reads 7 inputs but the observation has")
            && e.contains(&sim.actuation.file.display().to_string()),
        "{e}"
    );
}

#[test]
fn an_actuation_file_names_its_weights_file_relative_to_itself() {
    let dir = common::scratch("policy-module-actuation-file");
    let root = common::root().join("configs");
    let act = dir.join("policy.actuation.xml");
    std::fs::write(
        &act,
        r#"<actuation>
  <actuationModule name="PatternGenerator_sinusoidal">
    <jointConfiguration joints="11111"/>
  </actuationModule>
  <actuationModule name="Policy" weights="missing.safetensors">
    <jointConfiguration joints="11111"/>
  </actuationModule>
</actuation>
"#,
    )
    .expect("actuation");
    let sim_file = dir.join("policy.simulation.xml");
    let text = std::fs::read_to_string(root.join("demo.simulation.xml"))
        .expect("demo")
        .replace(
            "robots/snake5p.robot.xml",
            &root.join("robots/snake5p.robot.xml").display().to_string(),
        )
        .replace(
            "environments/flat.env.xml",
            &root.join("environments/flat.env.xml").display().to_string(),
        )
        .replace(
            "actuation/snake5p_sine40.actuation.xml",
            "policy.actuation.xml",
        );
    std::fs::write(&sim_file, text).expect("simulation");
    let e = load_simulation(&sim_file).expect_err("a missing weights file");
    let text = e.to_string();
    assert!(
        text.contains("policy.actuation.xml") && text.contains("missing.safetensors"),
        "{text}"
    );
    let joints = 5;
    let net = PolicyNet::new(
        vec![Layer {
            weight: vec![0.0; joints * 24],
            bias: vec![0.0; joints],
        }],
        Activation::Tanh,
    )
    .expect("net");
    net.write(&dir.join("missing.safetensors")).expect("write");
    let sim = load_simulation(&sim_file).expect("the weights file is found now");
    assert_eq!(
        sim.actuation.modules[1]
            .weights
            .as_ref()
            .map(|w| w.path.as_path()),
        Some(dir.join("missing.safetensors").as_path())
    );
    let written = proleg::config::actuation::write_actuation_file(
        &proleg::config::actuation::parse_actuation_file(
            "policy.actuation.xml",
            &std::fs::read_to_string(&act).expect("read"),
        )
        .expect("parse"),
    );
    assert!(
        written.contains(r#"weights="missing.safetensors""#),
        "{written}"
    );
    // Its network reads 24 inputs; the demo snake with a sine observes 18: `proleg run`
    // refuses it before the first step, naming the file and the module's line.
    let (ok, out, err) = common::proleg(&["run", sim_file.to_str().expect("path")]);
    assert!(!ok && !out.contains("displacement"), "{out}");
    assert!(
        err.contains("policy.actuation.xml:5:3")
            && err.contains("the network reads 24 inputs but the observation has 18"),
        "{err}"
    );
}

#[test]
fn a_fresh_policy_runs_the_files_gait_unchanged() {
    // `proleg policy init` writes an output layer of zeros: the demo with its Policy module
    // walks exactly as the demo without it, on either engine's first seconds.
    let with = load_simulation(common::root().join("configs/demo_policy_es.simulation.xml"))
        .expect("demo with a policy");
    let without = demo(EngineKind::Rapier);
    let com = |sim: &Simulation| {
        let mut world = Simulator::new(sim, &BuildOptions::default()).expect("world");
        world.run_steps(1500);
        world.com(0).expect("com")
    };
    assert_eq!(com(&with), com(&without));
    let net = PolicyNet::read(&common::root().join("configs/policies/demo_start.safetensors"))
        .expect("the shipped start");
    // The file holds F32 values: the floor as F32 rounds it.
    let floor = proleg::gym::statistics::MIN_STD as f32 as f64;
    assert!(net.obs_std.iter().all(|s| *s >= floor), "{:?}", net.obs_std);
    assert!(
        net.layers[net.layers.len() - 1]
            .weight
            .iter()
            .all(|w| *w == 0.0)
    );
}
