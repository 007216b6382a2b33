//! A task's world: the controller's robot, control and physics properties on one of the
//! task's courses, started where the controller's own environment starts its robot.

use std::path::Path;

use crate::config::Simulation;
use crate::config::environment::{EnvObject, EnvironmentFile};
use crate::config::resolve::environment::resolve_environment;
use crate::config::source::FsSource;
use crate::config::suite::Task;
use crate::suite::error::SuiteError;

/// `controller` on task `task`'s course of terrain seed `seed`, for the task's duration.
/// `suite` is the suite file (what errors name).
pub fn task_world(
    controller: &Simulation,
    task: &Task,
    seed: u64,
    suite: &Path,
) -> Result<Simulation, SuiteError> {
    let env = EnvironmentFile {
        physics: controller.environment.physics.clone(),
        objects: vec![EnvObject::Terrain(task.course(seed))],
        robot_pose: Some(controller.environment.robot_pose),
    };
    let mut sim = controller.clone();
    sim.environment = resolve_environment(&FsSource, suite, &env)?;
    sim.files.simulation.properties.duration = task.duration;
    Ok(sim)
}

/// The course's forward direction in the world (its +y, turned by its placement).
pub fn course_direction(task: &Task) -> [f64; 3] {
    task.terrain.pose.rotate([0.0, 1.0, 0.0])
}
