//! A 3D replay in the browser: an episode recorded as its bodies' poses per frame with the
//! scene drawn once (a pose stream), and the viewer page (three.js) that plays one or two
//! of them on one timeline — served by the dashboard, or one self-contained HTML file
//! (`proleg run --html`, the Python environments' `save_html`).
//!
//! - [`scene`]: what is drawn: bodies, their geometries, meshes and height fields, pads
//! - [`stream`]: the [`PoseStream`] and the [`stream::Recorder`] that fills it frame by frame
//! - [`record`]: an episode run to its end while it is recorded
//! - [`encode`]: base64 arrays and the quantizations of poses, angles and heights
//! - [`page`]: the viewer's page and its assets, built into the binary
//! - [`error`]: why a replay could not be made

pub mod encode;
pub mod error;
pub mod page;
pub mod record;
pub mod scene;
pub mod stream;

pub use error::PlaybackError;
pub use record::{DEFAULT_FPS, Recorded, Recording, record_episode};
pub use stream::PoseStream;
