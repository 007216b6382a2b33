//! `proleg policy`: learned policies' weights files. `init` writes a network that starts as
//! a simulation's own gait (its output layer zero) and normalizes its inputs by the
//! statistics of that gait's observations; `show` describes a weights file.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

use crate::cli::error::CliError;
use crate::control::ModuleRegistry;
use crate::control::policy::{Activation, PolicyNet};
use crate::gym::statistics::{initial_network, observation_statistics};

/// `proleg policy` subcommands.
#[derive(clap::Subcommand)]
pub enum PolicyCommand {
    /// A new weights file for a `Policy` over SIMULATION's own modules: inputs normalized
    /// by the statistics of the observations the modules alone produce, output 0.
    Init(InitArgs),
    /// The layers, activation and input statistics of a weights file.
    Show {
        /// The weights file (.safetensors).
        file: PathBuf,
    },
}

/// Options of `proleg policy init`.
#[derive(clap::Args)]
pub struct InitArgs {
    /// The simulation whose modules the policy will run beside (without the policy).
    pub simulation: PathBuf,
    /// Where to write the weights file.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Hidden layer widths, comma-separated (none: a linear policy).
    #[arg(long, value_delimiter = ',', default_value = "16")]
    pub hidden: Vec<usize>,
    /// The hidden layers' activation (tanh, relu, linear).
    #[arg(long, default_value = "tanh")]
    pub activation: String,
    /// Episodes whose observations give the statistics.
    #[arg(long, default_value_t = 2)]
    pub episodes: u32,
    /// Simulated seconds per episode.
    #[arg(long, default_value_t = 20.0)]
    pub seconds: f64,
    /// The policy's control period (s): the `Policy` module's `Period`.
    #[arg(long, default_value_t = 0.02)]
    pub period: f64,
    /// Seed of the episodes and of the hidden weights.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// A weights file described.
#[derive(Debug, Clone, PartialEq)]
pub struct PolicyReport {
    /// The file.
    pub file: PathBuf,
    /// Inputs, each layer's outputs.
    pub widths: Vec<usize>,
    /// The hidden layers' activation.
    pub activation: Activation,
    /// Weights and biases.
    pub parameters: usize,
    /// Whether it was just written.
    pub written: bool,
}

impl fmt::Display for PolicyReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let widths: Vec<String> = self.widths.iter().map(usize::to_string).collect();
        writeln!(
            f,
            "{} {}: layers {} ({}), {} weights and biases",
            if self.written { "wrote" } else { "policy" },
            self.file.display(),
            widths.join(" -> "),
            self.activation.name(),
            self.parameters
        )
    }
}

fn report(file: PathBuf, net: &PolicyNet, written: bool) -> PolicyReport {
    let mut widths = vec![net.inputs()];
    widths.extend(net.layers.iter().map(|l| l.outputs()));
    PolicyReport {
        file,
        widths,
        activation: net.activation,
        parameters: net.parameter_count(),
        written,
    }
}

/// Runs a `proleg policy` subcommand.
pub fn run(command: &PolicyCommand, registry: &ModuleRegistry) -> Result<PolicyReport, CliError> {
    match command {
        PolicyCommand::Show { file } => {
            let net = PolicyNet::read(file).map_err(|e| CliError::Policy(Box::new(e)))?;
            Ok(report(file.clone(), &net, false))
        }
        PolicyCommand::Init(a) => {
            let activation = Activation::parse(&a.activation).ok_or(CliError::Option {
                option: "--activation",
                value: a.activation.clone(),
                want: "give tanh, relu or linear",
            })?;
            let sim = Arc::new(crate::control::load_simulation_in(&a.simulation, registry)?);
            let (mean, std, joints) =
                observation_statistics(&sim, registry, a.episodes, a.seconds, a.seed, a.period)?;
            let net = initial_network((mean, std), &a.hidden, joints, activation, a.seed).ok_or(
                CliError::Options("--hidden: every layer needs a width above 0"),
            )?;
            net.write(&a.out)
                .map_err(|e| CliError::Policy(Box::new(e)))?;
            Ok(report(a.out.clone(), &net, true))
        }
    }
}
