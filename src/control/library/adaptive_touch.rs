//! `Global_Adaptive_Touch`: the sensor-driven offset module of the thesis's second
//! experiment (6.2, table 6.5). The thesis gives its parameters but not its equations;
//! this is our design from 3.3.3 and 6.2. It is summed with a pattern generator by the
//! kernel (fig. 4.6) and outputs one offset per joint, changed every step by rules on the
//! pattern of touch pads, and returned to the base shape (0) when no rule acts.
//!
//! Pads: the robot's tactile pads in order, two per link (back, front), links from tail
//! to head, so joint i sits between the front pad of link i and the back pad of link i+1.
//! Positive offsets bend a joint so the head-side link tilts up.
//!
//! - Stuck: the robot has made no progress for `Get-stuck` steps, i.e. its centre of mass
//!   (the position sensor) has not got [`PROGRESS_STEP`] farther from where it started
//!   than its farthest point so far. The shape is adapted only while stuck and for
//!   `Get-stuck` steps after (the thesis: the threshold "determines when manipulation of
//!   the robot's base shape has to be applied"); otherwise every offset returns towards 0
//!   at the `Recovering` rate, so crawling on flat ground is left alone. Offsets no rule
//!   moves this step also recover, even while stuck, so a shape that did not help
//!   (say, a head still raised on the crest) does not stay. A crawler stalls
//!   for part of every wave period (the tail pulls up), so thresholds shorter than that
//!   stall also adapt on flat ground; the optimizer finds the trade-off.
//!
//! The rates (`Constant 1..8`, 4 raising and 4 lowering offsets):
//! - `Constant 1`: while stuck with the head blocked (a head pad touches a surface that
//!   faces the robot: its contact normal points against the way the robot has travelled),
//!   the head joint bends up to lift the head onto the obstacle.
//! - `Constant 2`: in the same state, the joint behind it bends up too.
//! - `Constant 3`: a concave spot under joint i (its two near pads released, some pad
//!   behind and some pad ahead pressed: the body bridges a trough): joint i bends up so
//!   the body sags into it.
//! - `Constant 4`: the tail link's pads both released (tail hanging): the first joint bends
//!   up, pressing the tail down.
//! - `Constant 5`: the head link's pads both released while the link behind it touches
//!   (head over an edge): the head joint bends down.
//! - `Constant 6`: a convex spot under joint i (near pads pressed, far pads released):
//!   joint i bends down to wrap the crest.
//! - `Constant 7`: in the same state, the middle joints bend down (a crest behind the
//!   raised front), so the body props the head higher.
//! - `Constant 8`: fewer than a third of all pads touch (body lifted off): every offset
//!   shrinks towards 0 at this extra rate.
//!
//! Constants 3-6 and 8 act while stuck or adapting. Rates are degrees per step; offsets
//! stay within ±45°. The thesis's GA file (listing
//! B.7) names two of the parameters `Get-stuck-threshold` and `back to zero constant`;
//! both spellings are accepted.

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::measure::ground_distance;
use crate::rng::SimRng;

/// Largest offset magnitude (degrees).
pub const MAX_OFFSET: f64 = 45.0;

/// A head contact blocks when its normal's component against the travel direction exceeds
/// this (the sine of the surface's slope, here about 12°).
pub const BLOCKING: f64 = 0.2;

/// Progress smaller than this (m) does not reset the stuck counter.
pub const PROGRESS_STEP: f64 = 0.005;

const GET_STUCK: usize = 0;
const RECOVERING: usize = 1;
const C: usize = 2; // Constant 1 is parameter C, Constant 8 is C + 7.

const fn constant(name: &'static str, help: &'static str) -> ParamDescriptor {
    ParamDescriptor {
        name,
        aliases: &[],
        unit: "deg/step",
        default: 0.5,
        min: 0.0,
        max: 100.0,
        help,
    }
}

const PARAMETERS: &[ParamDescriptor] = &[
    ParamDescriptor {
        name: "Get-stuck",
        aliases: &["Get-stuck-threshold", "Get stuck threshold"],
        unit: "steps",
        default: 300.0,
        min: 1.0,
        max: 100_000.0,
        help: "steps without progress before the robot counts as stuck",
    },
    ParamDescriptor {
        name: "Recovering",
        aliases: &["back to zero constant", "Recovering speed"],
        unit: "deg/step",
        default: 0.1,
        min: 0.0,
        max: 10.0,
        help: "speed at which offsets return to the base shape",
    },
    constant(
        "Constant 1",
        "head joint up while stuck and the head blocked",
    ),
    constant(
        "Constant 2",
        "second joint up while stuck and the head blocked",
    ),
    constant("Constant 3", "joint up over a concave spot"),
    constant("Constant 4", "first joint up while the tail hangs"),
    constant(
        "Constant 5",
        "head joint down while the head hangs over an edge",
    ),
    constant("Constant 6", "joint down over a convex spot"),
    constant(
        "Constant 7",
        "middle joints down while stuck and the head blocked",
    ),
    constant(
        "Constant 8",
        "all offsets towards 0 while the body is lifted off",
    ),
];

/// The type's descriptor.
pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "Global_Adaptive_Touch",
        summary: "touch-driven adaptive offsets (experiment 2)",
        parameters: PARAMETERS,
        series: &["desired_angle", "stuck"],
        sensing: true,
        network: false,
    }
}

/// The adaptive offset module.
#[derive(Debug, Clone)]
pub struct AdaptiveTouch {
    core: ModuleCore,
    offsets: Vec<f64>,
    acted: Vec<bool>,
    /// Where the robot was at its first step after a reset.
    start: Option<[f64; 3]>,
    /// Farthest distance from `start` so far (m), counted in [`PROGRESS_STEP`]s.
    farthest: f64,
    /// Steps since `farthest` last grew.
    stalled: u64,
    /// Steps of adaptation left after the robot was last stuck.
    adapting: u64,
    stuck: bool,
}

impl AdaptiveTouch {
    /// A module for `joints` connected joints, its parameters at their defaults.
    pub fn new(joints: usize) -> Self {
        AdaptiveTouch {
            core: ModuleCore::new(descriptor(), joints),
            offsets: vec![0.0; joints],
            acted: vec![false; joints],
            start: None,
            farthest: 0.0,
            stalled: 0,
            adapting: 0,
            stuck: false,
        }
    }

    /// Whether the module currently considers the robot stuck.
    pub fn stuck(&self) -> bool {
        self.stuck
    }

    /// Counts the steps since the robot last got [`PROGRESS_STEP`] farther from its start.
    fn track_progress(&mut self, position: [f64; 3]) {
        let start = *self.start.get_or_insert(position);
        let distance = ground_distance(start, position);
        if distance >= self.farthest + PROGRESS_STEP {
            self.farthest = distance;
            self.stalled = 0;
        } else {
            self.stalled += 1;
        }
    }

    /// Whether a head pad touches a surface facing the robot: its contact normal (from
    /// the surface into the pad) points against the way the robot has travelled by more
    /// than [`BLOCKING`]. Before the robot has moved 1 cm, any head contact counts.
    fn head_blocked(&self, ctx: &StepContext, head: usize) -> bool {
        let sensors = ctx.sensors;
        let (p, start) = (sensors.position, self.start.unwrap_or(sensors.position));
        let (dx, dy) = (p[0] - start[0], p[1] - start[1]);
        let travelled = ground_distance(start, p);
        (2 * head..2 * head + 2).any(|i| {
            sensors.tactile.get(i).copied().unwrap_or(false)
                && match sensors.tactile_normals.get(i) {
                    Some(n) if travelled > 0.01 => (n[0] * dx + n[1] * dy) / travelled < -BLOCKING,
                    _ => true,
                }
        })
    }

    fn push(&mut self, joint: usize, delta: f64) {
        if let Some(o) = self.offsets.get_mut(joint) {
            *o = (*o + delta).clamp(-MAX_OFFSET, MAX_OFFSET);
            self.acted[joint] = true;
        }
    }
}

impl ActuationModule for AdaptiveTouch {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, _rng: &mut SimRng) {
        self.offsets.fill(0.0);
        self.start = None;
        self.farthest = 0.0;
        self.stalled = 0;
        self.adapting = 0;
        self.stuck = false;
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        let n = out.len();
        self.track_progress(ctx.sensors.position);
        let pads = &ctx.sensors.tactile;
        let links = n + 1;
        self.acted.fill(false);
        if n > 0 && pads.len() >= 2 * links {
            let p = |link: usize, front: bool| pads[2 * link + usize::from(front)];
            let k = |i: usize| self.core.params.get(C + i - 1, 0);
            let head = links - 1;
            let threshold = self.core.params.get(GET_STUCK, 0);
            self.stuck = self.stalled as f64 >= threshold;
            if self.stuck {
                self.adapting = threshold as u64;
            } else {
                self.adapting = self.adapting.saturating_sub(1);
            }
            if self.stuck || self.adapting > 0 {
                let (c1, c2, c3, c4, c5, c6, c7, c8) =
                    (k(1), k(2), k(3), k(4), k(5), k(6), k(7), k(8));
                if self.stuck && self.head_blocked(ctx, head) {
                    self.push(n - 1, c1);
                    if n >= 2 {
                        self.push(n - 2, c2);
                    }
                    for j in 1..n.saturating_sub(2) {
                        self.push(j, -c7);
                    }
                }
                for i in 0..n {
                    // Pads behind joint i's near pads are 0..=2i, those ahead 2i+3..
                    let (near_back, near_front) = (p(i, true), p(i + 1, false));
                    let behind = pads[..=2 * i].iter().any(|x| *x);
                    let ahead = pads[2 * i + 3..2 * links].iter().any(|x| *x);
                    let (far_back, far_front) = (p(i, false), p(i + 1, true));
                    if !near_back && !near_front && behind && ahead {
                        self.push(i, c3);
                    } else if near_back && near_front && !far_back && !far_front {
                        self.push(i, -c6);
                    }
                }
                if !p(0, false) && !p(0, true) {
                    self.push(0, c4);
                }
                if !p(head, false) && !p(head, true) && (p(head - 1, false) || p(head - 1, true)) {
                    self.push(n - 1, -c5);
                }
                let touching = pads.iter().filter(|x| **x).count();
                if 3 * touching < pads.len() {
                    for o in &mut self.offsets {
                        *o -= o.signum() * c8.min(o.abs());
                    }
                }
            }
        }
        let back = self.core.params.get(RECOVERING, 0);
        for (o, acted) in self.offsets.iter_mut().zip(&self.acted) {
            if !acted {
                *o -= o.signum() * back.min(o.abs());
            }
        }
        out.copy_from_slice(&self.offsets);
        let data = &mut self.core.data;
        data.series_mut(0).copy_from_slice(out);
        data.series_mut(1).fill(if self.stuck { 1.0 } else { 0.0 });
    }

    /// Moves the joint's offset by `amount` degrees (it then recovers as usual).
    fn perturb(&mut self, joint: usize, amount: f64) -> bool {
        self.offsets
            .get_mut(joint)
            .map(|o| *o = (*o + amount).clamp(-MAX_OFFSET, MAX_OFFSET))
            .is_some()
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensing::SensorData;

    /// One step with these pads pressed and the robot's centre at `y` (m).
    fn step(m: &mut AdaptiveTouch, pads: &[bool], y: f64) -> Vec<f64> {
        let n = m.core.params.joints();
        let sensors = SensorData {
            tactile: pads.to_vec(),
            position: [0.0, y, 0.03],
            ..SensorData::default()
        };
        let angles = vec![0.0; n];
        let ctx = StepContext {
            time: 0.0,
            dt: 0.001,
            step: 0,
            angles: &angles,
            robot_angles: &angles,
            sensors: &sensors,
            phases: &[],
        };
        let mut out = vec![0.0; n];
        m.compute(&ctx, &mut out);
        out
    }

    fn module() -> AdaptiveTouch {
        let mut m = AdaptiveTouch::new(5);
        m.core.params.set(GET_STUCK, None, 10.0).unwrap();
        m
    }

    /// Pads of a crawler on flat ground at step `k`: a contact wave runs along the body.
    fn crawling(k: usize) -> [bool; 12] {
        let mut pads = [true; 12];
        for (i, p) in pads.iter_mut().enumerate() {
            *p = (i + k / 2) % 6 < 4;
        }
        pads
    }

    #[test]
    fn crawling_on_flat_ground_keeps_the_base_shape() {
        let mut m = module();
        // 2 mm forward per step with a short slide back every 8 steps: never 10 stalled.
        let mut y = 0.0;
        for k in 0..500 {
            y += if k % 8 < 6 { 0.002 } else { -0.002 };
            assert_eq!(step(&mut m, &crawling(k), y), vec![0.0; 5], "step {k}");
        }
        assert!(!m.stuck());
    }

    #[test]
    fn a_blocked_robot_lifts_its_front_and_recovers_after_moving_on() {
        let mut m = module();
        let all = [true; 12];
        for _ in 0..9 {
            step(&mut m, &all, 0.002);
        }
        assert!(
            !m.stuck(),
            "progress under 5 mm still counts as stalled, not yet long"
        );
        let out = step(&mut m, &all, 0.002);
        assert!(m.stuck());
        assert!(out[4] > 0.0 && out[3] > 0.0 && out[2] < 0.0, "{out:?}");
        for _ in 0..200 {
            step(&mut m, &all, 0.0);
        }
        assert_eq!(
            step(&mut m, &all, 0.0)[4],
            MAX_OFFSET,
            "offsets are bounded"
        );
        // Moving on (a first 1 cm, then 1 mm per step): no longer stuck, and offsets
        // return to 0 at the recovering rate.
        let mut y = 0.01;
        let mut last = Vec::new();
        for k in 0..2000 {
            y += 0.001;
            last = step(&mut m, &crawling(k), y);
            assert!(!m.stuck());
        }
        assert_eq!(last, vec![0.0; 5]);
    }

    #[test]
    fn sliding_back_is_no_progress() {
        let mut m = module();
        step(&mut m, &[true; 12], 0.0);
        step(&mut m, &[true; 12], 0.1);
        for k in 0..10 {
            assert!(!m.stuck(), "step {k}");
            step(&mut m, &[true; 12], 0.1 - 0.001 * k as f64);
        }
        assert!(m.stuck());
    }

    /// A module that has just been stuck, now moving again and adapting.
    fn adapting() -> AdaptiveTouch {
        let mut m = module();
        for _ in 0..11 {
            step(&mut m, &[true; 12], 0.0);
        }
        assert!(m.stuck());
        let before = step(&mut m, &[true; 12], 0.01);
        assert!(!m.stuck() && before.iter().any(|o| *o != 0.0));
        m
    }

    #[test]
    fn concave_and_convex_spots_bend_the_joint_above_them() {
        let mut m = adapting();
        let o = m.offsets[2];
        let mut concave = [true; 12];
        concave[5] = false; // front pad of link 2
        concave[6] = false; // back pad of link 3
        assert!(step(&mut m, &concave, 0.02)[2] > o);
        let mut m = adapting();
        let o = m.offsets[2];
        let mut convex = [true; 12];
        convex[4] = false; // back pad of link 2
        convex[7] = false; // front pad of link 3
        assert!(step(&mut m, &convex, 0.02)[2] < o);
        // Not stuck lately: the same spots leave the shape alone.
        let mut m = module();
        assert_eq!(step(&mut m, &convex, 0.0), vec![0.0; 5]);
    }

    #[test]
    fn reset_forgets_the_start_and_the_stall() {
        let mut m = module();
        for _ in 0..11 {
            step(&mut m, &[true; 12], 0.0);
        }
        assert!(m.stuck());
        m.reset(&mut SimRng::new(1));
        step(&mut m, &[true; 12], 5.0);
        assert!(!m.stuck());
    }

    #[test]
    fn without_pads_it_does_nothing() {
        let mut m = module();
        for _ in 0..20 {
            assert_eq!(step(&mut m, &[], 0.0), vec![0.0; 5]);
        }
    }
}
