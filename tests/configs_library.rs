//! The ready configurations in configs/: every simulation loads and checks, every file
//! there is used by some simulation (so every file is checked), and the thesis's
//! experiment set-ups hold the values of chapter 6.

mod common;

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::Command;

use proleg::config::Simulation;
use proleg::config::optimizer::Algorithm;
use proleg::config::resolve::JointOrientation;
use proleg::config::sensor::Sensor;
use proleg::config::simulation::Mode;
use proleg::control::load_simulation;

fn load(name: &str) -> Simulation {
    load_simulation(common::root().join("configs").join(name)).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_simulation_loads_and_every_file_is_used() {
    let configs = common::root().join("configs");
    let sims = common::files_ending(&configs, ".simulation.xml");
    assert!(sims.len() >= 6);
    let mut used: BTreeSet<PathBuf> = BTreeSet::new();
    for s in &sims {
        let sim = load_simulation(s).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            sim.warnings.is_empty(),
            "{}: {:?}",
            s.display(),
            sim.warnings
        );
        used.insert(std::fs::canonicalize(s).unwrap());
        let mut files = sim.robot.files.clone();
        files.extend(sim.environment.files.iter().cloned());
        files.push(sim.actuation.file.clone());
        files.extend(sim.optimizer.iter().map(|o| o.file.clone()));
        // A co-design space's bodies use the part files of its orientations and sets.
        let source = proleg::config::source::FsSource;
        files.extend(proleg::optimize::design::body_files(&sim, &source).unwrap());
        for b in &sim.environment.bodies {
            for g in &b.geoms {
                if let proleg::config::body::Shape::Trimesh { file, .. } = &g.shape {
                    files.push(PathBuf::from(file));
                }
            }
        }
        for f in files {
            used.insert(std::fs::canonicalize(&f).unwrap_or_else(|_| panic!("{}", f.display())));
        }
    }
    for f in common::files_ending(&configs, ".xml") {
        let f = std::fs::canonicalize(&f).unwrap();
        if f.to_string_lossy().ends_with(".remote.xml") {
            // Gamepad bindings are chosen at run time: they must fit the remote demo.
            check_remote_file(&f);
            continue;
        }
        if f.to_string_lossy().ends_with(".suite.xml") {
            // Suites name their terrains; `proleg suite` takes the controller.
            let text = std::fs::read_to_string(&f).unwrap();
            proleg::config::suite::parse_suite_file(&f.display().to_string(), &text)
                .unwrap_or_else(|e| panic!("{e}"));
            continue;
        }
        assert!(
            used.contains(&f),
            "{} is used by no simulation in configs/",
            f.display()
        );
    }
}

#[test]
fn experiment_1_setup() {
    let sim = load("experiment1_gd.simulation.xml");
    let r = &sim.robot;
    assert_eq!(r.name, "snake5p");
    assert_eq!(
        (r.links.len(), r.joints.len(), r.pattern().as_str()),
        (6, 5, "PPPPP")
    );
    let pitch: Vec<f64> = r
        .joints
        .windows(2)
        .map(|w| ((w[1].anchor[1] - w[0].anchor[1]) * 1e6).round() / 1e3)
        .collect();
    assert_eq!(pitch, [72.0; 4], "module pitch in mm");
    let p = &sim.files.simulation.properties;
    assert_eq!(
        (p.mode, p.duration, p.step_width),
        (Mode::GreatDeluge, 30.0, 0.001)
    );
    let sine = &sim.actuation.modules[0];
    assert_eq!(sine.descriptor.type_name, "PatternGenerator_sinusoidal");
    let get = |n: &str| {
        sine.params
            .iter()
            .find(|p| p.name == n)
            .map(|p| p.value.clone())
    };
    use proleg::config::actuation::ParamValue::Uniform;
    assert_eq!(get("Amplitude"), Some(Uniform(40.0)));
    assert_eq!(get("Phase_Difference"), Some(Uniform(55.0)));
    let o = sim.optimizer.unwrap();
    let Algorithm::GreatDeluge(gd) = &o.spec.algorithm else {
        panic!()
    };
    assert_eq!(
        (
            gd.credits,
            gd.retries,
            gd.initial_water_level,
            gd.rain,
            gd.confidence
        ),
        (10, 200, 0.15, 0.01, 20)
    );
    // Footnote 2 of chapter 6: (40 / 0.25 + 1)^5 = 108,175,616,801 solutions.
    assert_eq!(o.search_space(), 108_175_616_801.0);

    let ga = load("experiment1_ga.simulation.xml").optimizer.unwrap();
    let Algorithm::Genetic(g) = &ga.spec.algorithm else {
        panic!()
    };
    assert_eq!(
        (
            g.popsize,
            g.pmut,
            g.pcross,
            g.p_convergence,
            g.n_convergence
        ),
        (30, 0.8, 0.2, 0.99, 50)
    );
}

#[test]
fn experiment_2_setup() {
    let sim = load("experiment2_gd.simulation.xml");
    let r = &sim.robot;
    assert_eq!(
        (r.name.as_str(), r.pattern().as_str()),
        ("tactile5p", "PPPPP")
    );
    let touch = r
        .sensors
        .iter()
        .filter(|s| matches!(s.sensor, Sensor::Tactile(_)))
        .count();
    assert_eq!(touch, 12, "twelve touch sensors");
    // Pads are under the links: below the link origin.
    assert!(r.sensors.iter().all(|s| s.pose.translation[2] < 0.0));
    assert!(
        r.joints
            .iter()
            .all(|j| j.orientation == JointOrientation::Pitch)
    );
    assert_eq!(sim.files.simulation.properties.duration, 90.0);
    let names: Vec<&str> = sim
        .actuation
        .modules
        .iter()
        .map(|m| m.descriptor.type_name)
        .collect();
    assert_eq!(
        names,
        ["PatternGenerator_sinusoidal", "Global_Adaptive_Touch"]
    );
    assert!(sim.environment.bodies.iter().any(|b| b.name == "obstacle"));
    let marks = sim
        .environment
        .bodies
        .iter()
        .filter(|b| b.name.starts_with("mark"))
        .count();
    assert!(marks >= 4, "a metre scale beside the track");
    let o = sim.optimizer.unwrap();
    let Algorithm::GreatDeluge(gd) = &o.spec.algorithm else {
        panic!()
    };
    assert_eq!((gd.initial_water_level, gd.rain), (0.6, 0.02));
    // Table 6.5: 37 * 200 * 10^8 = 740,000,000,000 candidates.
    assert_eq!(o.search_space().round(), 740_000_000_000.0);
    let ga = load("experiment2_ga.simulation.xml").optimizer.unwrap();
    let Algorithm::Genetic(g) = &ga.spec.algorithm else {
        panic!()
    };
    assert_eq!((g.popsize, g.pmut, g.pcross), (40, 1.0, 0.0));
}

#[test]
fn longer_chains_alternate_pitch_and_yaw() {
    assert_eq!(
        load("snake8py_slope.simulation.xml").robot.pattern(),
        "PYPYPYP"
    );
    assert_eq!(
        load("snake16py_stairs.simulation.xml").robot.pattern(),
        "PYPYPYPYPYPYPYP"
    );
    assert_eq!(load("cube5_flat.simulation.xml").robot.pattern(), "PPPPP");
}

#[test]
fn cli_check_prints_a_summary() {
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["check", "configs/demo.simulation.xml"])
        .current_dir(common::root())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for needle in [
        "robot       snake5p",
        "joints 5 [PPPPP]",
        "PatternGenerator_sinusoidal  joints 11111",
        "floor (static)",
        "ok",
    ] {
        assert!(stdout.contains(needle), "{needle:?} missing in:\n{stdout}");
    }
}

#[test]
fn cli_check_fails_with_the_location() {
    let dir = std::env::temp_dir().join(format!("proleg-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.simulation.xml");
    std::fs::write(&bad, "<simulation>\n  <robot>missing.robot.xml</robot>\n  <actuation>a.xml</actuation>\n</simulation>\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .arg("check")
        .arg(&bad)
        .output()
        .unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("bad.simulation.xml:2:10: robot file \"missing.robot.xml\" not found"),
        "{stderr}"
    );
}

/// A binding file parses and fits the gamepad demo's robot.
fn check_remote_file(path: &std::path::Path) {
    let text = std::fs::read_to_string(path).unwrap();
    let name = path.display().to_string();
    let file =
        proleg::config::remote::parse_remote_file(&name, &text).unwrap_or_else(|e| panic!("{e}"));
    let sim = load_simulation("configs/snake8py_remote.simulation.xml").unwrap();
    let limits = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let kernel = proleg::control::ControlKernel::from_actuation(
        &sim.actuation,
        &proleg::control::ModuleRegistry::default(),
        limits,
    )
    .unwrap();
    let orientations: Vec<_> = sim.robot.joints.iter().map(|j| j.orientation).collect();
    proleg::remote::RemoteMapper::new(&file, &name, &kernel, &orientations)
        .unwrap_or_else(|e| panic!("{e}"));
}
