//! The families made of boxes and cylinders on a flat floor: `steps` (random steps up and
//! down), `stairs` (flights up, then down), `pegs` (a field of vertical cylinders),
//! `channel` (walls that narrow and bend) and `rubble` (random boxes). Every size is a
//! function of the difficulty named in its doc line.

use crate::config::terrain::course::{Course, FEATURES_FROM, START_PAD, yaw_of, yaw_towards};
use crate::config::terrain::field::smooth;
use crate::config::terrain::spec::{WALL_SAMPLE, peg_spacing, rubble_density};
use crate::config::transform::Pose;

/// Highest level a run of steps climbs to (m).
const HIGHEST_STEP: f64 = 0.3;

/// `steps`: treads 0.5-1.4 m long; each a rise or a drop of half to all of 1 cm
/// (difficulty 0) to 6 cm (1), never below the floor nor above 30 cm.
pub fn steps(c: &mut Course) {
    c.add_floor(0.0);
    let d = c.spec.difficulty;
    let highest = 0.01 + 0.05 * d;
    let (mut y, mut level) = (FEATURES_FROM, 0.0_f64);
    let mut n = 0;
    while y < c.spec.length {
        let tread = c.rng.range(0.5, 1.4);
        let rise = highest * c.rng.range(0.5, 1.0);
        let down = level - rise >= 0.0 && (level + rise > HIGHEST_STEP || c.rng.uniform() < 0.5);
        level += if down { -rise } else { rise };
        level_box(c, &mut n, y, tread, level);
        y += tread;
    }
    level_box(c, &mut n, y, super::course::END_PAD, level);
}

/// `stairs`: flights of 3-6 steps up, a landing, as many down, a flat stretch; rises of
/// 70-100 % of 1 cm (difficulty 0) to 6 cm (1), treads 0.45 m (0) to 0.21 m (1).
pub fn stairs(c: &mut Course) {
    c.add_floor(0.0);
    let d = c.spec.difficulty;
    let (mut y, mut n) = (FEATURES_FROM, 0);
    let mut level = 0.0;
    while y < c.spec.length {
        let count = 3 + (c.rng.uniform() * 4.0) as usize;
        let rise = (0.01 + 0.05 * d) * c.rng.range(0.7, 1.0);
        let tread = (0.45 - 0.24 * d) * c.rng.range(0.9, 1.1);
        for _ in 0..count {
            level += rise;
            level_box(c, &mut n, y, tread, level);
            y += tread;
        }
        let landing = c.rng.range(0.5, 1.5);
        level_box(c, &mut n, y, landing, level);
        y += landing;
        for _ in 0..count {
            level -= rise;
            level_box(c, &mut n, y, tread, level);
            y += tread;
        }
        level = 0.0;
        y += c.rng.range(1.0, 2.0);
    }
}

/// A box across the course from `y` for `len`, its top at `level` (none at the floor's).
fn level_box(c: &mut Course, n: &mut usize, y: f64, len: f64, level: f64) {
    if level <= 1e-6 {
        return;
    }
    let half = [c.half_width(), len / 2.0, level / 2.0];
    c.add_box(
        format!("step{n}"),
        [0.0, y + len / 2.0, level / 2.0],
        half,
        Pose::IDENTITY.rotation,
    );
    *n += 1;
}

/// Height of pegs and walls (m): higher than the shipped robots can climb.
const POST_HEIGHT: f64 = 0.2;

/// `pegs`: vertical cylinders of radius 1.5 cm (difficulty 0) to 4.5 cm (1) in rows
/// [`peg_spacing`] apart, each row's columns as far apart and shifted by a random fraction
/// of it (no lane runs straight down the field), each peg moved up to 0.2 spacings in x
/// and y.
pub fn pegs(c: &mut Course) {
    c.add_floor(0.0);
    let d = c.spec.difficulty;
    let (spacing, radius) = (peg_spacing(d), 0.015 + 0.03 * d);
    let half = c.half_width() - radius;
    let (mut y, mut n) = (FEATURES_FROM + spacing / 2.0, 0);
    while y < c.spec.length {
        // Each row's columns start at a random place: no lane runs straight down the field.
        let mut x = -half + c.rng.range(0.0, spacing);
        while x <= half {
            let jx = c.rng.range(-0.2, 0.2) * spacing;
            let jy = c.rng.range(-0.2, 0.2) * spacing;
            let at = [(x + jx).clamp(-half, half), y + jy];
            c.add_peg(format!("peg{n}"), at, radius, POST_HEIGHT);
            n += 1;
            x += spacing;
        }
        y += spacing;
    }
}

/// Thickness of a channel's walls (m).
const WALL: f64 = 0.04;
/// Spacing of the channel's bend control points (m).
const BEND_EVERY: f64 = 2.0;
/// How far a channel's wall may stray from its curve (m).
const WALL_TOLERANCE: f64 = 0.01;
/// Longest straight piece of a channel's wall (m).
const WALL_LONGEST: f64 = 4.0;

/// `channel`: two walls around a centre line that bends by up to 0.2 m (difficulty 0) to
/// 1.2 m (1) every [`BEND_EVERY`], and a gap that narrows from 1.2 m to 1 m (0) or 0.24 m (1)
/// along the course (±10 %).
pub fn channel(c: &mut Course) {
    c.add_floor(0.0);
    let d = c.spec.difficulty;
    let bend = 0.2 + 1.0 * d;
    let narrowest = 0.5 - 0.38 * d;
    let room = (c.half_width() - WALL).max(0.0);
    let knots = ((c.spec.length - FEATURES_FROM) / BEND_EVERY).ceil() as usize + 2;
    let centres: Vec<f64> = (0..knots)
        .map(|k| {
            if k == 0 {
                0.0
            } else {
                c.rng.range(-bend, bend)
            }
        })
        .collect();
    let wiggle: Vec<f64> = (0..knots).map(|_| c.rng.range(0.9, 1.1)).collect();
    let along = |y: f64, values: &[f64], start: f64| -> f64 {
        let t = ((y - FEATURES_FROM) / BEND_EVERY).max(0.0);
        let k = (t.floor() as usize).min(values.len() - 2);
        let (a, b) = (values[k], values[k + 1]);
        let a = if k == 0 { start } else { a };
        a + (b - a) * smooth(t - k as f64)
    };
    let half_gap = |y: f64| {
        let p = c.progress(y);
        let w = 0.6 + (narrowest - 0.6) * p;
        (w * along(y, &wiggle, 1.0)).min(room)
    };
    let centre = |y: f64| {
        let hg = half_gap(y);
        along(y, &centres, 0.0).clamp(-(room - hg).max(0.0), (room - hg).max(0.0))
    };
    let [_, y1] = c.y_range();
    let samples = ((y1 + START_PAD / 2.0) / WALL_SAMPLE).ceil() as usize;
    let walls: Vec<_> = [-1.0, 1.0]
        .into_iter()
        .flat_map(|side| {
            let curve: Vec<[f64; 2]> = (0..=samples)
                .map(|k| {
                    let y = (-START_PAD / 2.0 + WALL_SAMPLE * k as f64).min(y1);
                    [centre(y) + side * (half_gap(y) + WALL / 2.0), y]
                })
                .collect();
            wall_segments(&curve)
        })
        .collect();
    for (n, (a, b)) in walls.into_iter().enumerate() {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt();
        let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, POST_HEIGHT / 2.0];
        let half = [WALL / 2.0, len / 2.0 + WALL / 2.0, POST_HEIGHT / 2.0];
        c.add_box(format!("wall{n}"), mid, half, yaw_towards(dx, dy));
    }
}

/// A wall's polyline, sampled every [`WALL_SAMPLE`], as few straight segments as keep every
/// sample within [`WALL_TOLERANCE`] of its segment, none longer than [`WALL_LONGEST`]:
/// long where the channel runs straight, short in its bends (fewer bodies for the engines
/// to pose and test).
fn wall_segments(curve: &[[f64; 2]]) -> Vec<([f64; 2], [f64; 2])> {
    let fits = |a: usize, b: usize| {
        let (p, q) = (curve[a], curve[b]);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = (dx * dx + dy * dy).sqrt();
        len <= WALL_LONGEST
            && curve[a + 1..b]
                .iter()
                .all(|r| ((r[0] - p[0]) * dy - (r[1] - p[1]) * dx).abs() <= WALL_TOLERANCE * len)
    };
    let mut segments = Vec::new();
    let mut a = 0;
    while a + 1 < curve.len() {
        let mut b = a + 1;
        while b + 1 < curve.len() && fits(a, b + 1) {
            b += 1;
        }
        segments.push((curve[a], curve[b]));
        a = b;
    }
    segments
}

/// `rubble`: boxes at [`rubble_density`], 4-6 cm across (difficulty 0) to 4-20 cm (1),
/// 1-1.6 cm (0) to 1-7.6 cm (1) high, at any yaw, lying on the floor.
pub fn rubble(c: &mut Course) {
    c.add_floor(0.0);
    let d = c.spec.difficulty;
    let area = (c.spec.length - FEATURES_FROM) * c.spec.width;
    let count = (rubble_density(d) * area).round() as usize;
    for n in 0..count {
        let x = c.rng.range(-c.half_width(), c.half_width());
        let y = c.rng.range(FEATURES_FROM + 0.2, c.spec.length);
        let half = [
            c.rng.range(0.02, 0.03 + 0.07 * d),
            c.rng.range(0.02, 0.03 + 0.07 * d),
            c.rng.range(0.005, 0.008 + 0.03 * d),
        ];
        let yaw = yaw_of(c.rng.range(-1.0, 1.0));
        c.add_box(format!("rubble{n}"), [x, y, half[2]], half, yaw);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance of `r` from the line through `p` and `q`.
    fn off_line(r: [f64; 2], p: [f64; 2], q: [f64; 2]) -> f64 {
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        ((r[0] - p[0]) * dy - (r[1] - p[1]) * dx).abs() / (dx * dx + dy * dy).sqrt()
    }

    #[test]
    fn a_straight_wall_is_few_long_pieces_and_a_bent_one_follows_its_curve() {
        let line: Vec<[f64; 2]> = (0..=200).map(|k| [0.3, 0.05 * k as f64]).collect();
        let pieces = wall_segments(&line);
        assert_eq!(pieces.len(), 3, "10 m straight in pieces of at most 4 m");
        assert!(pieces.windows(2).all(|w| w[0].1 == w[1].0), "pieces join");
        // A bend as sharp as a hard channel's: 2 m across in 2 m of smoothstep.
        let bend: Vec<[f64; 2]> = (0..=80)
            .map(|k| {
                let y = 0.05 * k as f64;
                [2.0 * smooth(y / 2.0 - 0.5), y]
            })
            .collect();
        let pieces = wall_segments(&bend);
        assert!(pieces.len() < 40, "{} pieces for 80 samples", pieces.len());
        assert!(pieces.len() > 4, "{} pieces follow a bend", pieces.len());
        for r in &bend {
            let piece = pieces
                .iter()
                .find(|(p, q)| p[1] <= r[1] && r[1] <= q[1])
                .map(|&(p, q)| off_line(*r, p, q));
            assert!(piece.is_some_and(|d| d <= WALL_TOLERANCE + 1e-12), "{r:?}");
        }
    }
}
