//! The command line's logic, as a library: each subcommand of `proleg` is a function here
//! that takes its parsed options and returns a typed value (a report that prints itself, or
//! the text to print) or its typed error. [`crate::commands`] dispatches the parsed command
//! line to them and `main.rs` only prints, so tests and other front ends call the same
//! functions.
//!
//! | command | module |
//! |---|---|
//! | `proleg run` | [`run`] ([`run::RunReport`]); `--html`: [`run_html`] |
//! | `proleg optimize` | [`optimize`] ([`optimize::OptimizeReport`]) |
//! | `proleg compare` | [`compare`] ([`compare::CompareReport`]) |
//! | `proleg results` | [`results`] ([`results::ResultsReport`]) |
//! | `proleg worker` | [`worker`] ([`worker::WorkerRun`]) |
//! | `proleg data info / export / plot` | [`data`] ([`data::InfoReport`]; export and plot: what was written) |
//! | `proleg plugin new / build / list` | [`plugin`] (the listing's text) |
//! | `proleg import`, `proleg export mjcf` | [`interop`] ([`interop::ImportReport`]) |
//! | `proleg calibrate` | [`calibrate`] ([`calibrate::CalibrateReport`]) |
//! | `proleg robot`, `proleg robot-emulator` | [`robot`] ([`robot::RobotReport`]; the emulator: its port) |
//! | `proleg bench`, `proleg check-physics` | [`bench`] (the figures' text; failed checks: [`error::CliError::Failed`]) |
//! | `proleg settle` | [`interop`] (the settle report) |
//! | `proleg policy init / show` | [`policy`] |
//! | `proleg robustness` | [`robustness`] |
//! | `proleg terrain` | [`terrain`] ([`terrain::TerrainReport`]) |
//! | `proleg suite` | [`suite`] ([`suite::SuiteOutcome`]) |
//! | `proleg dashboard` | [`dashboard`] |

pub mod bench;
pub mod calibrate;
pub mod compare;
pub mod dashboard;
pub mod data;
pub mod error;
pub mod interop;
pub mod optimize;
pub mod plugin;
pub mod policy;
pub mod results;
pub mod robot;
pub mod robustness;
pub mod run;
pub mod run_html;
pub mod suite;
pub mod terrain;
pub mod worker;

/// The simulation the control window and the benchmarks use when none is given.
pub const DEMO_CONFIG: &str = "configs/demo.simulation.xml";

/// `DISTANCE,YAW,PITCH`: where `proleg run --video`'s camera looks at the robot from
/// (metres, degrees, degrees).
pub fn parse_camera(s: &str) -> Result<[f64; 3], error::CliError> {
    let bad = |want| error::CliError::Option {
        option: "--camera",
        value: s.to_string(),
        want,
    };
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [d, yaw, pitch] = parts[..] else {
        return Err(bad("expected DISTANCE,YAW,PITCH, e.g. 3,-25,35"));
    };
    let n = |t: &str| t.parse::<f64>().ok().filter(|v| v.is_finite());
    match (n(d), n(yaw), n(pitch)) {
        (Some(d), Some(yaw), Some(pitch))
            if (0.05..=50.0).contains(&d) && (-10.0..=85.0).contains(&pitch) =>
        {
            Ok([d, yaw, pitch])
        }
        _ => Err(bad(
            "a distance of 0.05 to 50 m, a yaw in degrees and a pitch of -10 to 85 degrees",
        )),
    }
}

/// `WIDTHxHEIGHT` in pixels (image and video sizes of `proleg data plot`, `proleg run
/// --video`).
pub fn parse_size(s: &str) -> Result<(u32, u32), error::CliError> {
    let bad = |want| error::CliError::Option {
        option: "--size",
        value: s.to_string(),
        want,
    };
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| bad("expected WIDTHxHEIGHT, e.g. 1280x720"))?;
    let n = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| bad("WIDTH and HEIGHT are pixel counts"))
    };
    Ok((n(w)?, n(h)?))
}
