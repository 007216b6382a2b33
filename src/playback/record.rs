//! An episode run to its end while it is recorded: stepped a frame's steps at a time
//! through the episode runner ([`Episode::advance`], so the exit rule and the stop flag
//! act as in any run), the world sampled after each frame.

use crate::config::Simulation;
use crate::playback::error::PlaybackError;
use crate::playback::scene::Scene;
use crate::playback::stream::{PoseStream, Recorder, StreamInfo};
use crate::signal::StopFlag;
use crate::sim::{Episode, EpisodeEnd, Simulator, WorldExit};

/// Frames per simulated second when nobody asks for another rate.
pub const DEFAULT_FPS: f64 = 30.0;

/// How a replay is recorded.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// Frames per simulated second asked for (the frame period is a whole number of
    /// steps, the nearest).
    pub fps: f64,
    /// What was run, for the page.
    pub label: String,
}

/// The recorded stream and how the episode ended.
pub struct Recorded {
    /// The stream.
    pub stream: PoseStream,
    /// How the episode ended.
    pub end: EpisodeEnd,
}

/// Steps between two frames of `fps` frames per second at step `dt`: at least one.
pub fn steps_per_frame(fps: f64, dt: f64) -> Result<u64, PlaybackError> {
    if !(fps.is_finite() && fps > 0.0) {
        return Err(PlaybackError::Fps(fps));
    }
    Ok(((1.0 / (fps * dt)).round() as u64).max(1))
}

/// Runs `episode` (begun on `simulator`, built from `sim`) to its end, recording it.
pub fn record_episode(
    sim: &Simulation,
    simulator: &mut Simulator,
    episode: &mut Episode,
    recording: &Recording,
    stop: Option<&StopFlag>,
) -> Result<Recorded, PlaybackError> {
    let dt = simulator.clock().dt;
    let every = steps_per_frame(recording.fps, dt)?;
    let frames = episode
        .settings()
        .steps
        .map_or(0, |s| (s / every) as usize + 2);
    let mut recorder = Recorder::new(Scene::of(sim, simulator)?, frames);
    recorder.sample(simulator, episode.score(simulator, 0)?)?;
    let end = loop {
        let before = episode.steps(simulator);
        let end = episode.advance(simulator, every, stop)?;
        if episode.steps(simulator) > before {
            recorder.sample(simulator, episode.score(simulator, 0)?)?;
        }
        if let Some(end) = end {
            break end;
        }
    };
    let info = StreamInfo {
        label: recording.label.clone(),
        engine: simulator.engine().settings(),
        frame_seconds: every as f64 * dt,
        score_name: episode.settings().fitness.name().to_string(),
    };
    Ok(Recorded {
        stream: recorder.stream(info, &end_text(end)),
        end,
    })
}

/// How an episode ended, as the page says it.
pub fn end_text(end: EpisodeEnd) -> String {
    match end {
        EpisodeEnd::Duration => "ran its duration".into(),
        EpisodeEnd::Stopped => "stopped".into(),
        EpisodeEnd::Left(WorldExit::Diverged) => "the physics diverged".into(),
        EpisodeEnd::Left(WorldExit::Left(c)) => format!(
            "the robot left the world at ({:.2}, {:.2}, {:.2}) m",
            c[0], c[1], c[2]
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::steps_per_frame;

    #[test]
    fn a_frame_is_the_whole_number_of_steps_nearest_the_rate_asked_for() {
        // At an environment's 20-ms step as at a physics step.
        let every = |fps| steps_per_frame(fps, 0.02).ok();
        assert_eq!(every(25.0), Some(2));
        assert_eq!(every(30.0), Some(2));
        assert_eq!(every(50.0), Some(1));
        assert_eq!(every(1000.0), Some(1));
        assert_eq!(every(10.0), Some(5));
        assert!(steps_per_frame(0.0, 0.02).is_err());
    }
}
