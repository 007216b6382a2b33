//! Terrain shapes beyond a geometry's own: height fields, and the floor as a half-space.
//!
//! A `heightfield` geometry becomes rapier's `HeightField` over its OBJ's x-y grid (parry's
//! height fields lie in their x-z plane with y up, so the shape is turned to our z up).
//! With the `halfspace_floor` physics setting, a static box wide enough to be the floor
//! becomes a half-space at its top face (the robot never reaches the edge of a floor this
//! wide; the viewer still draws the box). Measured: 2.4 % more instructions per step than
//! the box on the reference scenario (parry's box-box contact is specialised,
//! box-half-space is not), so production keeps the box (docs/MEASUREMENTS.md).

use rapier3d::parry::utils::Array2;
use rapier3d::prelude as rp;

use super::pose;
use crate::config::body::{Geom, Shape};
use crate::config::mesh::HeightMap;
use crate::config::transform::Pose;

/// A height map scaled by `scale` as rapier's height field, and its placement in the
/// geometry's frame: the grid spans the map's x and y, heights along z.
pub fn heightfield(map: &HeightMap, scale: f64) -> (rp::SharedShape, rp::Pose) {
    // Parry: row r runs along its z (our -y after the turn), column c along x; the data is
    // column-major. Our y grows with j, so row r is node j = ny - 1 - r.
    let (rows, cols) = (map.ny, map.nx);
    let mut data = Vec::with_capacity(rows * cols);
    for c in 0..cols {
        data.extend((0..rows).map(|r| (map.at(c, rows - 1 - r) * scale) as f32));
    }
    let size = rp::Vector::new(
        ((map.x[1] - map.x[0]) * scale) as f32,
        1.0,
        ((map.y[1] - map.y[0]) * scale) as f32,
    );
    let centre = rp::Vector::new(
        ((map.x[0] + map.x[1]) / 2.0 * scale) as f32,
        ((map.y[0] + map.y[1]) / 2.0 * scale) as f32,
        0.0,
    );
    let y_up_to_z_up = rp::Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let shape = rp::SharedShape::heightfield(Array2::new(rows, cols, data), size);
    (shape, rp::Pose::from_parts(centre, y_up_to_z_up))
}

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

#[cfg(test)]
mod heightfield_tests {
    use super::*;
    use crate::config::mesh::HeightMap;
    use rapier3d::parry::query::Ray;

    /// Height of `shape` placed at `at` under (x, y), by a ray cast down from 10 m.
    fn height_under(shape: &rp::SharedShape, at: &rp::Pose, x: f32, y: f32) -> f32 {
        let ray = Ray::new(rp::Vector::new(x, y, 10.0), rp::Vector::new(0.0, 0.0, -1.0));
        let toi = shape.cast_ray(at, &ray, 100.0, true).unwrap();
        10.0 - toi
    }

    #[test]
    fn a_height_field_stands_where_its_map_says() {
        // 4 x 3 nodes over x 1..2.5, y -1..0: a distinct height at every node.
        let (nx, ny) = (4, 3);
        let heights = (0..nx * ny).map(|k| 0.1 + 0.01 * k as f64).collect();
        let map = HeightMap {
            x: [1.0, 2.5],
            y: [-1.0, 0.0],
            nx,
            ny,
            heights,
        };
        let (shape, at) = heightfield(&map, 2.0);
        for j in 0..ny {
            for i in 0..nx {
                // Nodes on the border are probed just inside it.
                let x = (2.0 * (1.0 + 0.5 * i as f32)).clamp(2.001, 4.999);
                let y = (2.0 * (-1.0 + 0.5 * j as f32)).clamp(-1.999, -0.001);
                let want = 2.0 * map.at(i, j) as f32;
                let got = height_under(&shape, &at, x, y);
                assert!(
                    (got - want).abs() < 1e-3,
                    "node ({i}, {j}): {got} vs {want}"
                );
            }
        }
    }
}
