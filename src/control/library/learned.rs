//! `Policy`: a learned closed-loop controller. Every `Period` seconds it writes the robot's
//! observation ([`crate::control::observation`], the parts its switches select), runs its
//! network ([`PolicyNet`], read from the weights file the actuation file names) and holds
//! each output, clamped to [-1, 1] and times `Amplitude`, as its joint's angle offset until
//! the next period; the kernel sums it with the other modules (a residual over a
//! generator, or alone). The same observation and the same action scaling as the Python
//! environment's residual mode: a policy trained there runs here unchanged.
//!
//! Without a network it outputs 0 (training starts from the other modules alone). A
//! network whose inputs do not match the robot's observation is refused before the run
//! ([`ActuationModule::check_observation`]); one that stops fitting during a run (its
//! switches changed in the window) or computes a non-finite output stops the module (it
//! outputs 0 and says why in [`ActuationModule::failure`]). `Senses` = 0 holds every sensor input at the
//! network's observation mean (the generator phases stay): the ablation that measures what
//! sensing is worth; `Hold` = k holds the k-th part alone (1 angles .. 7 phases), the
//! ablation per sense. Nothing is allocated per step once the observation's layout is known.

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::control::observation::{
    ObsLayout, ObsParts, ObsSource, heading_velocity, write_observation,
};
use crate::control::policy::{NetworkMismatch, PolicyNet};
use crate::rng::SimRng;
use crate::sensing::SensorData;

/// The type name in actuation files.
pub const TYPE_NAME: &str = "Policy";

const PERIOD: usize = 0;
const AMPLITUDE: usize = 1;
const SENSES: usize = 2;
const HOLD: usize = 3;
/// The first of the seven input switches, in [`ObsParts`] order.
const INPUTS: usize = 4;

const fn switch(name: &'static str, help: &'static str) -> ParamDescriptor {
    ParamDescriptor {
        name,
        aliases: &[],
        unit: "on/off",
        default: 1.0,
        min: 0.0,
        max: 1.0,
        help,
    }
}

const PARAMETERS: &[ParamDescriptor] = &[
    ParamDescriptor {
        name: "Period",
        aliases: &["Control_Period"],
        unit: "s",
        default: 0.02,
        min: 0.0,
        max: 10.0,
        help: "seconds between two evaluations of the network (0: every step)",
    },
    ParamDescriptor {
        name: "Amplitude",
        aliases: &[],
        unit: "°",
        default: 22.5,
        min: 0.0,
        max: 180.0,
        help: "the joint's angle offset at network output 1 (outputs are clamped to [-1, 1])",
    },
    ParamDescriptor {
        name: "Senses",
        aliases: &[],
        unit: "on/off",
        default: 1.0,
        min: 0.0,
        max: 1.0,
        help: "0 holds every sensor input at the network's observation mean (ablation)",
    },
    ParamDescriptor {
        name: "Hold",
        aliases: &[],
        unit: "part",
        default: 0.0,
        min: 0.0,
        max: 7.0,
        help: "holds one part of the observation at the network's mean (1 angles, 2 speeds, 3 pads, 4 lasers, 5 gravity, 6 velocity, 7 phases; 0 none): the per-sense ablation",
    },
    switch("Angles", "observe every joint's angle"),
    switch("Speeds", "observe every joint's angular speed"),
    switch("Pads", "observe the tactile pads"),
    switch("Lasers", "observe the laser ranges"),
    switch("Gravity", "observe gravity in the head's frame"),
    switch(
        "Velocity",
        "observe the centre of mass's velocity in the heading frame",
    ),
    switch("Phases", "observe the generators' phases (sine and cosine)"),
];

/// The type's descriptor.
pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: TYPE_NAME,
        summary: "learned neural policy from the sensors to joint angle offsets",
        parameters: PARAMETERS,
        series: &["Action"],
        sensing: true,
        network: true,
    }
}

/// Why the module stopped (its [`ActuationModule::failure`] says it in words).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolicyFailure {
    /// The network does not fit the observation (its inputs).
    #[error("{0}")]
    Mismatch(#[from] NetworkMismatch),
    /// The network computed a NaN or infinite output.
    #[error("the network's output {output} is {value}")]
    NotFinite {
        /// The output's index.
        output: usize,
        /// Its value.
        value: f64,
    },
}

/// The policy module.
#[derive(Debug, Clone)]
pub struct Policy {
    core: ModuleCore,
    net: Option<PolicyNet>,
    /// The observation's layout, fixed at the first step (again when the switches change).
    layout: Option<ObsLayout>,
    obs: Vec<f64>,
    action: Vec<f64>,
    /// Steps since the reset.
    steps: u64,
    /// The centre of mass at the last evaluation.
    last_position: Option<[f64; 3]>,
    failure: Option<String>,
}

impl Policy {
    /// A module for `joints` connected joints, without a network.
    pub fn new(joints: usize) -> Self {
        Policy {
            core: ModuleCore::new(descriptor(), joints),
            net: None,
            layout: None,
            obs: Vec::new(),
            action: vec![0.0; joints],
            steps: 0,
            last_position: None,
            failure: None,
        }
    }

    fn parts(&self) -> ObsParts {
        let on = |k: usize| self.core.params.get(INPUTS + k, 0) >= 0.5;
        ObsParts {
            angles: on(0),
            speeds: on(1),
            pads: on(2),
            lasers: on(3),
            gravity: on(4),
            velocity: on(5),
            phases: on(6),
        }
    }

    /// Makes the layout anew (once) when this step's sizes or the switches changed.
    fn fit_layout(&mut self, ctx: &StepContext) {
        let parts = self.parts();
        let fits = self.layout.as_ref().is_some_and(|l| {
            l.parts == parts && l.fits(ctx.robot_angles.len(), ctx.sensors, ctx.phases.len())
        });
        if !fits {
            let layout =
                ObsLayout::new(ctx.robot_angles.len(), ctx.sensors, ctx.phases.len(), parts);
            self.obs = vec![0.0; layout.len()];
            self.layout = Some(layout);
        }
    }

    /// One evaluation of the network: the new held action, or why there is none.
    fn evaluate(&mut self, ctx: &StepContext, period: f64) -> Result<(), PolicyFailure> {
        let position = ctx.sensors.position;
        let from = self.last_position.replace(position).unwrap_or(position);
        let velocity = heading_velocity(from, position, period, ctx.sensors.heading);
        self.fit_layout(ctx);
        let Policy {
            core,
            net: Some(net),
            layout: Some(layout),
            obs,
            action,
            ..
        } = self
        else {
            return Ok(());
        };
        inputs_fit(net, layout)?;
        let src = ObsSource {
            angles: ctx.robot_angles,
            sensors: ctx.sensors,
            velocity,
            phases: ctx.phases,
        };
        write_observation(layout, &src, obs);
        if core.params.get(SENSES, 0) < 0.5 {
            // Every part before the phases is sensed.
            let sensed = layout.part_range(6).start;
            obs[..sensed].copy_from_slice(&net.obs_mean[..sensed]);
        }
        let hold = core.params.get(HOLD, 0).round();
        if hold >= 1.0 {
            let held = layout.part_range(hold as usize - 1);
            obs[held.clone()].copy_from_slice(&net.obs_mean[held]);
        }
        net.forward(obs, action);
        if let Some((output, &value)) = action.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(PolicyFailure::NotFinite { output, value });
        }
        Ok(())
    }
}

/// Whether `net` reads as many inputs as `layout` holds.
fn inputs_fit(net: &PolicyNet, layout: &ObsLayout) -> Result<(), NetworkMismatch> {
    if net.inputs() == layout.len() {
        return Ok(());
    }
    Err(NetworkMismatch::Inputs {
        network: net.inputs(),
        observation: layout.len(),
        joints: layout.joints,
        pads: layout.pads,
        beams: layout.beams.iter().sum(),
        generators: layout.phases,
    })
}

impl ActuationModule for Policy {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, _rng: &mut SimRng) {
        self.steps = 0;
        self.last_position = None;
        self.action.fill(0.0);
        self.core.data.values_mut().fill(0.0);
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        if self.failure.is_some() {
            out.fill(0.0);
            return;
        }
        let every = (self.core.params.get(PERIOD, 0) / ctx.dt).round().max(1.0) as u64;
        if self.steps.is_multiple_of(every)
            && let Err(cause) = self.evaluate(ctx, every as f64 * ctx.dt)
        {
            self.failure = Some(cause.to_string());
            self.action.fill(0.0);
        }
        self.steps += 1;
        let ModuleCore { params, data, .. } = &mut self.core;
        let logged = data.series_mut(0);
        for (j, ((o, a), l)) in out.iter_mut().zip(&self.action).zip(logged).enumerate() {
            *o = a.clamp(-1.0, 1.0) * params.get(AMPLITUDE, j);
            *l = *o;
        }
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        Box::new(self.clone())
    }

    fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }

    fn network(&self) -> Option<&PolicyNet> {
        self.net.as_ref()
    }

    fn check_observation(
        &self,
        joints: usize,
        sensors: &SensorData,
        phases: usize,
    ) -> Result<(), NetworkMismatch> {
        let Some(net) = &self.net else {
            return Ok(());
        };
        inputs_fit(net, &ObsLayout::new(joints, sensors, phases, self.parts()))
    }

    fn set_network(&mut self, net: PolicyNet) -> Result<(), NetworkMismatch> {
        let joints = self.core.params.joints();
        if net.outputs() != joints {
            return Err(NetworkMismatch::Outputs {
                given: net.outputs(),
                want: joints,
            });
        }
        self.net = Some(net);
        self.failure = None;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::policy::{Activation, Layer};
    use crate::sensing::SensorData;

    /// A one-layer network: action[j] = sum of weights[j] * obs + bias[j].
    fn linear(weights: Vec<f64>, bias: Vec<f64>) -> PolicyNet {
        PolicyNet::new(
            vec![Layer {
                weight: weights,
                bias,
            }],
            Activation::Tanh,
        )
        .expect("a valid layer")
    }

    fn context<'a>(step: u64, angles: &'a [f64], sensors: &'a SensorData) -> StepContext<'a> {
        StepContext {
            time: step as f64 * 0.01,
            dt: 0.01,
            step,
            angles,
            robot_angles: angles,
            sensors,
            phases: &[],
        }
    }

    fn only_angles(p: &mut Policy) {
        for k in 1..7 {
            p.core.params.set(INPUTS + k, None, 0.0).expect("a switch");
        }
    }

    #[test]
    fn outputs_the_network_of_the_angles_scaled_and_held_for_a_period() {
        let mut p = Policy::new(2);
        only_angles(&mut p);
        // action0 = 0.5 angle0(rad) - angle1(rad) + 0.1, action1 = 2 angle1 (clamped to 1).
        p.set_network(linear(vec![0.5, -1.0, 0.0, 2.0], vec![0.1, 0.0]))
            .expect("two outputs");
        p.core.params.set(AMPLITUDE, None, 10.0).expect("amplitude");
        let sensors = SensorData::default();
        let angles = [30.0f64, 45.0];
        let mut out = [0.0; 2];
        p.compute(&context(0, &angles, &sensors), &mut out);
        let (a0, a1) = (30f64.to_radians(), 45f64.to_radians());
        let want0 = (0.5 * a0 - a1 + 0.1) * 10.0;
        assert!((out[0] - want0).abs() < 1e-12, "{} vs {want0}", out[0]);
        assert_eq!(out[1], 10.0, "2 * 0.785 clamps to 1");
        // Held until the period (0.02 s = 2 steps) is over, whatever the angles do.
        p.compute(&context(1, &[0.0, 0.0], &sensors), &mut out);
        assert!((out[0] - want0).abs() < 1e-12);
        p.compute(&context(2, &[0.0, 0.0], &sensors), &mut out);
        assert!((out[0] - 1.0).abs() < 1e-12 && out[1] == 0.0);
    }

    #[test]
    fn without_a_network_it_outputs_nothing() {
        let mut p = Policy::new(3);
        let sensors = SensorData::default();
        let mut out = [7.0; 3];
        p.compute(&context(0, &[10.0, 20.0, 30.0], &sensors), &mut out);
        assert_eq!(out, [0.0; 3]);
        assert!(p.failure().is_none());
    }

    #[test]
    fn a_network_of_the_wrong_width_is_refused_or_stops_the_module() {
        let mut p = Policy::new(2);
        assert_eq!(
            p.set_network(linear(vec![1.0, 1.0], vec![0.0])),
            Err(NetworkMismatch::Outputs { given: 1, want: 2 })
        );
        only_angles(&mut p);
        p.set_network(linear(vec![1.0; 6], vec![0.0; 2]))
            .expect("two outputs");
        let sensors = SensorData::default();
        let mut out = [1.0; 2];
        p.compute(&context(0, &[10.0, 20.0], &sensors), &mut out);
        assert_eq!(out, [0.0; 2]);
        let why = p.failure().expect("a stopped module");
        assert!(
            why.contains("reads 3 inputs") && why.contains("has 2"),
            "{why}"
        );
    }

    #[test]
    fn senses_off_holds_the_inputs_at_their_mean() {
        let mut p = Policy::new(1);
        only_angles(&mut p);
        let mut net = linear(vec![1.0], vec![0.0]);
        net.obs_mean = vec![0.3];
        p.set_network(net).expect("one output");
        p.core.params.set(AMPLITUDE, None, 1.0).expect("amplitude");
        p.core.params.set(SENSES, None, 0.0).expect("senses");
        let sensors = SensorData::default();
        let mut out = [1.0];
        p.compute(&context(0, &[57.0], &sensors), &mut out);
        assert_eq!(out, [0.0], "the held input is the mean: normalized to 0");
    }

    #[test]
    fn hold_holds_one_part_at_its_mean_and_leaves_the_others() {
        let mut p = Policy::new(1);
        only_angles(&mut p);
        p.core.params.set(INPUTS + 1, None, 1.0).expect("speeds on");
        // action = angle(rad) + speed(rad/s), both normalized by their means 0.3 and 0.2.
        let mut net = linear(vec![1.0, 1.0], vec![0.0]);
        net.obs_mean = vec![0.3, 0.2];
        p.set_network(net).expect("one output");
        p.core.params.set(AMPLITUDE, None, 1.0).expect("amplitude");
        let sensors = SensorData {
            joint_speeds: vec![0.4f64.to_degrees()],
            ..SensorData::default()
        };
        let angle = [0.5f64.to_degrees()];
        let mut out = [0.0];
        let mut run = |p: &mut Policy, hold: f64| {
            p.core.params.set(HOLD, None, hold).expect("hold");
            p.reset(&mut SimRng::new(1));
            p.compute(&context(0, &angle, &sensors), &mut out);
            out[0]
        };
        let both = run(&mut p, 0.0);
        let angle_held = run(&mut p, 1.0);
        let speed_held = run(&mut p, 2.0);
        let phases_held = run(&mut p, 7.0);
        let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(near(both, 0.2 + 0.2), "{both}");
        assert!(near(angle_held, 0.2), "{angle_held}");
        assert!(near(speed_held, 0.2), "{speed_held}");
        assert!(near(phases_held, both), "no phases observed: nothing held");
    }
}
