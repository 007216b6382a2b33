//! The commands that open a window or render off-screen: the control window (`proleg gui`,
//! a replay), the configuration window (`proleg wizard`), `proleg run --video` and
//! `proleg results --gallery`. A build without the `gui` feature answers each with why it
//! has no windows.

use std::path::PathBuf;

use crate::cli;
use crate::cli::DEMO_CONFIG;
use crate::cli::error::CliError;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::plugin_host::PluginHost;

use super::Printed;

/// What a headless build says when asked for a window.
#[cfg(not(feature = "gui"))]
const NO_WINDOWS: &str = "this proleg was built without the `gui` feature, so it has no windows: \
scripts/demo builds the complete program (it installs the Debian packages the windows need, \
libudev-dev among them, and runs `cargo build --release`); the headless commands work here \
(proleg --help)";

/// `proleg gui`: the control window on a simulation, or replaying a stored evaluation.
#[derive(clap::Args, Debug)]
pub struct GuiArgs {
    /// A `*.simulation.xml` file.
    #[arg(default_value = DEMO_CONFIG)]
    pub config: PathBuf,
    /// Replay a stored evaluation instead: the store (a results .sqlite file or a
    /// postgres:// URL) holding the run.
    #[arg(long, requires = "run")]
    pub replay: Option<String>,
    /// With --replay: the run's id (`proleg results STORE` lists them).
    #[arg(long, requires = "replay")]
    pub run: Option<i64>,
    /// With --replay: the evaluation's number, or "best".
    #[arg(long, default_value = "best", requires = "replay")]
    pub eval: String,
    /// With --replay of a run with robust fitness: the randomized episode (default 0).
    #[arg(long, requires = "replay")]
    pub episode: Option<u32>,
    /// Drive the window from a script (tests, screenshots; see proleg::gui::control::script).
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// Gamepad bindings (`*.remote.xml`; default: configs/remote/default.remote.xml).
    #[arg(long)]
    pub remote: Option<PathBuf>,
    /// The physics engine instead of the one the simulation file names (rapier, mujoco).
    #[arg(long)]
    pub engine: Option<EngineKind>,
}

impl GuiArgs {
    /// The window `proleg` opens without a command: the demo.
    pub fn demo() -> GuiArgs {
        GuiArgs {
            config: PathBuf::from(DEMO_CONFIG),
            replay: None,
            run: None,
            eval: "best".into(),
            episode: None,
            script: None,
            remote: None,
            engine: None,
        }
    }
}

/// `proleg wizard`: the configuration window's folders and what it opens.
#[derive(clap::Args, Debug)]
pub struct WizardArgs {
    /// The configuration folder (module parts, robots, environments, ...).
    #[arg(long, default_value = "configs")]
    pub configs: PathBuf,
    /// Where new files are written.
    #[arg(long, default_value = "configs/user")]
    pub out: PathBuf,
    /// Open this `*.env.xml` in the environment editor.
    #[arg(long, conflicts_with = "expert")]
    pub env: Option<PathBuf>,
    /// Open this `*.simulation.xml` in the expert composition.
    #[arg(long)]
    pub expert: Option<PathBuf>,
    /// Drive the window from a script (tests, screenshots; see proleg::gui::setup::script).
    #[arg(long)]
    pub script: Option<PathBuf>,
}

/// The control window on `args.config`, or replaying the stored evaluation `--replay`
/// names (on `--engine` if given).
pub fn gui(args: &GuiArgs, host: PluginHost, registry: &ModuleRegistry) -> Printed {
    let replay = match (&args.replay, args.run) {
        (Some(store), Some(run)) => {
            use crate::optimize::replay::{Which, replay_from};
            let replay = Which::parse(&args.eval)
                .and_then(|which| replay_from(store, run, which, args.episode, registry))?;
            Some(match args.engine {
                Some(e) => replay.on_engine(e),
                None => replay,
            })
        }
        _ => None,
    };
    #[cfg(feature = "gui")]
    {
        let engine = if replay.is_some() { None } else { args.engine };
        crate::gui::run(
            &args.config,
            engine,
            replay,
            args.script.as_deref(),
            args.remote.as_deref(),
            host,
        )
        .map(|()| String::new())
        .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        drop((replay, host));
        Err(Box::new(CliError::Options(NO_WINDOWS)))
    }
}

/// `proleg wizard`: the configuration window.
pub fn wizard(args: WizardArgs, host: PluginHost) -> Printed {
    #[cfg(feature = "gui")]
    {
        let options = crate::gui::setup::SetupOptions {
            configs: args.configs,
            out: args.out,
            env: args.env,
            expert: args.expert,
            script: args.script,
        };
        crate::gui::setup::run(&options, host)
            .map(|()| String::new())
            .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        drop((args, host));
        Err(Box::new(CliError::Options(NO_WINDOWS)))
    }
}

/// `proleg run --video`: the file's own run rendered off-screen.
pub fn video(req: &cli::run::RunRequest, registry: &ModuleRegistry) -> Printed {
    if req.seed.is_some() || req.data.is_some() || !req.physics.is_empty() || req.realtime != 0.0 {
        return Err(Box::new(CliError::Options(
            "--video renders the file's own run: leave out --seed, --data, --physics and --realtime",
        )));
    }
    #[cfg(feature = "gui")]
    {
        let request = crate::gui::video::VideoRequest {
            config: req.config.clone(),
            out: req.video.clone().unwrap_or_default(),
            fps: req.fps,
            size: req.size,
            seconds: req.duration,
            engine: req.engine,
            grid: !req.no_grid,
            view: req.camera.map_or(
                crate::gui::video::VideoView::close(),
                |[distance, yaw_deg, pitch_deg]| crate::gui::video::VideoView {
                    distance,
                    yaw_deg,
                    pitch_deg,
                },
            ),
        };
        crate::gui::video::record_video(&request, registry)
            .map(|r| r.to_string())
            .map_err(Into::into)
    }
    #[cfg(not(feature = "gui"))]
    {
        let _ = registry;
        Err(Box::new(CliError::Options(NO_WINDOWS)))
    }
}

/// `proleg results --gallery`: the stores' report, then the first run's best bodies
/// rendered off-screen into the gallery's PNG.
pub fn results(args: &cli::results::ResultsArgs, registry: &ModuleRegistry) -> Printed {
    let report = cli::results::run(&args.options()?, registry)?;
    let run = report
        .stores
        .first()
        .and_then(|(_, runs)| runs.first())
        .ok_or(CliError::NoRun(0))?
        .id;
    #[cfg(feature = "gui")]
    {
        let request = crate::gui::video::gallery::GalleryRequest {
            store: args.stores[0].clone(),
            run,
            count: args.gallery_count,
            tile: args.gallery_tile,
            at: args.gallery_at,
            out: args.gallery.clone().unwrap_or_default(),
        };
        let gallery = crate::gui::video::gallery::render_gallery(&request, registry)?;
        Ok(format!("{report}{gallery}"))
    }
    #[cfg(not(feature = "gui"))]
    {
        let _ = run;
        Err(Box::new(CliError::Options(NO_WINDOWS)))
    }
}

/// What renders the dashboard's videos: the off-screen renderer of `proleg run --video`
/// (none in a build without the `gui` feature; the page then says why).
pub fn video_renderer() -> Option<std::sync::Arc<dyn crate::dashboard::media::VideoRenderer>> {
    #[cfg(feature = "gui")]
    {
        Some(std::sync::Arc::new(OffscreenRenderer))
    }
    #[cfg(not(feature = "gui"))]
    {
        None
    }
}

/// The dashboard's videos, rendered off-screen and encoded by ffmpeg.
#[cfg(feature = "gui")]
struct OffscreenRenderer;

#[cfg(feature = "gui")]
impl crate::dashboard::media::VideoRenderer for OffscreenRenderer {
    fn render(
        &self,
        replay: crate::optimize::replay::Replay,
        out: &std::path::Path,
        registry: &ModuleRegistry,
    ) -> Result<(), crate::dashboard::media::RenderFailure> {
        use crate::dashboard::media::{VIDEO_FPS, VIDEO_SIZE};
        if !crate::gui::video::sink::have_ffmpeg() {
            return Err(Box::new(crate::gui::video::VideoError::Ffmpeg(
                "no ffmpeg installed (Debian: apt install ffmpeg), so no videos".into(),
            )));
        }
        crate::gui::video::record_replay_video(replay, out, VIDEO_FPS, VIDEO_SIZE, registry)?;
        Ok(())
    }
}
