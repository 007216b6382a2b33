//! The physics world: rapier3d's bodies, colliders and joints, owned by one resource and
//! stepped once per simulation step. Coordinates are the configuration's (metres, z up);
//! the viewer turns them into Bevy's y-up frame.
//!
//! We drive rapier directly instead of through bevy_rapier's plugin: the fixed-step
//! pipeline needs physics as one set among ours, and headless runs must not pay for
//! syncing transforms nobody looks at (see docs/DESIGN.md §7).

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::sim::physics_settings::PhysicsSettings;

/// Most robots one world can hold (one collision group each, besides the environment).
pub const MAX_ROBOTS_PER_WORLD: usize = 31;

/// rapier's world, and the settings of the run.
#[derive(Resource)]
pub struct SimPhysics {
    /// rapier's bodies, colliders, joints, contacts and integration parameters.
    pub world: rp::PhysicsWorld,
    /// How it integrates a simulation step.
    pub settings: PhysicsSettings,
}

impl SimPhysics {
    /// A world with gravity (m/s², z up), simulation step width `dt` (s) and `settings`.
    pub fn new(gravity: [f64; 3], dt: f64, settings: PhysicsSettings) -> Self {
        let world = rp::PhysicsWorld {
            gravity: vec3(gravity),
            integration_parameters: settings.integration_parameters(dt),
            ..Default::default()
        };
        SimPhysics { world, settings }
    }

    /// Duration of the last solver substep (s): the servos' torque is its motor impulse
    /// divided by it.
    pub fn substep_duration(&self) -> f64 {
        let p = &self.world.integration_parameters;
        p.dt as f64 / p.num_solver_iterations.max(1) as f64
    }
}

/// Bit of collision group `g`: group 0 is the environment, robot `i` of a batch uses `i + 1`.
pub fn group_bit(g: u32) -> rp::Group {
    rp::Group::from_bits_truncate(1u32 << g)
}

/// f64 triple to rapier's vector.
pub fn vec3(v: [f64; 3]) -> rp::Vector {
    rp::Vector::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// Rapier's vector to an f64 triple.
pub fn arr3(v: rp::Vector) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// Configuration pose (translation, quaternion w x y z) to rapier's pose.
pub fn pose(t: &crate::config::transform::Pose) -> rp::Pose {
    let [w, x, y, z] = t.rotation;
    rp::Pose::from_parts(
        vec3(t.translation),
        rp::Rotation::from_xyzw(x as f32, y as f32, z as f32, w as f32).normalize(),
    )
}

/// The physics step (the `Physics` set of the pipeline): one rapier step, or several when
/// the settings refine the simulation step (converged references).
pub fn step_physics(mut physics: ResMut<SimPhysics>) {
    for _ in 0..physics.settings.steps_per_step {
        physics.world.step();
    }
}
