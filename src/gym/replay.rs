//! An environment's episode recorded for the browser's 3D replay (the option `replay_fps`,
//! Python's `ProlegEnv.save_html`): a [`Recorder`] begun on every reset's fresh world,
//! sampled every few environment steps, read back as a [`PoseStream`] at any time — the
//! frames so far of the running episode, or all of the one that ended.
//!
//! A frame is a state the caller saw: the frame period is the whole number of environment
//! steps nearest `1 / replay_fps` (at least one), and the step that ends an episode is
//! always recorded.

use crate::config::Simulation;
use crate::gym::error::GymError;
use crate::playback::PoseStream;
use crate::playback::record::end_text;
use crate::playback::scene::Scene;
use crate::playback::stream::{Recorder, StreamInfo};
use crate::sim::{EpisodeEnd, Simulator};

/// One episode's recording.
pub struct EnvReplay {
    recorder: Recorder,
    every: u64,
    info: StreamInfo,
    control_period: f64,
    steps: u64,
    end: Option<EpisodeEnd>,
}

impl EnvReplay {
    /// A recording of the episode about to start on `world` (built from `sim`), a frame
    /// every `every` environment steps of `control_period` seconds, room made for
    /// `max_steps` steps; its first frame is the world now.
    pub fn begin(
        sim: &Simulation,
        world: &Simulator,
        every: u64,
        control_period: f64,
        max_steps: u64,
        info: (String, String),
    ) -> Result<EnvReplay, GymError> {
        let every = every.max(1);
        let frames = (max_steps / every) as usize + 2;
        let mut recorder = Recorder::new(Scene::of(sim, world)?, frames);
        recorder.sample(world, 0.0)?;
        let (label, score_name) = info;
        Ok(EnvReplay {
            recorder,
            every,
            info: StreamInfo {
                label,
                engine: world.engine().settings(),
                frame_seconds: every as f64 * control_period,
                score_name,
            },
            control_period,
            steps: 0,
            end: None,
        })
    }

    /// After the episode's `steps`-th step, with its `score` so far and how it ended, if it
    /// did: records the world when a frame is due or the episode is over.
    pub fn after_step(
        &mut self,
        world: &Simulator,
        steps: u64,
        score: f64,
        end: Option<EpisodeEnd>,
    ) -> Result<(), GymError> {
        if steps.is_multiple_of(self.every) || end.is_some() {
            self.recorder.sample(world, score)?;
        }
        self.steps = steps;
        self.end = end;
        Ok(())
    }

    /// The frames recorded so far, as the page plays them; `label` instead of the
    /// episode's own.
    pub fn stream(&self, label: Option<&str>) -> PoseStream {
        let mut info = self.info.clone();
        if let Some(l) = label {
            info.label = l.to_string();
        }
        let end = match self.end {
            Some(end) => end_text(end),
            None => format!(
                "stepped for {:.2} s so far (the episode goes on)",
                self.steps as f64 * self.control_period
            ),
        };
        self.recorder.stream(info, &end)
    }
}
