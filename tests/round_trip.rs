//! Every file of configs/ and of the thesis fixtures, written back and read again,
//! gives an equal model; so does every loaded simulation's set of files.

mod common;

use std::path::Path;

use proleg::config::ConfigResult;
use proleg::config::actuation::{parse_actuation_file, write_actuation_file};
use proleg::config::environment::{parse_environment_file, write_environment_file};
use proleg::config::kinbody::{parse_kinbody_file, write_kinbody_file};
use proleg::config::optimizer::{parse_optimizer_file, write_optimizer_file};
use proleg::config::robot::{parse_robot_file, write_robot_file};
use proleg::config::sensor::{parse_sensor_file, write_sensor_file};
use proleg::config::simulation::{parse_simulation_file, write_simulation_file};
use proleg::control::load_simulation;

fn check<T: PartialEq + std::fmt::Debug>(
    path: &Path,
    parse: fn(&str, &str) -> ConfigResult<T>,
    write: fn(&T) -> String,
) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let name = path.display().to_string();
    let model = parse(&name, &text).unwrap_or_else(|e| panic!("{e}"));
    let written = write(&model);
    let again =
        parse("written", &written).unwrap_or_else(|e| panic!("re-reading {name}: {e}\n{written}"));
    assert_eq!(model, again, "{name} changed in a round trip:\n{written}");
    // Writing is stable: the second write is byte-identical.
    assert_eq!(written, write(&again));
    1
}

#[test]
fn every_file_round_trips() {
    let mut n = 0;
    for dir in [common::root().join("configs"), common::thesis()] {
        for p in common::files_ending(&dir, ".simulation.xml") {
            n += check(&p, parse_simulation_file, write_simulation_file);
        }
        for p in common::files_ending(&dir, ".robot.xml") {
            n += check(&p, parse_robot_file, write_robot_file);
        }
        for p in common::files_ending(&dir, ".kinbody.xml") {
            n += check(&p, parse_kinbody_file, write_kinbody_file);
        }
        for p in common::files_ending(&dir, ".sensor.xml") {
            n += check(&p, parse_sensor_file, write_sensor_file);
        }
        for p in common::files_ending(&dir, ".actuation.xml") {
            n += check(&p, parse_actuation_file, write_actuation_file);
        }
        for p in common::files_ending(&dir, ".env.xml") {
            n += check(&p, parse_environment_file, write_environment_file);
        }
        for p in common::files_ending(&dir, ".ga.xml")
            .into_iter()
            .chain(common::files_ending(&dir, ".gd.xml"))
            .chain(common::files_ending(&dir, ".cmaes.xml"))
        {
            n += check(&p, parse_optimizer_file, write_optimizer_file);
        }
    }
    assert!(n >= 40, "only {n} files found");
}

/// A simulation whose files are all rewritten in a temporary folder loads to an equal model.
#[test]
fn rewritten_simulation_loads_equal() {
    let sim =
        load_simulation(common::root().join("configs/experiment2_gd.simulation.xml")).unwrap();
    let dir = std::env::temp_dir().join(format!("proleg-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Parts, sensors and meshes stay where they are; the top-level files are rewritten.
    let f = &sim.files;
    let mut top = f.simulation.clone();
    top.robot.path = "r.robot.xml".into();
    top.actuation.path = "a.actuation.xml".into();
    top.environment.as_mut().unwrap().path = "e.env.xml".into();
    top.optimizer.as_mut().unwrap().path = "o.gd.xml".into();
    let mut robot = f.robot.clone();
    for inc in &mut robot.kinbody.includes {
        inc.file = sim
            .robot
            .files
            .iter()
            .find(|p| p.ends_with(&inc.file[3..]))
            .unwrap()
            .display()
            .to_string();
    }
    let mut env = f.environment.clone().unwrap();
    for o in &mut env.objects {
        if let proleg::config::environment::EnvObject::Inline(kb) = o {
            for b in &mut kb.bodies {
                for g in &mut b.geoms {
                    if let proleg::config::body::Shape::Trimesh { file, .. } = &mut g.shape {
                        *file = common::root().join(&*file).display().to_string();
                    }
                }
            }
        }
    }
    std::fs::write(dir.join("s.simulation.xml"), write_simulation_file(&top)).unwrap();
    std::fs::write(dir.join("r.robot.xml"), write_robot_file(&robot)).unwrap();
    std::fs::write(
        dir.join("a.actuation.xml"),
        write_actuation_file(&f.actuation),
    )
    .unwrap();
    std::fs::write(dir.join("e.env.xml"), write_environment_file(&env)).unwrap();
    std::fs::write(
        dir.join("o.gd.xml"),
        write_optimizer_file(f.optimizer.as_ref().unwrap()),
    )
    .unwrap();
    let again = load_simulation(dir.join("s.simulation.xml")).unwrap_or_else(|e| panic!("{e}"));
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(again.robot.links, sim.robot.links);
    assert_eq!(again.robot.joints, sim.robot.joints);
    assert_eq!(again.robot.sensors, sim.robot.sensors);
    assert_eq!(again.actuation.modules, sim.actuation.modules);
    assert_eq!(again.environment.bodies.len(), sim.environment.bodies.len());
    assert_eq!(again.environment.physics, sim.environment.physics);
    assert_eq!(
        again.optimizer.unwrap().parameters,
        sim.optimizer.unwrap().parameters
    );
    assert_eq!(
        again.files.simulation.properties,
        sim.files.simulation.properties
    );
}
