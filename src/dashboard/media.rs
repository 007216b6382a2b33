//! An evaluation's video, data file and 3D replay, made on demand: the page asks for them,
//! one thread makes them in order (a queue: never two renders at once, however many pages
//! ask), each replayed from the store as the optimization scored it
//! ([`crate::optimize::replay`]) and kept in a cache folder, so each is made once. The data
//! file and the 3D replay's pose stream (on the run's engine or the other) are recorded
//! headless by the replay itself; the video by a [`VideoRenderer`] the builds with a
//! renderer supply (the off-screen renderer of `proleg run --video`); without one the page
//! says why there is no video.

use std::collections::{HashMap, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

use serde::Serialize;

use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::optimize::replay::{Replay, load_replay};
use crate::optimize::store::{Store, StoreLocation};

/// Why a video could not be rendered: the renderer's own error.
pub type RenderFailure = Box<dyn std::error::Error + Send + Sync>;

/// What renders a replayed evaluation into a WebM video (the off-screen renderer).
pub trait VideoRenderer: Send + Sync {
    /// Renders `replay`'s whole episode into the WebM file `out`.
    fn render(
        &self,
        replay: Replay,
        out: &Path,
        registry: &ModuleRegistry,
    ) -> Result<(), RenderFailure>;
}

/// Which of an evaluation's media.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// The episode as a WebM video.
    Video,
    /// The episode's B.8 data file.
    Data,
    /// The episode replayed on this engine as the 3D viewer's pose stream (JSON).
    Replay(EngineKind),
}

impl Kind {
    /// The cached file's extension.
    fn extension(self) -> &'static str {
        match self {
            Kind::Video => "webm",
            Kind::Data => "data.xml",
            Kind::Replay(EngineKind::Rapier) => "replay-rapier.json",
            Kind::Replay(EngineKind::Mujoco) => "replay-mujoco.json",
        }
    }

    /// What it is, as messages name it.
    pub fn what(self) -> &'static str {
        match self {
            Kind::Video => "video",
            Kind::Data => "data file",
            Kind::Replay(_) => "3D replay",
        }
    }
}

/// One medium of one evaluation: what the queue makes.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Job {
    /// The run.
    pub run: i64,
    /// When the run started, so that a store made again with the same run ids never shows
    /// another run's cached files.
    pub started: String,
    /// The evaluation's number.
    pub number: u64,
    /// Video or data file.
    pub kind: Kind,
}

/// Where a medium is.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "state", rename_all = "lowercase")]
pub enum MediaState {
    /// Not asked for yet.
    Absent,
    /// Waiting: `ahead` jobs are made before it.
    Queued {
        /// Jobs before it.
        ahead: usize,
    },
    /// Being made now.
    Making,
    /// Made: the page may load it.
    Ready,
    /// It could not be made; why.
    Failed {
        /// The cause, as it reads.
        error: String,
    },
    /// This build has no renderer (videos only).
    Unavailable {
        /// Why.
        error: String,
    },
}

/// The queue and what it made, shared by the web server and the thread that works it.
pub struct Media {
    /// The cache folder of this store.
    folder: PathBuf,
    renderer: Option<Arc<dyn VideoRenderer>>,
    state: Mutex<Queue>,
    wake: Condvar,
}

/// The jobs waiting and those that failed (made ones are files in the folder).
#[derive(Default)]
struct Queue {
    waiting: VecDeque<Job>,
    making: Option<Job>,
    failed: HashMap<Job, String>,
}

/// Pixels and frames per simulated second of the dashboard's videos: a laptop screen's
/// panel, cheap to render on a small machine.
pub const VIDEO_SIZE: (u32, u32) = (640, 360);
/// Frames per simulated second.
pub const VIDEO_FPS: u32 = 25;

impl Media {
    /// Media of the store `store` (as shown, no password) cached under `cache`.
    pub fn new(cache: &Path, store: &str, renderer: Option<Arc<dyn VideoRenderer>>) -> Media {
        Media {
            folder: cache.join(folder_name(store)),
            renderer,
            state: Mutex::new(Queue::default()),
            wake: Condvar::new(),
        }
    }

    /// The file a job makes.
    pub fn file(&self, job: &Job) -> PathBuf {
        self.named(job, "")
    }

    /// The file a job makes, with `part` before its extension.
    fn named(&self, job: &Job, part: &str) -> PathBuf {
        let started: String = job.started.chars().filter(char::is_ascii_digit).collect();
        self.folder.join(format!(
            "run{}-{started}-eval{}{part}.{}",
            job.run,
            job.number,
            job.kind.extension()
        ))
    }

    /// Where `job` is.
    pub fn state(&self, job: &Job) -> MediaState {
        if job.kind == Kind::Video && self.renderer.is_none() {
            return MediaState::Unavailable {
                error: "this proleg was built without the renderer (the gui feature), so it \
                        makes no videos"
                    .into(),
            };
        }
        if self.file(job).is_file() {
            return MediaState::Ready;
        }
        let Ok(q) = self.state.lock() else {
            return MediaState::Failed {
                error: "the media queue is not readable".into(),
            };
        };
        if q.making.as_ref() == Some(job) {
            return MediaState::Making;
        }
        if let Some(ahead) = q.waiting.iter().position(|j| j == job) {
            return MediaState::Queued {
                ahead: ahead + usize::from(q.making.is_some()),
            };
        }
        match q.failed.get(job) {
            Some(error) => MediaState::Failed {
                error: error.clone(),
            },
            None => MediaState::Absent,
        }
    }

    /// Asks for `job` (again, after a failure); a job already made, waiting or being made
    /// is asked for once. Returns where it is then.
    pub fn request(&self, job: Job) -> MediaState {
        match self.state(&job) {
            MediaState::Absent | MediaState::Failed { .. } => {}
            other => return other,
        }
        if let Ok(mut q) = self.state.lock() {
            q.failed.remove(&job);
            q.waiting.push_back(job.clone());
            self.wake.notify_one();
        }
        self.state(&job)
    }

    /// Makes the jobs asked for, one at a time, until `stop` is set (the dashboard's
    /// media thread).
    pub fn work(&self, location: &StoreLocation, registry: &ModuleRegistry, stop: &AtomicBool) {
        while !stop.load(Ordering::Relaxed) {
            let Some(job) = self.next_job() else {
                continue;
            };
            let made = self.make(&job, location, registry);
            if let Ok(mut q) = self.state.lock() {
                q.making = None;
                if let Err(e) = made {
                    q.failed.insert(job, e.to_string());
                }
            }
        }
    }

    /// The next job, marked as being made; `None` after a short wait with nothing to do
    /// (so the caller sees a stop).
    fn next_job(&self) -> Option<Job> {
        let q = self.state.lock().ok()?;
        let (mut q, _) = self
            .wake
            .wait_timeout_while(q, Duration::from_millis(200), |q| q.waiting.is_empty())
            .ok()?;
        let job = q.waiting.pop_front()?;
        q.making = Some(job.clone());
        Some(job)
    }

    /// Replays `job`'s evaluation into a file beside its final name, then renames it (a
    /// file in the cache is always whole).
    fn make(
        &self,
        job: &Job,
        location: &StoreLocation,
        registry: &ModuleRegistry,
    ) -> Result<(), MediaError> {
        let done = self.file(job);
        std::fs::create_dir_all(&self.folder).map_err(|source| MediaError::Io {
            path: self.folder.clone(),
            source,
        })?;
        let mut store = Store::open_existing(location)?;
        let replay = load_replay(&mut store, job.run, job.number, None, registry)?;
        drop(store);
        let part = self.named(job, ".part");
        match job.kind {
            Kind::Data => {
                replay.record_data(&part, registry)?;
            }
            Kind::Video => {
                let renderer = self.renderer.as_ref().ok_or(MediaError::NoRenderer)?;
                renderer
                    .render(replay, &part, registry)
                    .map_err(MediaError::Render)?;
            }
            Kind::Replay(engine) => {
                let replay = if engine == replay.engine {
                    replay
                } else {
                    replay.on_engine(engine)
                };
                let stream = replay.pose_stream(registry, crate::playback::DEFAULT_FPS)?;
                std::fs::write(&part, stream.to_json()?).map_err(|source| MediaError::Io {
                    path: part.clone(),
                    source,
                })?;
            }
        }
        std::fs::rename(&part, &done).map_err(|source| MediaError::Io { path: done, source })
    }
}

/// Why a medium could not be made.
#[derive(Debug, thiserror::Error)]
pub enum MediaError {
    /// The cache folder or file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The folder or file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The store could not be read.
    #[error("{0}")]
    Store(#[from] crate::optimize::store::StoreError),
    /// The evaluation could not be replayed.
    #[error("{0}")]
    Replay(#[from] crate::optimize::replay::ReplayError),
    /// The 3D replay's stream could not be encoded.
    #[error("{0}")]
    Playback(#[from] crate::playback::PlaybackError),
    /// A video asked of a build without renderer.
    #[error("this build has no renderer")]
    NoRenderer,
    /// The renderer failed.
    #[error("rendering failed: {0}")]
    Render(RenderFailure),
}

/// A folder name for a store: its description with every character that is not a letter,
/// digit, dot or dash replaced.
fn folder_name(store: &str) -> String {
    store
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The cache folder when none is given: `$XDG_CACHE_HOME/proleg/dashboard`, else
/// `~/.cache/proleg/dashboard`, else the system's temporary folder.
pub fn default_cache() -> PathBuf {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir);
    base.join("proleg").join("dashboard")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_store_gets_a_folder_name_without_separators() {
        assert_eq!(
            folder_name("postgres://u@h:5432/db"),
            "postgres___u_h_5432_db"
        );
        assert_eq!(folder_name("/a/b/runs.sqlite"), "_a_b_runs.sqlite");
    }

    #[test]
    fn a_video_without_renderer_is_unavailable_and_a_data_file_queues_once() {
        let dir = std::env::temp_dir().join(format!("proleg-media-{}", std::process::id()));
        let media = Media::new(&dir, "store", None);
        let job = |kind| Job {
            run: 1,
            started: "2026-11-28 03:00:00".into(),
            number: 4,
            kind,
        };
        assert!(matches!(
            media.request(job(Kind::Video)),
            MediaState::Unavailable { .. }
        ));
        assert_eq!(
            media.request(job(Kind::Data)),
            MediaState::Queued { ahead: 0 }
        );
        assert_eq!(
            media.request(job(Kind::Data)),
            MediaState::Queued { ahead: 0 }
        );
        assert_eq!(
            media.file(&job(Kind::Data)),
            dir.join("store").join("run1-20261128030000-eval4.data.xml")
        );
    }
}
