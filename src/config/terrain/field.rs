//! The height-field families: `rough` (fractal value noise), `hills` (experiment 2's hump,
//! plateau with a trough, and trough, repeated with random sizes) and `slope` (inclines up
//! and down with bumps). Each is a height function of (x, y), 0 on the start pad and eased
//! in over the first half metre of features, sampled by [`Course::add_field`].

use crate::config::terrain::course::{Course, FEATURES_FROM};
use crate::rng::SimRng;

/// Smoothstep: 0 below 0, 1 above 1, C¹ between.
pub fn smooth(t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A bump on [0, 1]: 0 at the ends, 1 in the middle, flat at both ends (16 u² (1-u)²).
fn bump(u: f64) -> f64 {
    if (0.0..=1.0).contains(&u) {
        16.0 * u * u * (1.0 - u) * (1.0 - u)
    } else {
        0.0
    }
}

/// The ease-in of the features: 0 on the start pad, 1 from half a metre into them.
fn ease_in(y: f64) -> f64 {
    smooth((y - FEATURES_FROM) / 0.5)
}

/// Value noise: random values on a unit lattice, blended by smoothstep.
struct Lattice {
    nx: usize,
    values: Vec<f64>,
}

impl Lattice {
    fn new(rng: &mut SimRng, nx: usize, ny: usize) -> Self {
        let values = (0..nx * ny).map(|_| rng.range(-1.0, 1.0)).collect();
        Lattice { nx, values }
    }

    /// The noise at lattice coordinates (u, v) >= 0.
    fn at(&self, u: f64, v: f64) -> f64 {
        let (i, j) = (u.floor() as usize, v.floor() as usize);
        let (fu, fv) = (smooth(u - i as f64), smooth(v - j as f64));
        let get = |a: usize, b: usize| {
            let k = (b * self.nx + a).min(self.values.len() - 1);
            self.values[k]
        };
        let top = get(i, j) + (get(i + 1, j) - get(i, j)) * fu;
        let bottom = get(i, j + 1) + (get(i + 1, j + 1) - get(i, j + 1)) * fu;
        top + (bottom - top) * fv
    }
}

/// Octaves of the rough family's noise: the finest lattice is at least two grid cells long
/// (20 cm at difficulty 1), so every lattice value and the blend between two of them is
/// sampled.
const OCTAVES: usize = 3;

/// `rough`: amplitude 1 cm (difficulty 0) to 6 cm (1); base wavelength 2 m to 0.8 m;
/// three octaves, each half the wavelength and half the amplitude.
pub fn rough(c: &mut Course) {
    let d = c.spec.difficulty;
    let amplitude = 0.01 + 0.05 * d;
    let wavelength = 2.0 - 1.2 * d;
    let [y0, y1] = c.y_range();
    let (x0, span_x, span_y) = (-c.half_width(), c.spec.width, y1 - y0);
    let mut octaves = Vec::with_capacity(OCTAVES);
    for o in 0..OCTAVES {
        let scale = wavelength / (1u32 << o) as f64;
        let nx = (span_x / scale).ceil() as usize + 2;
        let ny = (span_y / scale).ceil() as usize + 2;
        octaves.push((
            scale,
            0.5f64.powi(o as i32),
            Lattice::new(&mut c.rng, nx, ny),
        ));
    }
    let norm: f64 = octaves.iter().map(|o| o.1).sum();
    c.add_field(|x, y| {
        let n: f64 = octaves
            .iter()
            .map(|(scale, weight, lattice)| {
                weight * lattice.at(((x - x0) / scale).max(0.0), ((y - y0) / scale).max(0.0))
            })
            .sum();
        2.0 * amplitude * n / norm * ease_in(y)
    });
}

/// One obstacle of the hills family, along y.
enum Hill {
    /// A convex hump of this height.
    Hump(f64),
    /// A plateau of this height with a concave trough in its top.
    Plateau(f64),
    /// A trough this deep.
    Trough(f64),
}

/// `hills`: obstacles half to all of 3 cm (difficulty 0) to 28 cm (1) high, 0.8-2 m long,
/// with flat gaps between them that shrink with the difficulty.
pub fn hills(c: &mut Course) {
    let d = c.spec.difficulty;
    let highest = 0.03 + 0.25 * d;
    let mut features = Vec::new();
    let mut y = FEATURES_FROM + 0.5;
    while y < c.spec.length {
        let h = highest * c.rng.range(0.5, 1.0);
        let kind = match (c.rng.uniform() * 3.0) as u32 {
            0 => Hill::Hump(h),
            1 => Hill::Plateau(h),
            _ => Hill::Trough(0.7 * h),
        };
        let len = c.rng.range(0.8, 2.0);
        features.push((y, len, kind));
        y += len + c.rng.range(0.3, 1.2) * (1.3 - d);
    }
    c.add_field(|_, y| {
        features
            .iter()
            .map(|(at, len, kind)| hill(kind, (y - at) / len))
            .sum()
    });
}

/// A hill's height at `u` in [0, 1] along it.
fn hill(kind: &Hill, u: f64) -> f64 {
    if !(0.0..=1.0).contains(&u) {
        return 0.0;
    }
    match *kind {
        Hill::Hump(h) => h * bump(u),
        Hill::Trough(h) => -h * bump(u),
        Hill::Plateau(h) => {
            let edge = smooth(u / 0.25) * smooth((1.0 - u) / 0.25);
            h * edge - 0.5 * h * bump((u - 0.35) / 0.3)
        }
    }
}

/// `slope`: inclines of grade 0.07 (4°, difficulty 0) to 0.36 (20°, 1), 1.5-3.5 m long, up
/// and down within ±1.5 m of the start's level, with bumps 0.5 cm to 3 cm high.
pub fn slope(c: &mut Course) {
    let d = c.spec.difficulty;
    let steepest = 0.07 + 0.29 * d;
    let mut knots = vec![(FEATURES_FROM, 0.0)];
    let (mut y, mut h) = (FEATURES_FROM, 0.0);
    while y < c.spec.length {
        let len = c.rng.range(1.5, 3.5);
        let grade = steepest * c.rng.range(0.5, 1.0);
        let up = if h <= -1.0 {
            true
        } else if h >= 1.0 {
            false
        } else {
            c.rng.uniform() < 0.5
        };
        h += if up { grade * len } else { -grade * len };
        y += len;
        knots.push((y, h));
    }
    let bump_height = 0.005 + 0.025 * d;
    let count = ((c.spec.length - FEATURES_FROM) * 0.6 * c.spec.width / 3.0).ceil() as usize;
    let bumps: Vec<[f64; 3]> = (0..count)
        .map(|_| {
            let x = c.rng.range(-c.half_width(), c.half_width());
            let y = c.rng.range(FEATURES_FROM + 0.5, c.spec.length);
            [x, y, c.rng.range(0.15, 0.4)]
        })
        .collect();
    c.add_field(|x, y| {
        let base = profile(&knots, y);
        let extra: f64 = bumps
            .iter()
            .filter(|b| (y - b[1]).abs() < b[2])
            .map(|b| {
                let r2 = ((x - b[0]) * (x - b[0]) + (y - b[1]) * (y - b[1])) / (b[2] * b[2]);
                if r2 < 1.0 {
                    (1.0 - r2) * (1.0 - r2)
                } else {
                    0.0
                }
            })
            .sum();
        base + bump_height * extra
    });
}

/// The piecewise-linear height through `knots` at `y` (flat before the first and after
/// the last).
fn profile(knots: &[(f64, f64)], y: f64) -> f64 {
    match knots.iter().position(|k| k.0 > y) {
        None => knots.last().map_or(0.0, |k| k.1),
        Some(0) => knots[0].1,
        Some(i) => {
            let (a, b) = (knots[i - 1], knots[i]);
            a.1 + (b.1 - a.1) * (y - a.0) / (b.0 - a.0)
        }
    }
}
