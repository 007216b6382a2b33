//! One picture of a world on demand: the video's off-screen app and following camera
//! (`super::following_app`), for a simulator that lives elsewhere (an environment's). The
//! simulator is lent for the frame: swapped into the renderer's session, drawn, swapped
//! back, so the renderer never steps it and the caller's world stays the caller's.

use bevy::prelude::*;

use crate::gui::control::session::SimSession;
use crate::gui::video::sink::Frame;
use crate::gui::video::{VideoError, VideoView, WARM_UP, capture, check_size, following_app};
use crate::sim::Simulator;

/// An off-screen renderer of other simulators' worlds.
pub struct FrameRenderer {
    app: App,
    target: Handle<Image>,
    size: (u32, u32),
}

impl FrameRenderer {
    /// A renderer of `size` pixels whose scene is built from `session`'s configuration
    /// (the worlds it draws must be of the same simulation file).
    pub fn new(session: SimSession, size: (u32, u32)) -> Result<FrameRenderer, VideoError> {
        check_size(size)?;
        let (app, target) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            following_app(session, size, VideoView::close())
        }))
        .map_err(|_| no_renderer())?;
        Ok(FrameRenderer { app, target, size })
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The picture of `world` now. `rebuilt` says the world is a new one (the first frame,
    /// a reset): the scene's bodies are looked up again and given updates to reach the
    /// renderer before the picture is taken.
    pub fn frame(&mut self, world: &mut Simulator, rebuilt: bool) -> Result<Frame, VideoError> {
        self.lend(world, rebuilt);
        let warm_up = if rebuilt { WARM_UP } else { 0 };
        let shot = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            capture(&mut self.app, &self.target, warm_up)
        }))
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
}

fn no_renderer() -> VideoError {
    VideoError::Renderer(
        "rendering failed (no usable graphics driver? Debian: mesa-vulkan-drivers)".into(),
    )
}
