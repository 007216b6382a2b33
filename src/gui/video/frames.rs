//! One picture of a world on demand: the video's off-screen app and following camera
//! (`super::video_app`), for a simulator that lives elsewhere (an environment's). The
//! simulator is lent for the frame: swapped into the renderer's session, drawn, swapped
//! back, so the renderer never steps it and the caller's world stays the caller's.

use std::sync::{Arc, Mutex};

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};

use crate::gui::control::camera::OrbitCamera;
use crate::gui::control::session::SimSession;
use crate::gui::video::sink::Frame;
use crate::gui::video::{
    Captured, VideoCamera, VideoError, drain_one, render_target, update, video_app,
};
use crate::sim::Simulator;

/// Updates a frame may take to come back from the renderer.
const MAX_UPDATES: usize = 8;

/// An off-screen renderer of other simulators' worlds.
pub struct FrameRenderer {
    app: App,
    target: Handle<Image>,
    captured: Arc<Mutex<Captured>>,
    size: (u32, u32),
    frames: u64,
}

impl FrameRenderer {
    /// A renderer of `size` pixels whose scene is built from `session`'s configuration
    /// (the worlds it draws must be of the same simulation file).
    pub fn new(session: SimSession, size: (u32, u32)) -> Result<FrameRenderer, VideoError> {
        super::check_size(size)?;
        let built = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut app = video_app(session);
            let target = render_target(&mut app, size);
            let orbit = OrbitCamera {
                distance: 0.75,
                ..OrbitCamera::default()
            };
            app.world_mut().spawn((
                Name::new("frame camera"),
                VideoCamera,
                Camera3d::default(),
                bevy::camera::RenderTarget::from(target.clone()),
                orbit.transform(),
                orbit,
            ));
            (app, target)
        }))
        .map_err(|_| no_renderer())?;
        Ok(FrameRenderer {
            app: built.0,
            target: built.1,
            captured: Arc::new(Mutex::new(Captured::default())),
            size,
            frames: 0,
        })
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The picture of `world` now. `rebuilt` says the world is a new one (a reset), so the
    /// scene's bodies are looked up again.
    pub fn frame(&mut self, world: &mut Simulator, rebuilt: bool) -> Result<Frame, VideoError> {
        self.lend(world, rebuilt);
        let shot = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.capture()))
            .map_err(|_| no_renderer());
        self.lend(world, false);
        shot?
    }

    /// Swaps `world` with the session's simulator.
    fn lend(&mut self, world: &mut Simulator, rebuilt: bool) {
        let mut session = self.app.world_mut().non_send_mut::<SimSession>();
        std::mem::swap(&mut session.simulator, world);
        if rebuilt {
            session.generation += 1;
        }
    }

    /// Asks for a screenshot and updates until it is back.
    fn capture(&mut self) -> Result<Frame, VideoError> {
        let k = self.frames;
        self.frames += 1;
        let shared = self.captured.clone();
        self.app
            .world_mut()
            .spawn(Screenshot::image(self.target.clone()))
            .observe(move |shot: On<ScreenshotCaptured>| {
                let frame = super::to_frame(&shot.image);
                if let Ok(mut c) = shared.lock() {
                    match frame {
                        Ok(f) => {
                            c.frames.insert(k, f);
                        }
                        Err(e) => c.error = Some(e),
                    }
                }
            });
        for _ in 0..MAX_UPDATES {
            update(&mut self.app)?;
            if let Some(f) = drain_one(&self.captured, k)? {
                return Ok(f);
            }
        }
        Err(VideoError::Renderer(format!(
            "frame {k} did not come back from the renderer in {MAX_UPDATES} updates"
        )))
    }
}

fn no_renderer() -> VideoError {
    VideoError::Renderer(
        "rendering failed (no usable graphics driver? Debian: mesa-vulkan-drivers)".into(),
    )
}
