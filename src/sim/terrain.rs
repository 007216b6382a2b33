//! Alternative terrain shapes: with the `halfspace_floor` physics setting, a static box wide
//! enough to be the floor becomes a half-space at its top face (the robot never reaches the
//! edge of a floor this wide; the viewer still draws the box). Measured: 2.4 % more
//! instructions per step than the box on the reference scenario (parry's box-box contact is
//! specialised, box-half-space is not), so production keeps the box (DESIGN.md §3).

use rapier3d::prelude as rp;

use crate::config::body::{Geom, Shape};
use crate::config::transform::Pose;
use crate::sim::physics::pose;

/// Half-extent (m) in x and in y from which a static box with a horizontal top face is the
/// floor (the shipped floors are 8 m).
pub const FLOOR_MIN_HALF_EXTENT: f64 = 4.0;

/// For a geometry of a static body placed at `body`: when it is a floor box, a half-space
/// whose boundary is the box's top face, and its placement in the body's frame.
pub fn floor_halfspace(body: &Pose, g: &Geom) -> Option<(rp::SharedShape, rp::Pose)> {
    let Shape::Box { extents: [x, y, z] } = g.shape else {
        return None;
    };
    let up = body.mul(&g.pose).rotate([0.0, 0.0, 1.0]);
    let horizontal = up[2] > 1.0 - 1e-9;
    if !(horizontal && x >= FLOOR_MIN_HALF_EXTENT && y >= FLOOR_MIN_HALF_EXTENT) {
        return None;
    }
    let top = g.pose.mul(&Pose::from_translation([0.0, 0.0, z]));
    Some((rp::SharedShape::halfspace(rp::Vector::Z), pose(&top)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::body::Geom;

    fn geom(extents: [f64; 3], pose: Pose) -> Geom {
        Geom {
            shape: Shape::Box { extents },
            pose,
            diffuse_color: None,
            ambient_color: None,
            transparency: None,
            friction: None,
            visible: true,
            pos: crate::config::error::Pos::new(0, 0),
        }
    }

    #[test]
    fn a_wide_horizontal_box_is_a_floor_at_its_top_face() {
        let body = Pose::from_translation([0.0, 0.0, -0.003]);
        let (shape, at) =
            floor_halfspace(&body, &geom([8.0, 8.0, 0.003], Pose::default())).unwrap();
        assert!(shape.as_halfspace().is_some());
        assert!((at.translation.z - 0.003).abs() < 1e-7, "{at:?}");
    }

    #[test]
    fn small_or_tilted_boxes_stay_boxes() {
        let flat = Pose::default();
        assert!(floor_halfspace(&flat, &geom([0.5, 8.0, 0.1], flat)).is_none());
        let tilted = Pose {
            rotation: [0.9659, 0.2588, 0.0, 0.0],
            ..Pose::default()
        };
        assert!(floor_halfspace(&tilted, &geom([8.0, 8.0, 0.1], flat)).is_none());
    }
}
