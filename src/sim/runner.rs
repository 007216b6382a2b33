//! [`Simulator`]: a headless world built from a configuration, stepped as fast as possible
//! (or paced to real time), with the one API for reading state and changing parameters
//! between steps that the CLI, the benchmarks, the optimizers and the GUI all use.

use std::time::{Duration, Instant};

use bevy::prelude::*;

use crate::config::Simulation;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::data::store::DataStore;
use crate::sim::SimPlugin;
use crate::sim::clock::SimClock;
use crate::sim::datalog::{DataLog, DataSettings, DataSink, flush_round, handlers_for};
use crate::sim::error::SimError;
use crate::sim::kernel::{Kernel, SimRobot};
use crate::sim::physics::Physics;
use crate::sim::record::{Track, centre_of_mass, heading};
use crate::sim::schedule::SimStep;
use crate::sim::servo::JointState;
use crate::sim::spawn::{BuildOptions, build_world};
use crate::sim::tactile::RobotSensors;

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    pub steps: u64,
    /// Simulated seconds.
    pub sim_time: f64,
    /// Wall-clock seconds.
    pub wall_time: f64,
    /// Simulated seconds per wall second.
    pub realtime_factor: f64,
    pub start_com: [f64; 3],
    pub end_com: [f64; 3],
    /// Thesis eq. 3.7: distance between start and end in the ground plane (m).
    pub displacement: f64,
    /// displacement / simulated time (m/s).
    pub mean_speed: f64,
}

impl RunSummary {
    /// The summary of `steps` steps of `dt` seconds that took `wall_time` wall seconds and
    /// moved robot 0's centre of mass from `start_com` to `end_com`.
    pub fn new(
        steps: u64,
        dt: f64,
        wall_time: f64,
        start_com: [f64; 3],
        end_com: [f64; 3],
    ) -> Self {
        let sim_time = steps as f64 * dt;
        let displacement =
            ((end_com[0] - start_com[0]).powi(2) + (end_com[1] - start_com[1]).powi(2)).sqrt();
        RunSummary {
            steps,
            sim_time,
            wall_time,
            realtime_factor: if wall_time > 0.0 {
                sim_time / wall_time
            } else {
                f64::INFINITY
            },
            start_com,
            end_com,
            displacement,
            mean_speed: if sim_time > 0.0 {
                displacement / sim_time
            } else {
                0.0
            },
        }
    }
}

/// A headless simulation.
pub struct Simulator {
    app: App,
    robots: Vec<Entity>,
}

impl Simulator {
    /// Builds the world of `sim` with the standard module registry.
    pub fn new(sim: &Simulation, opts: &BuildOptions) -> Result<Self, SimError> {
        Simulator::with_registry(sim, opts, &ModuleRegistry::default())
    }

    /// Builds the world of `sim` with the given module registry.
    pub fn with_registry(
        sim: &Simulation,
        opts: &BuildOptions,
        registry: &ModuleRegistry,
    ) -> Result<Self, SimError> {
        let mut app = App::new();
        app.add_plugins(SimPlugin);
        let robots = build_world(app.world_mut(), sim, opts, registry)?;
        Ok(Simulator { app, robots })
    }

    pub fn world(&self) -> &World {
        self.app.world()
    }

    pub fn world_mut(&mut self) -> &mut World {
        self.app.world_mut()
    }

    /// The robot entities, in batch order.
    pub fn robots(&self) -> &[Entity] {
        &self.robots
    }

    fn robot(&self, index: usize) -> Result<Entity, SimError> {
        self.robots
            .get(index)
            .copied()
            .ok_or(SimError::NoSuchRobot {
                index,
                count: self.robots.len(),
            })
    }

    /// A component of robot `index`'s root entity.
    fn robot_component<C: Component>(&self, index: usize) -> Result<&C, SimError> {
        let e = self.robot(index)?;
        self.app.world().get::<C>(e).ok_or(SimError::NoSuchRobot {
            index,
            count: self.robots.len(),
        })
    }

    pub fn clock(&self) -> &SimClock {
        self.app.world().resource::<SimClock>()
    }

    /// Runs `n` steps as fast as possible.
    pub fn run_steps(&mut self, n: u64) {
        let world = self.app.world_mut();
        // Taking the schedule out once saves its lookup on every step.
        let Some(mut schedule) = world.resource_mut::<Schedules>().remove(SimStep) else {
            return;
        };
        for _ in 0..n {
            schedule.run(world);
        }
        world.resource_mut::<Schedules>().insert(schedule);
    }

    /// One step.
    pub fn step(&mut self) {
        self.run_steps(1);
    }

    /// Runs for `seconds` of simulated time (rounded to whole steps), paced by the clock's
    /// real-time factor and delay, and summarizes robot 0's motion over the run.
    pub fn run_for(&mut self, seconds: f64) -> RunSummary {
        let dt = self.clock().dt;
        let steps = (seconds / dt).round().max(0.0) as u64;
        let (factor, delay) = (self.clock().realtime_factor, self.clock().delay_ms);
        let start_com = self.com(0).unwrap_or_default();
        let start_step = self.clock().step;
        let wall = Instant::now();
        if factor <= 0.0 && delay <= 0.0 {
            self.run_steps(steps);
        } else {
            for k in 1..=steps {
                self.run_steps(1);
                if delay > 0.0 {
                    std::thread::sleep(Duration::from_secs_f64(delay / 1000.0));
                }
                if factor > 0.0 {
                    let due = Duration::from_secs_f64(k as f64 * dt / factor);
                    if let Some(wait) = due.checked_sub(wall.elapsed()) {
                        std::thread::sleep(wait);
                    }
                }
            }
        }
        let end_com = self.com(0).unwrap_or_default();
        let done = self.clock().step - start_step;
        RunSummary::new(done, dt, wall.elapsed().as_secs_f64(), start_com, end_com)
    }

    /// The link bodies of robot `index`, in link order.
    pub fn robot_bodies(
        &self,
        index: usize,
    ) -> Result<Vec<rapier3d::prelude::RigidBodyHandle>, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        Ok(robot.bodies.iter().map(|(h, _)| *h).collect())
    }

    /// Moves `bodies` by `delta` metres (z up) between steps, keeping their velocities and
    /// orientations (the viewer's drag); unknown handles are skipped.
    pub fn translate_bodies(
        &mut self,
        bodies: &[rapier3d::prelude::RigidBodyHandle],
        delta: [f64; 3],
    ) {
        if !delta.iter().all(|d| d.is_finite()) {
            return;
        }
        let mut physics = self.app.world_mut().resource_mut::<Physics>();
        for h in bodies {
            if let Some(b) = physics.world.bodies.get_mut(*h) {
                let t = crate::sim::physics::arr3(b.translation());
                let moved = [t[0] + delta[0], t[1] + delta[1], t[2] + delta[2]];
                b.set_translation(crate::sim::physics::vec3(moved), true);
            }
        }
    }

    /// Centre of mass of robot `index` (m, z up).
    pub fn com(&self, index: usize) -> Result<[f64; 3], SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let w = self.app.world();
        Ok(centre_of_mass(&w.resource::<Physics>().world.bodies, robot))
    }

    /// Tail-to-head heading of robot `index` in the ground plane (degrees from +x).
    pub fn heading(&self, index: usize) -> Result<f64, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let w = self.app.world();
        Ok(heading(&w.resource::<Physics>().world.bodies, robot))
    }

    /// The current state of every joint of robot `index`.
    pub fn joint_states(&self, index: usize) -> Result<Vec<JointState>, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let w = self.app.world();
        Ok(robot
            .joints
            .iter()
            .map(|j| w.get::<JointState>(*j).copied().unwrap_or_default())
            .collect())
    }

    /// The recorded trajectory of robot `index`.
    pub fn track(&self, index: usize) -> Result<&Track, SimError> {
        self.robot_component::<Track>(index)
    }

    /// The control kernel of robot `index`.
    pub fn kernel(&self, index: usize) -> Result<&ControlKernel, SimError> {
        self.robot_component::<Kernel>(index).map(|k| &k.0)
    }

    /// Makes robot `index`'s servos follow `angles` (degrees, one per joint) instead of
    /// its kernel — the twin of a real robot — or the kernel again with `None`.
    pub fn set_joint_override(
        &mut self,
        index: usize,
        angles: Option<Vec<f64>>,
    ) -> Result<(), SimError> {
        let e = self.robot(index)?;
        let mut entity = self.app.world_mut().entity_mut(e);
        match angles {
            Some(a) => match entity.get_mut::<crate::sim::kernel::JointOverride>() {
                Some(mut o) => {
                    o.0.clear();
                    o.0.extend_from_slice(&a);
                }
                None => {
                    entity.insert(crate::sim::kernel::JointOverride(a));
                }
            },
            None => {
                entity.remove::<crate::sim::kernel::JointOverride>();
            }
        }
        Ok(())
    }

    /// The control kernel of robot `index`, to change between steps (parameters,
    /// distortions, perturbations; see [`ControlKernel`]).
    pub fn kernel_mut(&mut self, index: usize) -> Result<&mut ControlKernel, SimError> {
        let e = self.robot(index)?;
        let count = self.robots.len();
        self.app
            .world_mut()
            .get_mut::<Kernel>(e)
            .map(|k| &mut k.into_inner().0)
            .ok_or(SimError::NoSuchRobot { index, count })
    }

    /// Starts recording data handlers on every robot (thesis 4.3.2); with `store`, robot 0's
    /// frames are also written to that data file by its background writer. Call
    /// [`Simulator::finish_data`] to close the file.
    pub fn enable_data(&mut self, settings: DataSettings, store: Option<DataStore>) {
        let world = self.app.world_mut();
        world.insert_resource(settings);
        let mut q = world.query::<(Entity, &SimRobot, &Kernel, &RobotSensors)>();
        let logs: Vec<(Entity, DataLog)> = q
            .iter(world)
            .map(|(e, robot, kernel, sensors)| {
                let mass = robot.bodies.iter().map(|(_, m)| m).sum();
                (
                    e,
                    DataLog::new(handlers_for(&kernel.0, &sensors.0), &settings, mass),
                )
            })
            .collect();
        for (e, log) in logs {
            world.entity_mut(e).insert(log);
        }
        if let Some(store) = store {
            world.insert_resource(DataSink {
                store,
                rounds_sent: 0,
                error: None,
            });
        }
    }

    /// The data handlers of robot `index` (after [`Simulator::enable_data`]).
    pub fn data(&self, index: usize) -> Result<&DataLog, SimError> {
        self.robot_component::<DataLog>(index)
    }

    /// Sends the last frames to the data file and closes it well-formed; returns the
    /// rounds written (0 without a file).
    pub fn finish_data(&mut self) -> Result<u64, String> {
        let world = self.app.world_mut();
        flush_round(world);
        match world.remove_resource::<DataSink>() {
            Some(sink) => {
                if let Some(e) = sink.error {
                    return Err(e);
                }
                sink.store.finish()
            }
            None => Ok(0),
        }
    }

    /// Changes a module parameter of robot `robot` between steps (see
    /// [`ControlKernel::set_parameter`]).
    pub fn set_parameter(
        &mut self,
        robot: usize,
        actuator: usize,
        name: &str,
        joint: Option<usize>,
        value: f64,
    ) -> Result<(), SimError> {
        let e = self.robot(robot)?;
        let count = self.robots.len();
        let mut kernel =
            self.app
                .world_mut()
                .get_mut::<Kernel>(e)
                .ok_or(SimError::NoSuchRobot {
                    index: robot,
                    count,
                })?;
        Ok(kernel.0.set_parameter(actuator, name, joint, value)?)
    }
}
