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
//! - Stuck: the head link's pads stay pressed for `Get-stuck` steps in a row (while
//!   crawling they lift every wave period). The shape is adapted only while stuck and for
//!   `Get-stuck` steps after (the thesis: the threshold "determines when manipulation of
//!   the robot's base shape has to be applied"); otherwise every offset returns towards 0
//!   at the `Recovering` rate, so crawling on flat ground is left alone.
//! - `Constant 1`: while stuck, the head joint bends up (lift the head onto the obstacle).
//! - `Constant 2`: while stuck, the joint behind it bends up too.
//! - `Constant 3`: a concave spot under joint i (its two near pads released, the far pads
//!   of both links pressed): joint i bends up to fit the trough.
//! - `Constant 4`: the tail link's pads both released (tail hanging): the first joint bends
//!   up, pressing the tail down.
//! - `Constant 5`: the head link's pads both released while the link behind it touches
//!   (head over an edge): the head joint bends down.
//! - `Constant 6`: a convex spot under joint i (near pads pressed, far pads released):
//!   joint i bends down to wrap the crest.
//! - `Constant 7`: while stuck, the middle joints bend down, lowering the centre of
//!   gravity so the body pushes rather than lifts.
//! - `Constant 8`: fewer than a third of all pads touch (body lifted off): every offset
//!   shrinks towards 0 at this extra rate.
//!
//! Rates are degrees per step; offsets stay within ±45°. The thesis's GA file (listing
//! B.7) names two of the parameters `Get-stuck-threshold` and `back to zero constant`;
//! both spellings are accepted.

use crate::control::descriptor::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::rng::SimRng;

/// Largest offset magnitude (degrees).
pub const MAX_OFFSET: f64 = 45.0;

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
        help: "steps the head pads stay pressed before the robot counts as stuck",
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
    constant("Constant 1", "head joint up while stuck"),
    constant("Constant 2", "second joint from the head up while stuck"),
    constant("Constant 3", "joint up over a concave spot"),
    constant("Constant 4", "first joint up while the tail hangs"),
    constant(
        "Constant 5",
        "head joint down while the head hangs over an edge",
    ),
    constant("Constant 6", "joint down over a convex spot"),
    constant("Constant 7", "middle joints down while stuck"),
    constant(
        "Constant 8",
        "all offsets towards 0 while the body is lifted off",
    ),
];

pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "Global_Adaptive_Touch",
        summary: "touch-driven adaptive offsets (experiment 2)",
        parameters: PARAMETERS,
        series: &["desired_angle", "stuck"],
        sensing: true,
    }
}

/// The adaptive offset module.
#[derive(Debug, Clone)]
pub struct AdaptiveTouch {
    core: ModuleCore,
    offsets: Vec<f64>,
    acted: Vec<bool>,
    head_pressed_steps: u64,
    /// Steps of adaptation left after the robot was last stuck.
    adapting: u64,
    stuck: bool,
}

impl AdaptiveTouch {
    pub fn new(joints: usize) -> Self {
        AdaptiveTouch {
            core: ModuleCore::new(descriptor(), joints),
            offsets: vec![0.0; joints],
            acted: vec![false; joints],
            head_pressed_steps: 0,
            adapting: 0,
            stuck: false,
        }
    }

    /// Whether the module currently considers the robot stuck.
    pub fn stuck(&self) -> bool {
        self.stuck
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
        self.head_pressed_steps = 0;
        self.adapting = 0;
        self.stuck = false;
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        let n = out.len();
        let pads = &ctx.sensors.tactile;
        let links = n + 1;
        self.acted.fill(false);
        if n > 0 && pads.len() >= 2 * links {
            let p = |link: usize, front: bool| pads[2 * link + usize::from(front)];
            let k = |i: usize| self.core.params.get(C + i - 1, 0);
            let head = links - 1;
            let threshold = self.core.params.get(GET_STUCK, 0);
            if p(head, false) || p(head, true) {
                self.head_pressed_steps += 1;
            } else {
                self.head_pressed_steps = 0;
                self.stuck = false;
            }
            if self.head_pressed_steps as f64 >= threshold {
                self.stuck = true;
                self.adapting = threshold as u64;
            } else {
                self.adapting = self.adapting.saturating_sub(1);
            }
            if self.stuck || self.adapting > 0 {
                let (c1, c2, c3, c4, c5, c6, c7, c8) =
                    (k(1), k(2), k(3), k(4), k(5), k(6), k(7), k(8));
                if self.stuck {
                    self.push(n - 1, c1);
                    if n >= 2 {
                        self.push(n - 2, c2);
                    }
                    for j in 1..n.saturating_sub(2) {
                        self.push(j, -c7);
                    }
                }
                for i in 0..n {
                    let (far_back, near_back, near_front, far_front) =
                        (p(i, false), p(i, true), p(i + 1, false), p(i + 1, true));
                    if !near_back && !near_front && far_back && far_front {
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
            if !acted && !self.stuck {
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

    fn step(m: &mut AdaptiveTouch, pads: &[bool]) -> Vec<f64> {
        let n = m.core.params.joints();
        let sensors = SensorData {
            tactile: pads.to_vec(),
            ..SensorData::default()
        };
        let angles = vec![0.0; n];
        let ctx = StepContext {
            time: 0.0,
            dt: 0.001,
            step: 0,
            angles: &angles,
            sensors: &sensors,
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

    #[test]
    fn flat_ground_keeps_the_base_shape() {
        let mut m = module();
        let all = [true; 12];
        // The head lifts now and then while crawling: never stuck.
        for k in 0..100 {
            let mut pads = all;
            if k % 8 == 0 {
                pads[10] = false;
                pads[11] = false;
            }
            assert_eq!(step(&mut m, &pads), vec![0.0; 5]);
        }
        assert!(!m.stuck());
    }

    #[test]
    fn a_blocked_head_lifts_the_front_and_recovers_afterwards() {
        let mut m = module();
        let all = [true; 12];
        for _ in 0..9 {
            step(&mut m, &all);
        }
        assert!(!m.stuck());
        let out = step(&mut m, &all);
        assert!(m.stuck());
        assert!(out[4] > 0.0 && out[3] > 0.0 && out[2] < 0.0, "{out:?}");
        for _ in 0..200 {
            step(&mut m, &all);
        }
        assert_eq!(step(&mut m, &all)[4], MAX_OFFSET, "offsets are bounded");
        // The head releases: not stuck any more, offsets return to 0 at the recovering rate.
        let mut pads = all;
        pads[10] = false;
        pads[11] = false;
        pads[8] = false;
        pads[9] = false;
        let mut last = step(&mut m, &pads);
        assert!(!m.stuck());
        // Crawling again: the head lifts every few steps.
        for k in 0..1000 {
            let mut pads = all;
            if k % 8 == 0 {
                pads[10] = false;
                pads[11] = false;
            }
            last = step(&mut m, &pads);
        }
        assert!(!m.stuck());
        assert_eq!(last, vec![0.0; 5]);
    }

    /// A module that has just been stuck (head pressed for the threshold), now adapting.
    fn adapting() -> AdaptiveTouch {
        let mut m = module();
        for _ in 0..10 {
            step(&mut m, &[true; 12]);
        }
        let mut free = [true; 12];
        free[10] = false;
        free[11] = false;
        let before = step(&mut m, &free);
        assert!(!m.stuck() && before.iter().any(|o| *o != 0.0));
        m
    }

    #[test]
    fn concave_and_convex_spots_bend_the_joint_above_them() {
        let mut m = adapting();
        let o = m.offsets[2];
        let mut concave = [true; 12];
        concave[10] = false;
        concave[5] = false; // front pad of link 2
        concave[6] = false; // back pad of link 3
        assert!(step(&mut m, &concave)[2] > o);
        let mut m = adapting();
        let o = m.offsets[2];
        let mut convex = [true; 12];
        convex[10] = false;
        convex[4] = false; // back pad of link 2
        convex[7] = false; // front pad of link 3
        assert!(step(&mut m, &convex)[2] < o);
        // Not stuck lately: the same spots leave the shape alone.
        let mut m = module();
        assert_eq!(step(&mut m, &convex), vec![0.0; 5]);
    }

    #[test]
    fn without_pads_it_does_nothing() {
        let mut m = module();
        assert_eq!(step(&mut m, &[]), vec![0.0; 5]);
    }
}
