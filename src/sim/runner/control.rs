//! Typed writes to a running world between steps: module parameters and kernels (the GUI's
//! properties dialog, the gamepad, the optimizers), the twin's joint override, and moving
//! bodies (the viewer's drag, perturbation tests).

use crate::control::ControlKernel;
use crate::sim::Simulator;
use crate::sim::engine::{BodyId, PhysicsEngine};
use crate::sim::error::SimError;
use crate::sim::kernel::{JointOverride, Kernel};
use crate::sim::physics::SimPhysics;

impl Simulator {
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
        let mut kernel = self.robot_component_mut::<Kernel>(robot)?;
        Ok(kernel.0.set_parameter(actuator, name, joint, value)?)
    }

    /// The control kernel of robot `index`, to change between steps (parameters,
    /// distortions, perturbations; see [`ControlKernel`]).
    pub fn kernel_mut(&mut self, index: usize) -> Result<&mut ControlKernel, SimError> {
        self.robot_component_mut::<Kernel>(index)
            .map(|k| &mut k.into_inner().0)
    }

    /// Makes robot `index`'s servos follow `angles` (degrees, one per joint) instead of
    /// its kernel — the twin of a real robot — or the kernel again with `None`.
    pub fn set_joint_override(
        &mut self,
        index: usize,
        angles: Option<Vec<f64>>,
    ) -> Result<(), SimError> {
        let e = self.robot(index)?;
        let mut entity = self.world_mut().entity_mut(e);
        match angles {
            Some(a) => match entity.get_mut::<JointOverride>() {
                Some(mut o) => {
                    o.0.clear();
                    o.0.extend_from_slice(&a);
                }
                None => {
                    entity.insert(JointOverride(a));
                }
            },
            None => {
                entity.remove::<JointOverride>();
            }
        }
        Ok(())
    }

    /// Moves `bodies` by `delta` metres (z up) between steps, keeping their velocities and
    /// orientations (the viewer's drag); unknown handles are skipped.
    pub fn translate_bodies(&mut self, bodies: &[BodyId], delta: [f64; 3]) {
        if !delta.iter().all(|d| d.is_finite()) {
            return;
        }
        let mut physics = self.world_mut().resource_mut::<SimPhysics>();
        for b in bodies {
            physics.engine.translate_body(*b, delta);
        }
    }

    /// Sets the linear velocity (m/s, z up) of link `link` of robot `robot` between steps:
    /// a launch (the physical checks' sliding module). On MuJoCo only a robot's root link
    /// (its free joint) can be set.
    pub fn set_link_velocity(
        &mut self,
        robot: usize,
        link: usize,
        linvel: [f64; 3],
    ) -> Result<(), SimError> {
        self.with_link_body(robot, link, linvel, |engine, body, v| {
            engine.set_linear_velocity(body, v)
        })
    }

    /// Sets the angular velocity (rad/s, z up) of link `link` of robot `robot` between
    /// steps: a push from outside, to test servos and limits.
    pub fn set_link_angular_velocity(
        &mut self,
        robot: usize,
        link: usize,
        angvel: [f64; 3],
    ) -> Result<(), SimError> {
        self.with_link_body(robot, link, angvel, |engine, body, w| {
            engine.set_angular_velocity(body, w)
        })
    }

    /// Hands link `link`'s body of robot `robot` and `value` to `set`, when every component
    /// of `value` is finite.
    fn with_link_body(
        &mut self,
        robot: usize,
        link: usize,
        value: [f64; 3],
        set: impl FnOnce(&mut dyn PhysicsEngine, BodyId, [f64; 3]),
    ) -> Result<(), SimError> {
        let body = self.link_body(robot, link)?;
        if value.iter().all(|v| v.is_finite()) {
            let mut physics = self.world_mut().resource_mut::<SimPhysics>();
            set(physics.engine.as_mut(), body, value);
        }
        Ok(())
    }
}
