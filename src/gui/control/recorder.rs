//! The Record button: what the control window shows, one video frame per window frame,
//! into `out/recordings/NAME-TIME.mp4` (ffmpeg; PNG frames without it). The window's
//! frames are captured with Bevy's screenshot of the primary window and handed to the
//! same [`VideoSink`] the off-screen videos use.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy_egui::egui;

use crate::gui::video::sink::{Frame, VideoSink};

/// Frames per second the recording plays at (the window's nominal rate).
pub const RECORD_FPS: u32 = 30;

/// A recording in progress, shared with the screenshot observers.
struct Take {
    /// The output; `None` until the first frame gives the size.
    sink: Option<VideoSink>,
    /// Where it goes.
    out: PathBuf,
    /// Frames written.
    frames: u64,
    /// Frames of another size than the first (the window was resized), left out.
    skipped: u64,
    /// The first error, which ends the take.
    error: Option<String>,
    /// Stopped: frames still in flight are dropped.
    closed: bool,
}

/// The recorder's state (toolbar button, script `record on|off`).
#[derive(Resource, Default)]
pub struct Recorder {
    take: Option<Arc<Mutex<Take>>>,
    /// What the last recording wrote, or why it failed.
    pub status: Option<String>,
    /// The last finished recording's file and frame count.
    pub last: Option<(PathBuf, u64)>,
}

impl Recorder {
    /// Whether a recording runs.
    pub fn recording(&self) -> bool {
        self.take.is_some()
    }

    /// Frames of the running take so far.
    pub fn frames(&self) -> u64 {
        self.take
            .as_ref()
            .and_then(|t| t.lock().ok().map(|t| t.frames))
            .unwrap_or(0)
    }

    /// Starts a take into `out`, or of the configuration `config` into
    /// `out/recordings/` (named after it and the time).
    pub fn start(&mut self, config: &Path, out: Option<PathBuf>) {
        let out = out.unwrap_or_else(|| default_file(config));
        self.status = Some(format!("recording to {}", out.display()));
        self.take = Some(Arc::new(Mutex::new(Take {
            sink: None,
            out,
            frames: 0,
            skipped: 0,
            error: None,
            closed: false,
        })));
    }

    /// Ends the take and closes its file.
    pub fn stop(&mut self) {
        let Some(take) = self.take.take() else {
            return;
        };
        let Ok(mut t) = take.lock() else {
            self.status = Some("the recording was lost (a capture panicked)".into());
            return;
        };
        t.closed = true;
        let finished = t.sink.take().map(VideoSink::finish).transpose();
        self.status = Some(match (finished, t.error.take()) {
            (_, Some(e)) => format!("recording failed: {e}"),
            (Err(e), None) => format!("recording failed: {e}"),
            (Ok(None), None) => "nothing recorded".into(),
            (Ok(Some(w)), None) => {
                self.last = Some((w.path.clone(), w.frames));
                let skipped = if t.skipped > 0 {
                    format!(" ({} frames of another size left out)", t.skipped)
                } else {
                    String::new()
                };
                format!(
                    "recorded {} frames to {}{skipped}",
                    w.frames,
                    w.path.display()
                )
            }
        });
    }
}

/// `out/recordings/NAME-TIME.mp4` for configuration `config`.
fn default_file(config: &Path) -> PathBuf {
    let stem = config
        .file_name()
        .map(|n| {
            n.to_string_lossy()
                .trim_end_matches(".simulation.xml")
                .to_string()
        })
        .unwrap_or_else(|| "proleg".into());
    PathBuf::from("out/recordings").join(format!(
        "{stem}-{}.mp4",
        crate::compose::paths::timestamp_now()
    ))
}

/// Adds one take's frame.
fn add_frame(take: &Mutex<Take>, image: &Image) {
    let Ok(mut t) = take.lock() else {
        return;
    };
    if t.error.is_some() || t.closed {
        return;
    }
    let rgba = match image.clone().try_into_dynamic() {
        Ok(i) => i.to_rgba8(),
        Err(e) => {
            t.error = Some(format!("a frame could not be read: {e}"));
            return;
        }
    };
    let frame = Frame {
        width: rgba.width(),
        height: rgba.height(),
        rgba: rgba.into_raw(),
    };
    if t.sink.is_none() {
        match VideoSink::open(&t.out.clone(), (frame.width, frame.height), RECORD_FPS) {
            Ok((sink, notice)) => {
                t.sink = Some(sink);
                if let Some(n) = notice {
                    bevy::log::warn!("{n}");
                }
            }
            Err(e) => {
                t.error = Some(e.to_string());
                return;
            }
        }
    }
    let size = match &t.sink {
        Some(VideoSink::Ffmpeg { size, .. }) => Some(*size),
        _ => None,
    };
    if size.is_some_and(|s| s != (frame.width, frame.height)) {
        t.skipped += 1;
        return;
    }
    let pushed = t.sink.as_mut().map(|s| s.push(&frame));
    match pushed {
        Some(Ok(())) => t.frames += 1,
        Some(Err(e)) => t.error = Some(e.to_string()),
        None => {}
    }
}

/// Asks for this frame's picture while a take runs.
pub fn capture(mut commands: Commands, recorder: Res<Recorder>) {
    if let Some(take) = &recorder.take {
        let take = take.clone();
        commands
            .spawn(Screenshot::primary_window())
            .observe(move |shot: On<ScreenshotCaptured>| add_frame(&take, &shot.image));
    }
}

/// The Record / Stop button and the last recording's status.
pub fn button(ui: &mut egui::Ui, recorder: &mut Recorder, config: &Path) {
    if recorder.recording() {
        let label = format!("⏹ Stop recording ({} frames)", recorder.frames());
        if ui.button(label).clicked() {
            recorder.stop();
        }
    } else if ui
        .button("⏺ Record")
        .on_hover_text("Records what this window shows into out/recordings/ (MP4 with ffmpeg, else PNG frames)")
        .clicked()
    {
        recorder.start(config, None);
    }
    if let Some(s) = &recorder.status {
        ui.label(s);
    }
}

/// The Record button's capture of each frame.
pub struct RecorderPlugin;

impl Plugin for RecorderPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Recorder>().add_systems(
            Update,
            capture.in_set(crate::gui::control::schedule::GuiSystems::Capture),
        );
    }
}
