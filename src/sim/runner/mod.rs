//! [`Simulator`]: a headless world built from a configuration, stepped as fast as possible
//! or paced against the wall clock. It is the one door to a running world: the CLI, the
//! benchmarks, the optimizers, the real-robot twin and the GUI read its state and change it
//! between steps only through its typed methods, grouped by concern:
//!
//! | file | methods |
//! |---|---|
//! | `mod.rs` | building, stepping, pacing, [`RunSummary`] |
//! | `state.rs` | typed reads: centre of mass, heading, joints, sensors, energy, a read-only view of the bodies and contacts |
//! | `control.rs` | typed writes: module parameters, kernels, joint overrides (the twin), moving bodies |
//! | `data.rs` | recording data handlers, into ring buffers and a data file |

mod control;
mod data;
pub use data::RecordError;
mod state;

use std::time::Instant;

use bevy::prelude::*;

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::measure::ground_distance;
use crate::sim::SimPlugins;
use crate::sim::clock::SimClock;
use crate::sim::error::SimError;
use crate::sim::pacing::{Pacer, Pacing};
use crate::sim::schedule::SimStep;
use crate::sim::spawn::{BuildOptions, build_world};

pub use state::{PadReading, SceneBody};

/// What a run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Steps run.
    pub steps: u64,
    /// Simulated seconds.
    pub sim_time: f64,
    /// Wall-clock seconds.
    pub wall_time: f64,
    /// Simulated seconds per wall second.
    pub realtime_factor: f64,
    /// Robot 0's centre of mass at the start (m, z up).
    pub start_com: [f64; 3],
    /// Robot 0's centre of mass at the end (m, z up).
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
        let displacement = ground_distance(start_com, end_com);
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

/// A headless simulation. It owns the ECS world that [`SimPlugins`] set up (the `App`
/// that built it is dropped: nothing here runs Bevy's update loop), so a `Simulator` is
/// `Send` and moves between threads (a vectorized environment's thread pool).
pub struct Simulator {
    world: World,
    robots: Vec<Entity>,
    pacing: Pacing,
}

impl Simulator {
    /// Builds the world of `sim` with the standard module registry; it runs unpaced.
    pub fn new(sim: &Simulation, opts: &BuildOptions) -> Result<Self, SimError> {
        Simulator::with_registry(sim, opts, &ModuleRegistry::default())
    }

    /// Builds the world of `sim` with the given module registry; it runs unpaced.
    pub fn with_registry(
        sim: &Simulation,
        opts: &BuildOptions,
        registry: &ModuleRegistry,
    ) -> Result<Self, SimError> {
        Simulator::with_stages(sim, opts, registry, SimPlugins)
    }

    /// Builds the world of `sim` with the step's stages from `stages`: [`SimPlugins`] with
    /// a stage replaced (another servo model) or added ([`crate::sim::StageTimerPlugin`]).
    pub fn with_stages(
        sim: &Simulation,
        opts: &BuildOptions,
        registry: &ModuleRegistry,
        stages: impl PluginGroup,
    ) -> Result<Self, SimError> {
        let mut app = App::new();
        app.add_plugins(stages);
        let robots = build_world(app.world_mut(), sim, opts, registry)?;
        Ok(Simulator {
            world: std::mem::take(app.world_mut()),
            robots,
            pacing: Pacing::UNPACED,
        })
    }

    /// The wall time of each stage, when the world was built with
    /// [`crate::sim::StageTimerPlugin`].
    pub fn stage_times(&self) -> Option<&crate::sim::StageTimes> {
        self.world.get_resource()
    }

    /// The ECS world, for the crate's own systems and tests of the schedule.
    pub(crate) fn world(&self) -> &World {
        &self.world
    }

    /// The ECS world, mutable, for the crate's own benchmarks and the facade's methods.
    pub(crate) fn world_mut(&mut self) -> &mut World {
        &mut self.world
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
        self.world.get::<C>(e).ok_or(SimError::NoSuchRobot {
            index,
            count: self.robots.len(),
        })
    }

    /// A component of robot `index`'s root entity, to change.
    fn robot_component_mut<C: Component<Mutability = bevy::ecs::component::Mutable>>(
        &mut self,
        index: usize,
    ) -> Result<Mut<'_, C>, SimError> {
        let e = self.robot(index)?;
        let count = self.robots.len();
        self.world
            .get_mut::<C>(e)
            .ok_or(SimError::NoSuchRobot { index, count })
    }

    /// Step counter, step width and simulated time.
    pub fn clock(&self) -> &SimClock {
        self.world.resource::<SimClock>()
    }

    /// How [`Simulator::run_for`] paces against the wall clock.
    pub fn pacing(&self) -> Pacing {
        self.pacing
    }

    /// Sets the pacing of [`Simulator::run_for`] (default: unpaced).
    pub fn set_pacing(&mut self, pacing: Pacing) {
        self.pacing = pacing;
    }

    /// Runs `n` steps as fast as possible.
    pub fn run_steps(&mut self, n: u64) {
        // One scope for all `n` steps saves the schedule's lookup on every step; a world
        // without the step schedule (never built by `Simulator`) does not step.
        let stepped = self.world.try_schedule_scope(SimStep, |world, schedule| {
            for _ in 0..n {
                schedule.run(world);
            }
        });
        debug_assert!(
            stepped.is_ok(),
            "a Simulator's world has the SimStep schedule"
        );
    }

    /// Steps the physics engine alone `n` times, no stage of the pipeline around it (the
    /// servos hold their last command): the benchmarks' floor for the physics cost.
    pub fn step_engine_only(&mut self, n: u64) {
        let mut physics = self.world.resource_mut::<crate::sim::physics::SimPhysics>();
        for _ in 0..n {
            physics.engine.step();
        }
    }

    /// One step.
    pub fn step(&mut self) {
        self.run_steps(1);
    }

    /// Runs for `seconds` of simulated time (rounded to whole steps), paced by
    /// [`Simulator::pacing`], and summarizes robot 0's motion over the run.
    pub fn run_for(&mut self, seconds: f64) -> RunSummary {
        let dt = self.clock().dt;
        let steps = (seconds / dt).round().max(0.0) as u64;
        let pacer = Pacer::new(self.pacing, dt);
        let start_com = self.com(0).unwrap_or_default();
        let start_step = self.clock().step;
        let wall = Instant::now();
        if pacer.is_paced() {
            for k in 1..=steps {
                self.run_steps(1);
                if let Some(wait) = pacer.due(k).checked_sub(wall.elapsed()) {
                    std::thread::sleep(wait);
                }
            }
        } else {
            self.run_steps(steps);
        }
        let end_com = self.com(0).unwrap_or_default();
        let done = self.clock().step - start_step;
        RunSummary::new(done, dt, wall.elapsed().as_secs_f64(), start_com, end_com)
    }
}
