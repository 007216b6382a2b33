//! Typed reads of a running world: where each robot is, what its joints, sensors and
//! servos report, and a read-only view of the bodies and contacts for drawing and picking.

use bevy::prelude::Component;

use crate::config::simulation::EngineKind;
use crate::control::ControlKernel;
use crate::sensing::SensorData;
use crate::sim::Simulator;
use crate::sim::energy::Energy;
use crate::sim::engine::{BodyId, BodyState, PadArea, PhysicsEngine};
use crate::sim::error::SimError;
use crate::sim::kernel::Kernel;
use crate::sim::physics::SimPhysics;
use crate::sim::record::{Track, centre_of_mass, heading};
use crate::sim::robot::SimRobot;
use crate::sim::servo::{JointState, Servo};
use crate::sim::spawn::{SimEnvObject, SimLink};
use crate::sim::tactile::{RobotSensors, SimPad};

/// A body of the scene: an environment object or a robot link, with its engine body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneBody {
    /// Index among the environment's bodies, or among the robot's links.
    pub index: usize,
    /// The engine's body.
    pub body: BodyId,
}

/// One tactile pad of a robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PadReading {
    /// Index among the robot's pads (the order of `SensorData::tactile`).
    pub index: usize,
    /// The link it sits on.
    pub link: BodyId,
    /// Its area on the link.
    pub area: PadArea,
    /// Contact this step, before debouncing.
    pub raw: bool,
    /// The debounced reading modules see.
    pub pressed: bool,
}

/// Things listed in the order of their index.
trait Indexed {
    fn index(&self) -> usize;
}

impl Indexed for SceneBody {
    fn index(&self) -> usize {
        self.index
    }
}

impl Indexed for PadReading {
    fn index(&self) -> usize {
        self.index
    }
}

impl Simulator {
    /// A read-only view of the physics engine (bodies, colliders, contacts) for drawing
    /// and picking; changes go through the typed writes.
    pub fn engine(&self) -> &dyn PhysicsEngine {
        self.world().resource::<SimPhysics>().engine.as_ref()
    }

    /// The height (m) of the first surface straight below (x, y): the terrain's, where no
    /// robot is above it; `None` over nothing.
    pub fn height_below(&self, x: f64, y: f64) -> Option<f64> {
        self.engine().height_below(x, y)
    }

    /// Which engine steps this world.
    pub fn engine_kind(&self) -> EngineKind {
        self.engine().kind()
    }

    /// Centre of mass of robot `index` (m, z up).
    pub fn com(&self, index: usize) -> Result<[f64; 3], SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        Ok(centre_of_mass(self.engine(), robot))
    }

    /// Tail-to-head heading of robot `index` in the ground plane (degrees from +x).
    pub fn heading(&self, index: usize) -> Result<f64, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        Ok(heading(self.engine(), robot))
    }

    /// Gravity's direction in the frame of robot `index`'s head (unit).
    pub fn gravity_in_head(&self, index: usize) -> Result<[f64; 3], SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        Ok(crate::sim::record::gravity_in_head(self.engine(), robot))
    }

    /// The robot's mass (kg): the sum of its links'.
    pub fn mass(&self, index: usize) -> Result<f64, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        Ok(robot.bodies.iter().map(|(_, m)| m).sum())
    }

    /// The world's gravity (m/s², z up), as the environment file sets it.
    pub fn gravity(&self) -> [f64; 3] {
        self.engine().gravity()
    }

    /// The current state of every joint of robot `index`.
    pub fn joint_states(&self, index: usize) -> Result<Vec<JointState>, SimError> {
        let mut out = Vec::new();
        self.joint_states_into(index, &mut out)?;
        Ok(out)
    }

    /// [`Simulator::joint_states`] into `out` (cleared first; no allocation once `out` has
    /// room), for readers that run every control period.
    pub fn joint_states_into(
        &self,
        index: usize,
        out: &mut Vec<JointState>,
    ) -> Result<(), SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let w = self.world();
        out.clear();
        out.extend(
            robot
                .joints
                .iter()
                .map(|j| w.get::<JointState>(*j).copied().unwrap_or_default()),
        );
        Ok(())
    }

    /// Each joint's angle and speed of robot `index` as the engine has them now (after the
    /// last physics step: what the next step's sensing will read), degrees and degrees/s,
    /// into `angles` and `speeds` (cleared first; no allocation once they have room).
    pub fn joint_motion_into(
        &self,
        index: usize,
        angles: &mut Vec<f64>,
        speeds: &mut Vec<f64>,
    ) -> Result<(), SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let (w, engine) = (self.world(), self.engine());
        angles.clear();
        speeds.clear();
        for j in &robot.joints {
            let r = w
                .get::<crate::sim::servo::SimJoint>(*j)
                .map(|s| engine.joint(s.id));
            angles.push(r.as_ref().map_or(0.0, |r| r.angle));
            speeds.push(r.as_ref().map_or(0.0, |r| r.velocity));
        }
        Ok(())
    }

    /// The servo targets (degrees) of robot `index`'s joints, as the last step drove them.
    pub fn servo_targets(&self, index: usize) -> Result<Vec<f64>, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let w = self.world();
        Ok(robot
            .joints
            .iter()
            .map(|j| w.get::<Servo>(*j).map_or(0.0, |s| s.target))
            .collect())
    }

    /// How far robot `index`'s joints are from their servo targets now: the mean of
    /// |target - angle| over its joints (degrees).
    pub fn tracking_error(&self, index: usize) -> Result<f64, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        let w = self.world();
        let sum: f64 = robot
            .joints
            .iter()
            .filter_map(|j| Some((w.get::<Servo>(*j)?, w.get::<JointState>(*j)?)))
            .map(|(servo, state)| (servo.target - state.angle).abs())
            .sum();
        Ok(sum / robot.joints.len().max(1) as f64)
    }

    /// The latest sensor readings of robot `index`, as its modules see them.
    pub fn sensors(&self, index: usize) -> Result<&SensorData, SimError> {
        self.robot_component::<RobotSensors>(index).map(|s| &s.0)
    }

    /// Every tactile pad of robot `index`, in pad order, raw and debounced.
    pub fn tactile_pads(&self, index: usize) -> Result<Vec<PadReading>, SimError> {
        let robot = self.robot(index)?;
        Ok(self.collect_sorted(|p: &SimPad| {
            (p.robot == robot).then_some(PadReading {
                index: p.index,
                link: p.link,
                area: p.area,
                raw: p.raw,
                pressed: p.state.pressed,
            })
        }))
    }

    /// Power and energy robot `index`'s servos put out so far.
    pub fn energy(&self, index: usize) -> Result<Energy, SimError> {
        self.robot_component::<Energy>(index).copied()
    }

    /// The recorded trajectory of robot `index`.
    pub fn track(&self, index: usize) -> Result<&Track, SimError> {
        self.robot_component::<Track>(index)
    }

    /// The control kernel of robot `index`.
    pub fn kernel(&self, index: usize) -> Result<&ControlKernel, SimError> {
        self.robot_component::<Kernel>(index).map(|k| &k.0)
    }

    /// The environment's bodies, in the environment's order.
    pub fn environment_bodies(&self) -> Vec<SceneBody> {
        self.collect_sorted(|o: &SimEnvObject| {
            Some(SceneBody {
                index: o.index,
                body: o.body,
            })
        })
    }

    /// The link bodies of robot `index`, in link order.
    pub fn links(&self, index: usize) -> Result<Vec<SceneBody>, SimError> {
        let robot = self.robot(index)?;
        Ok(self.collect_sorted(|l: &SimLink| {
            (l.robot == robot).then_some(SceneBody {
                index: l.index,
                body: l.body,
            })
        }))
    }

    /// What `pick` takes from every entity with a `C`, sorted by its index.
    fn collect_sorted<C: Component, T: Indexed>(&self, pick: impl Fn(&C) -> Option<T>) -> Vec<T> {
        let w = self.world();
        let mut out: Vec<T> = w
            .try_query::<&C>()
            .map(|mut q| q.iter(w).filter_map(&pick).collect())
            .unwrap_or_default();
        out.sort_by_key(T::index);
        out
    }

    /// How many links robot `index` has.
    pub fn link_count(&self, index: usize) -> Result<usize, SimError> {
        Ok(self.robot_component::<SimRobot>(index)?.bodies.len())
    }

    /// The body of link `link` of robot `robot` (no allocation, unlike
    /// [`Simulator::links`]).
    pub fn link_body(&self, robot: usize, link: usize) -> Result<BodyId, SimError> {
        let bodies = &self.robot_component::<SimRobot>(robot)?.bodies;
        bodies
            .get(link)
            .map(|(b, _)| *b)
            .ok_or(SimError::NoSuchLink {
                link,
                count: bodies.len(),
            })
    }

    /// The link bodies of robot `index`, in link order (ids only).
    pub fn robot_bodies(&self, index: usize) -> Result<Vec<BodyId>, SimError> {
        let robot = self.robot_component::<SimRobot>(index)?;
        Ok(robot.bodies.iter().map(|(b, _)| *b).collect())
    }

    /// Position of a body (m, z up).
    pub fn body_position(&self, body: BodyId) -> Option<[f64; 3]> {
        self.engine().body(body).map(|b| b.pose.translation)
    }

    /// Pose, centre of mass, velocity and mass of a body.
    pub fn body_state(&self, body: BodyId) -> Option<BodyState> {
        self.engine().body(body)
    }

    /// Whether the physics blew up and the world stopped ([`PhysicsEngine::diverged`]).
    pub fn diverged(&self) -> bool {
        self.engine().diverged()
    }
}
