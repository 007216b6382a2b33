//! Behaviour descriptors measured in an episode (MAP-Elites' `<descriptor name="height">`
//! and `name="curvature"`): a [`Probe`] samples robot `i` of a running world after every
//! chunk of the episode runner ([`crate::sim::EXIT_CHECK_SECONDS`] of simulated time, the
//! chunks between its checks that the robots are still in the world) and gives the
//! quantities at the end; the physics is the same as in one run of steps.

use crate::config::Simulation;
use crate::config::optimizer::{Algorithm, Quantity};
use crate::measure::turn_deg;
use crate::sim::{SimError, Simulator};

/// Legs of a path shorter than this (m) do not turn it.
const SHORTEST_LEG: f64 = 0.005;

/// The quantities `sim`'s MAP-Elites descriptors measure, in descriptor order (empty for
/// other optimizers and for descriptors of the genome).
pub fn measured_quantities(sim: &Simulation) -> Vec<Quantity> {
    match sim.optimizer.as_ref().map(|o| &o.spec.algorithm) {
        Some(Algorithm::MapElites(m)) => m
            .descriptors
            .iter()
            .filter_map(|d| d.measured.map(|q| q.quantity))
            .collect(),
        _ => Vec::new(),
    }
}

/// The samples of one robot's episode.
#[derive(Debug, Clone)]
pub struct Probe {
    robot: usize,
    /// Centre of mass at the start.
    start: [f64; 3],
    /// Sum and count of the body heights sampled.
    height: (f64, u32),
    /// Centres of mass sampled after the start, in order.
    path: Vec<[f64; 3]>,
}

impl Probe {
    /// A probe of robot `robot` of `s`, sampling its start.
    pub fn start(s: &Simulator, robot: usize, samples: usize) -> Result<Probe, SimError> {
        let mut p = Probe {
            robot,
            start: s.com(robot)?,
            height: (0.0, 0),
            path: Vec::with_capacity(samples),
        };
        p.height_sample(s)?;
        Ok(p)
    }

    /// Samples the robot now.
    pub fn sample(&mut self, s: &Simulator) -> Result<(), SimError> {
        self.path.push(s.com(self.robot)?);
        self.height_sample(s)
    }

    fn height_sample(&mut self, s: &Simulator) -> Result<(), SimError> {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for b in s.robot_bodies(self.robot)? {
            if let Some(state) = s.body_state(b) {
                let z = state.pose.translation[2];
                lo = lo.min(z);
                hi = hi.max(z);
            }
        }
        if hi >= lo {
            self.height.0 += hi - lo;
            self.height.1 += 1;
        }
        Ok(())
    }

    /// The quantities `which`, in order.
    pub fn finish(&self, which: &[Quantity]) -> Vec<f64> {
        which
            .iter()
            .map(|q| match q {
                Quantity::Height => self.height.0 / f64::from(self.height.1.max(1)),
                Quantity::Curvature => {
                    let (Some(mid), Some(end)) =
                        (self.path.get(self.path.len() / 2), self.path.last())
                    else {
                        return 0.0;
                    };
                    turn_deg(self.start, *mid, *end, SHORTEST_LEG)
                }
            })
            .collect()
    }
}
