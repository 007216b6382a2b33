//! Tactile pads in the world. A pad is an area on its link's surface, not a collider of
//! its own: it reads the contact points of its link's colliders, and is touched when a
//! contact patch (the box around one contact manifold's points) overlaps the pad's box.
//! A touch by anything outside its own body (terrain, another robot) reads pressed once
//! it has lasted its debounce steps. Forces are not measured, as in the thesis (5.1); the
//! contact normal is. Runs in the `Sense` set and fills each robot's [`RobotSensors`].
//!
//! Reading the link's own contacts instead of giving each pad a collider saves the
//! narrow phase and the solver a pad's contacts (docs/DESIGN.md §3 has the figures).

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::sensing::{Debounce, SensorData};
use crate::sim::physics::{SimPhysics, arr3};

/// One tactile pad.
#[derive(Component, Debug, Clone)]
pub struct TactileSensor {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's tactile pads.
    pub index: usize,
    /// The link it sits on.
    pub link: rp::RigidBodyHandle,
    /// Its area: pose in the link's frame and half-extents.
    pub area: PadArea,
    /// The link's colliders, each with the map from its frame to the pad's.
    pub colliders: Vec<(rp::ColliderHandle, rp::Pose)>,
    /// Steps a new state must last before it is reported.
    pub debounce_steps: u32,
    /// Debounce state of the reading.
    pub state: Debounce,
    /// Whether a contact exists this step, before debouncing.
    pub raw: bool,
}

/// Where a pad is on its link: a box, posed in the link's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PadArea {
    /// Pose of the box in the link's frame.
    pub pose: rp::Pose,
    /// Half-extents of the box (m).
    pub half_extents: rp::Vector,
}

impl PadArea {
    /// How far (m) a contact patch may lie outside the box and still touch it: a tenth of
    /// the pad's thinnest half-extent, for the rounding of points on the box's faces.
    pub fn tolerance(&self) -> f32 {
        0.1 * self.half_extents.min_element()
    }

    /// Whether the box spanned by `points` (in the pad's frame) overlaps the pad.
    pub fn touched_by(&self, mut points: impl Iterator<Item = rp::Vector>) -> bool {
        let Some(first) = points.next() else {
            return false;
        };
        let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        let reach = self.half_extents + rp::Vector::splat(self.tolerance());
        lo.cmple(reach).all() && hi.cmpge(-reach).all()
    }

    /// Whether the pad lies on a collider whose frame maps to the pad's by `to_pad`: the
    /// collider's bounding box in the pad's frame overlaps the pad.
    pub fn lies_on(&self, shape: &dyn rp::Shape, to_pad: &rp::Pose) -> bool {
        let aabb = shape.compute_aabb(to_pad);
        self.touched_by([aabb.mins, aabb.maxs].into_iter())
    }
}

/// The latest sensor readings of a robot, given to its control kernel.
#[derive(Component, Debug, Clone, Default, PartialEq)]
pub struct RobotSensors(pub SensorData);

/// Raw contact of a pad and its normal (unit, from the touched surface into the pad).
pub fn pad_contact(narrow: &rp::NarrowPhase, pad: &TactileSensor) -> (bool, [f64; 3]) {
    let mut normal = rp::Vector::ZERO;
    let mut touching = false;
    for (collider, to_pad) in &pad.colliders {
        for pair in narrow.contact_pairs_with(*collider) {
            if !pair.has_any_active_contact() {
                continue;
            }
            let ours_first = pair.collider1 == *collider;
            for m in pair.manifolds() {
                let points = m.points.iter().map(|c| {
                    let local = if ours_first {
                        m.subshape_pos1()
                            .map_or(c.local_p1, |p| p.transform_point(c.local_p1))
                    } else {
                        m.subshape_pos2()
                            .map_or(c.local_p2, |p| p.transform_point(c.local_p2))
                    };
                    to_pad.transform_point(local)
                });
                if pad.area.touched_by(points) {
                    touching = true;
                    normal += if ours_first {
                        -m.data.normal
                    } else {
                        m.data.normal
                    };
                }
            }
        }
    }
    (touching, arr3(normal.normalize_or_zero()))
}

/// Updates every pad and the robots' sensor readings (part of the `Sense` set).
pub fn sense_tactile(
    physics: Res<SimPhysics>,
    mut pads: Query<&mut TactileSensor>,
    mut robots: Query<&mut RobotSensors>,
) {
    let narrow = &physics.world.narrow_phase;
    for mut pad in &mut pads {
        let (raw, normal) = pad_contact(narrow, &pad);
        pad.raw = raw;
        let steps = pad.debounce_steps;
        let pressed = pad.state.update(raw, steps);
        if let Ok(mut sensors) = robots.get_mut(pad.robot) {
            let i = pad.index;
            if let Some(p) = sensors.0.tactile.get_mut(i) {
                *p = pressed;
            }
            if let Some(n) = sensors.0.tactile_normals.get_mut(i) {
                *n = if pressed { normal } else { [0.0; 3] };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pad() -> PadArea {
        PadArea {
            pose: rp::Pose::IDENTITY,
            half_extents: rp::Vector::new(0.012, 0.015, 0.003),
        }
    }

    fn v(x: f32, y: f32, z: f32) -> rp::Vector {
        rp::Vector::new(x, y, z)
    }

    #[test]
    fn a_patch_wider_than_the_pad_touches_it() {
        // A sole lying flat: contact points at its corners, outside the pad in x.
        let corners = [v(-0.022, -0.03, -0.003), v(0.022, 0.03, -0.003)];
        assert!(pad().touched_by(corners.into_iter()));
    }

    #[test]
    fn a_patch_beside_the_pad_or_above_it_does_not() {
        let beside = [v(-0.022, 0.02, -0.003), v(0.022, 0.03, -0.003)];
        assert!(!pad().touched_by(beside.into_iter()));
        let above = [v(0.0, 0.0, 0.01)];
        assert!(!pad().touched_by(above.into_iter()));
        assert!(!pad().touched_by(std::iter::empty()));
    }

    #[test]
    fn points_on_the_face_touch_within_the_tolerance() {
        let on_face = [v(0.0, 0.0, -0.003 - 0.0002)];
        assert!(pad().touched_by(on_face.into_iter()));
        let below = [v(0.0, 0.0, -0.003 - 0.0005)];
        assert!(!pad().touched_by(below.into_iter()));
    }
}
