//! Formulas on positions that every layer shares (control modules, the simulator, the
//! fitness functions, the data logger, the GUI's overlays): each is written once here.
//! Plain `f64` triples in the configuration's frame (metres, z up); no dependencies.

/// Distance between two points in the ground plane (m): thesis eq. 3.7's displacement when
/// `a` and `b` are the centre of mass at the start and at the end of a run.
pub fn ground_distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (dx * dx + dy * dy).sqrt()
}

/// Distance travelled from `a` to `b` along a heading in the ground plane (degrees
/// counter-clockwise from +x; m, negative when backwards).
pub fn distance_along(a: [f64; 3], b: [f64; 3], heading_deg: f64) -> f64 {
    let h = heading_deg.to_radians();
    (b[0] - a[0]) * h.cos() + (b[1] - a[1]) * h.sin()
}

/// How a path through `a`, `b` and `c` turns at `b` in the ground plane: the angle
/// between `b - a` and `c - b` (degrees, 0 straight on, 180 back); 0 when either leg is
/// shorter than `shortest` m (a path that hardly moves does not turn).
pub fn turn_deg(a: [f64; 3], b: [f64; 3], c: [f64; 3], shortest: f64) -> f64 {
    let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
    let (lu, lv) = (u[0].hypot(u[1]), v[0].hypot(v[1]));
    if lu < shortest || lv < shortest {
        return 0.0;
    }
    let cos = ((u[0] * v[0] + u[1] * v[1]) / (lu * lv)).clamp(-1.0, 1.0);
    cos.acos().to_degrees()
}

/// Length of a vector.
pub fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Potential energy (J) of `mass` kg at `position` under `gravity` (m/s², any direction):
/// `-m g·r`, which is `m |g| z` for gravity along -z.
pub fn potential_energy(mass: f64, position: [f64; 3], gravity: [f64; 3]) -> f64 {
    -mass * (gravity[0] * position[0] + gravity[1] * position[1] + gravity[2] * position[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ground_distance_ignores_height() {
        assert_eq!(ground_distance([1.0, 1.0, 0.0], [4.0, 5.0, 9.0]), 5.0);
    }

    #[test]
    fn a_path_turns_by_the_angle_between_its_legs() {
        let straight = turn_deg([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 5.0], 0.01);
        assert_eq!(straight, 0.0);
        let left = turn_deg([0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], 0.01);
        assert!((left - 90.0).abs() < 1e-9, "{left}");
        let back = turn_deg([0.0; 3], [1.0, 0.0, 0.0], [0.5, 0.0, 0.0], 0.01);
        assert!((back - 180.0).abs() < 1e-9, "{back}");
        assert_eq!(
            turn_deg([0.0; 3], [0.001, 0.0, 0.0], [0.0, 1.0, 0.0], 0.01),
            0.0
        );
    }

    #[test]
    fn distance_along_is_signed() {
        let d = distance_along([0.0; 3], [0.0, -3.0, 0.0], 90.0);
        assert!((d + 3.0).abs() < 1e-12, "{d}");
    }

    #[test]
    fn potential_energy_follows_the_world_gravity() {
        let mars = [0.0, 0.0, -3.71];
        assert!((potential_energy(2.0, [5.0, 1.0, 0.5], mars) - 2.0 * 3.71 * 0.5).abs() < 1e-12);
        assert_eq!(norm(mars), 3.71);
    }
}
