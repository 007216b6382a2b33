//! A policy's starting point: the statistics of the observations the file's own modules
//! produce (residual mode, the policy's action held at 0), which a new network normalizes
//! its inputs with, and the network itself ([`initial_network`]): its hidden layers drawn
//! from a seed, its output layer zero, so it starts as the file's gait alone and an
//! optimizer learns the residual.

use std::sync::Arc;

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::control::policy::{Activation, Layer, PolicyNet};
use crate::gym::env::Env;
use crate::gym::error::GymError;
use crate::gym::options::{ActionMode, EnvOptions};
use crate::rng::SimRng;

/// The smallest standard deviation an input is normalized with (an input that never
/// changed in the rollouts, a pad never pressed, is not blown up when it does).
pub const MIN_STD: f64 = 0.01;

/// Mean and standard deviation of every observation value over `episodes` episodes of
/// `seconds` each (seeds `seed`, `seed + 1`, ...) with the policy's action at 0, and the
/// number of joints. `control_period` is the policy's period.
pub fn observation_statistics(
    sim: &Arc<Simulation>,
    registry: &ModuleRegistry,
    episodes: u32,
    seconds: f64,
    seed: u64,
    control_period: f64,
) -> Result<(Vec<f64>, Vec<f64>, usize), GymError> {
    let opts = EnvOptions {
        mode: ActionMode::Residual,
        duration: Some(seconds),
        control_period,
        ..EnvOptions::default()
    };
    let mut env = Env::new(sim.clone(), registry.clone(), opts)?;
    let n = env.layout().len();
    let action = vec![0.0; env.action_len()];
    let mut obs = vec![0.0; n];
    let (mut sum, mut squares, mut count) = (vec![0.0; n], vec![0.0; n], 0.0);
    let mut add = |obs: &[f64]| {
        for ((s, q), x) in sum.iter_mut().zip(squares.iter_mut()).zip(obs) {
            *s += x;
            *q += x * x;
        }
        count += 1.0;
    };
    for e in 0..episodes.max(1) {
        env.reset(Some(seed + u64::from(e)), &mut obs)?;
        add(&obs);
        loop {
            let t = env.step(&action, &mut obs)?;
            add(&obs);
            if t.terminated || t.truncated {
                break;
            }
        }
    }
    let mean: Vec<f64> = sum.iter().map(|s| s / count).collect();
    let std = squares
        .iter()
        .zip(&mean)
        .map(|(q, m)| (q / count - m * m).max(0.0).sqrt().max(MIN_STD))
        .collect();
    Ok((mean, std, env.action_len()))
}

/// A network from `mean.len()` inputs through `hidden` layers to `outputs`: hidden
/// weights normal with variance 1/inputs (drawn from `seed`), biases and the output layer
/// zero (it outputs 0 until trained), normalizing inputs by `mean` and `std`.
pub fn initial_network(
    (mean, std): (Vec<f64>, Vec<f64>),
    hidden: &[usize],
    outputs: usize,
    activation: Activation,
    seed: u64,
) -> Option<PolicyNet> {
    let mut rng = SimRng::new(seed);
    let mut layers = Vec::new();
    let mut inputs = mean.len();
    for &width in hidden {
        let scale = 1.0 / (inputs.max(1) as f64).sqrt();
        layers.push(Layer {
            weight: (0..width * inputs)
                .map(|_| rng.gaussian() * scale)
                .collect(),
            bias: vec![0.0; width],
        });
        inputs = width;
    }
    layers.push(Layer {
        weight: vec![0.0; outputs * inputs],
        bias: vec![0.0; outputs],
    });
    let mut net = PolicyNet::new(layers, activation)?;
    net.obs_mean = mean;
    net.obs_std = std;
    Some(net)
}
