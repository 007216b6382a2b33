//! The one rule for a robot that can no longer be scored where it is: it left the world
//! (its centre of mass below the scenery or beyond its sides) or the physics diverged (a
//! centre of mass or servo energy that is not a number, an engine that stopped, or a robot
//! flung farther than any crawl goes: what would make its score not a number). Only the episode runner ([`crate::sim::episode`]) applies it.

use crate::measure::ground_distance;
use crate::sim::Simulator;
use crate::sim::engine::ShapeOutline;
use crate::sim::error::SimError;

/// How far beyond the scenery a robot's centre of mass has left the world (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldMargin {
    /// Below the lowest static collider.
    pub below: f64,
    /// Beyond the scenery's sides.
    pub beside: f64,
}

/// The margins of every episode.
pub const WORLD_MARGIN: WorldMargin = WorldMargin {
    below: 1.0,
    beside: 2.0,
};

/// Without scenery, this far below its start a robot has left the world (m).
const FALL_WITHOUT_SCENERY: f64 = 10.0;

/// Farther than this from its start (m) a robot's physics blew up.
pub const BLOW_UP_DISTANCE: f64 = 1000.0;

/// How a robot left the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WorldExit {
    /// Its centre of mass (m) is below the scenery or beyond its sides.
    Left([f64; 3]),
    /// The physics diverged.
    Diverged,
}

/// The box holding every static collider of a world (its ground and fixed scenery; m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenery {
    /// The lowest corner.
    pub lo: [f64; 3],
    /// The highest corner.
    pub hi: [f64; 3],
}

impl Scenery {
    /// The scenery of `sim`'s world, or `None` when nothing is static.
    pub fn of(sim: &Simulator) -> Option<Scenery> {
        let mut out: Option<Scenery> = None;
        for c in sim.engine().colliders().iter().filter(|c| !c.dynamic) {
            let (lo, hi) = match c.shape {
                ShapeOutline::Box(h) => {
                    // The rotated box's extent along each world axis.
                    let mut e = [0.0; 3];
                    for (axis, half) in h.iter().enumerate() {
                        let mut local = [0.0; 3];
                        local[axis] = *half;
                        let w = c.pose.rotate(local);
                        for (ek, wk) in e.iter_mut().zip(w) {
                            *ek += wk.abs();
                        }
                    }
                    let t = c.pose.translation;
                    (
                        std::array::from_fn(|k| t[k] - e[k]),
                        std::array::from_fn(|k| t[k] + e[k]),
                    )
                }
                ShapeOutline::Sphere(r) => {
                    let t = c.pose.translation;
                    (t.map(|v| v - r), t.map(|v| v + r))
                }
                ShapeOutline::Bounds(lo, hi) => (lo, hi),
            };
            out = Some(match out {
                None => Scenery { lo, hi },
                Some(s) => Scenery {
                    lo: std::array::from_fn(|k| s.lo[k].min(lo[k])),
                    hi: std::array::from_fn(|k| s.hi[k].max(hi[k])),
                },
            });
        }
        out
    }

    /// Whether `c` is more than [`WORLD_MARGIN`] below the lowest point or beyond a side.
    fn leaves(&self, c: [f64; 3]) -> bool {
        c[2] < self.lo[2] - WORLD_MARGIN.below
            || (0..2).any(|k| {
                c[k] < self.lo[k] - WORLD_MARGIN.beside || c[k] > self.hi[k] + WORLD_MARGIN.beside
            })
    }
}

/// Whether robot `index`, which started with its centre of mass at `start`, left the world
/// of `scenery` (see the module's header).
pub(crate) fn world_exit(
    sim: &Simulator,
    index: usize,
    scenery: Option<&Scenery>,
    start: [f64; 3],
) -> Result<Option<WorldExit>, SimError> {
    let c = sim.com(index)?;
    if c.iter().any(|v| !v.is_finite())
        || sim.diverged()
        || !sim.energy(index)?.joules.is_finite()
        || ground_distance(start, c) > BLOW_UP_DISTANCE
    {
        return Ok(Some(WorldExit::Diverged));
    }
    let out = match scenery {
        Some(s) => s.leaves(c),
        None => c[2] < start[2] - FALL_WITHOUT_SCENERY,
    };
    Ok(out.then_some(WorldExit::Left(c)))
}
