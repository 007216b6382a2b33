//! Videos of a run, rendered off-screen (`proleg run CONFIG --video out.mp4`): the control
//! window's scene ([`crate::gui::control::scene`]) drawn by a camera that follows the
//! robot into an image instead of a window, one frame every 1/fps simulated seconds, each
//! read back and handed to a [`sink::VideoSink`] (ffmpeg or PNG frames). Bevy's update
//! loop is pumped here, frame by frame, so the video's time is simulated time whatever
//! the rendering speed (no window, no display needed: Mesa's software Vulkan renders).
//! - [`frames`]: one picture of a world on demand (galleries, the dashboard's replays)
//! - [`gallery`]: a co-design run's best bodies in one picture (`results --gallery`)
//! - [`vulkan`]: the environment an off-screen renderer asks for on a headless machine

pub mod frames;
pub mod gallery;
pub mod sink;
pub mod vulkan;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use bevy::asset::RenderAssetUsages;
use bevy::camera::RenderTarget;
use bevy::log::LogPlugin;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::render_resource::{
    Extent3d, PollType, TextureDimension, TextureFormat, TextureUsages,
};
use bevy::render::renderer::RenderDevice;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;

use crate::gui::control::scene::{self, SceneBuilt};
use crate::gui::control::session::SimSession;
use crate::gui::view3d::orbit::{OrbitCamera, to_bevy};
use crate::optimize::replay::Replay;
use sink::{Frame, VideoSink, Written};

pub use crate::gui::error::VideoError;

/// What to render.
#[derive(Debug, Clone, PartialEq)]
pub struct VideoRequest {
    /// The simulation file.
    pub config: PathBuf,
    /// The video file (or a folder for PNG frames).
    pub out: PathBuf,
    /// Frames per simulated second.
    pub fps: u32,
    /// Width and height in pixels.
    pub size: (u32, u32),
    /// Simulated seconds (default: the file's duration).
    pub seconds: Option<f64>,
    /// The physics engine instead of the file's.
    pub engine: Option<crate::config::simulation::EngineKind>,
    /// Draw the ground's metre grid.
    pub grid: bool,
    /// Where the following camera looks from (default: [`VideoView::close`]).
    pub view: VideoView,
}

/// Where a video's camera looks at robot 0 from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VideoView {
    /// Distance from the robot's centre of mass (m).
    pub distance: f64,
    /// Degrees about the vertical: 0 looks along the robot's start heading from behind,
    /// positive from its left.
    pub yaw_deg: f64,
    /// Degrees above the ground.
    pub pitch_deg: f64,
}

impl VideoView {
    /// The videos' default: the perspective views' angles (their [`OrbitCamera`]
    /// default), closer, the robot filling the frame.
    pub fn close() -> VideoView {
        let orbit = OrbitCamera::default();
        VideoView {
            distance: 0.75,
            yaw_deg: f64::from(orbit.yaw).to_degrees(),
            pitch_deg: f64::from(orbit.pitch).to_degrees(),
        }
    }

    /// The orbit camera of this view.
    fn orbit(self) -> OrbitCamera {
        OrbitCamera {
            distance: self.distance as f32,
            yaw: self.yaw_deg.to_radians() as f32,
            pitch: self.pitch_deg.to_radians() as f32,
            ..OrbitCamera::default()
        }
    }
}

/// What was rendered.
#[derive(Debug, Clone, PartialEq)]
pub struct VideoReport {
    /// The file or folder written and its frame count.
    pub written: Written,
    /// Why the output differs from the one asked for (no ffmpeg), if it does.
    pub notice: Option<String>,
    /// Simulated seconds shown.
    pub seconds: f64,
    /// Frames per second and size.
    pub fps: u32,
    /// Width and height.
    pub size: (u32, u32),
    /// Simulated time of the last frame (frame k shows time k / fps).
    pub last_frame_time: f64,
    /// Horizontal displacement of the robot's centre of mass up to the last frame (m).
    pub displacement: f64,
}

impl std::fmt::Display for VideoReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(n) = &self.notice {
            writeln!(f, "{n}")?;
        }
        let what = if self.written.pngs {
            "PNG frames in"
        } else {
            "video"
        };
        writeln!(
            f,
            "{what} {}: {} frames, {}x{} at {} fps, {} s; displacement {:.4} m at the last frame ({:.3} s)",
            self.written.path.display(),
            self.written.frames,
            self.size.0,
            self.size.1,
            self.fps,
            self.seconds,
            self.displacement,
            self.last_frame_time
        )
    }
}

/// Frames read back, waiting to go out in order.
#[derive(Default)]
struct Captured {
    frames: BTreeMap<u64, Frame>,
    error: Option<VideoError>,
}

/// The camera of the video (follows robot 0).
#[derive(Component)]
struct VideoCamera;

/// Renders `req`'s run into its output.
pub fn record_video(
    req: &VideoRequest,
    registry: &crate::control::ModuleRegistry,
) -> Result<VideoReport, VideoError> {
    check(req)?;
    let session = SimSession::open(&req.config, req.engine, registry)
        .map_err(|e| VideoError::Session(Box::new(e)))?;
    record_session(session, req)
}

/// Renders a stored evaluation replayed as the optimization scored it (the dashboard's
/// videos) into `out`: `fps` frames per simulated second of its episode, `size` pixels.
pub fn record_replay_video(
    replay: Replay,
    out: &std::path::Path,
    fps: u32,
    size: (u32, u32),
    registry: &crate::control::ModuleRegistry,
) -> Result<VideoReport, VideoError> {
    let req = VideoRequest {
        config: PathBuf::from(&replay.config),
        out: out.to_path_buf(),
        fps,
        size,
        seconds: Some(replay.duration),
        engine: Some(replay.engine),
        grid: true,
        view: VideoView::close(),
    };
    check(&req)?;
    let session =
        SimSession::open_replay(replay, registry).map_err(|e| VideoError::Session(Box::new(e)))?;
    record_session(session, &req)
}

/// Renders an open session for `req`'s seconds (default: its file's duration) into `req.out`.
fn record_session(session: SimSession, req: &VideoRequest) -> Result<VideoReport, VideoError> {
    let seconds = req
        .seconds
        .unwrap_or(session.sim.files.simulation.properties.duration);
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(VideoError::Option {
            option: "--duration",
            value: seconds.to_string(),
            want: "give a positive number of seconds",
        });
    }
    let frames = (seconds * f64::from(req.fps)).round().max(1.0) as u64;
    let start = session.simulator.com(0).unwrap_or_default();
    let (mut sink, notice) = VideoSink::open(&req.out, req.size, req.fps)?;
    let captured = Arc::new(Mutex::new(Captured::default()));
    let rendered = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        render(session, req, frames, &captured, &mut sink)
    }))
    .map_err(|_| {
        VideoError::Renderer(
            "rendering failed (no usable graphics driver? Debian: mesa-vulkan-drivers)".into(),
        )
    })?;
    let end = rendered?;
    let written = sink.finish()?;
    Ok(VideoReport {
        written,
        notice,
        seconds: frames as f64 / f64::from(req.fps),
        last_frame_time: (frames - 1) as f64 / f64::from(req.fps),
        fps: req.fps,
        size: req.size,
        displacement: crate::measure::ground_distance(start, end),
    })
}

fn check(req: &VideoRequest) -> Result<(), VideoError> {
    if req.fps == 0 || req.fps > 240 {
        return Err(VideoError::Option {
            option: "--fps",
            value: req.fps.to_string(),
            want: "give 1 to 240 frames per second",
        });
    }
    check_size(req.size)
}

/// Refuses a picture size the renderer cannot make.
fn check_size((w, h): (u32, u32)) -> Result<(), VideoError> {
    if !(16..=7680).contains(&w) || !(16..=4320).contains(&h) {
        return Err(VideoError::Option {
            option: "--size",
            value: format!("{w}x{h}"),
            want: "give 16x16 to 7680x4320 pixels",
        });
    }
    Ok(())
}

/// Pumps the app: each frame, steps to its time, renders and reads it back; returns robot
/// 0's final centre of mass.
fn render(
    session: SimSession,
    req: &VideoRequest,
    frames: u64,
    captured: &Arc<Mutex<Captured>>,
    sink: &mut VideoSink,
) -> Result<[f64; 3], VideoError> {
    let (mut app, target) = following_app(session, req.size, req.view);
    app.insert_resource(crate::gui::view3d::meshes::ShowGrid(req.grid));
    // The scene is built on the first update and reaches the render world updates later:
    // without these, the first frames were black or empty sky.
    for _ in 0..WARM_UP {
        update(&mut app)?;
    }
    let mut next = 0;
    for k in 0..frames {
        let t = k as f64 / f64::from(req.fps);
        app.world_mut()
            .non_send_mut::<SimSession>()
            .step_to(t, u64::MAX);
        let shared = captured.clone();
        app.world_mut()
            .spawn(Screenshot::image(target.clone()))
            .observe(move |shot: On<ScreenshotCaptured>| {
                let frame = to_frame(&shot.image);
                if let Ok(mut c) = shared.lock() {
                    match frame {
                        Ok(f) => {
                            c.frames.insert(k, f);
                        }
                        Err(e) => c.error = Some(e),
                    }
                }
            });
        update(&mut app)?;
        next = drain(captured, sink, next)?;
    }
    // Read-backs finish an update or two after their frame.
    for _ in 0..8 {
        if next >= frames {
            break;
        }
        update(&mut app)?;
        next = drain(captured, sink, next)?;
    }
    if next < frames {
        return Err(VideoError::Renderer(format!(
            "only {next} of {frames} frames came back from the renderer"
        )));
    }
    let session = app.world().non_send::<SimSession>();
    Ok(session.simulator.com(0)?)
}

/// The app: Bevy's plugins without windows or winit, the scene of the control window and
/// the following camera. Without Bevy's log plugin: a video is drawn inside other
/// programs too (the command line, the optimizer's gallery, a Python process rendering an
/// environment), whose own logging it must neither take over nor fill with the renderer's
/// adapter report.
fn video_app(session: SimSession) -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .set(RenderPlugin {
                synchronous_pipeline_compilation: true,
                ..default()
            })
            .disable::<WinitPlugin>()
            .disable::<LogPlugin>(),
    )
    .insert_resource(ClearColor(Color::srgb(0.62, 0.74, 0.86)))
    .insert_non_send(session)
    .init_resource::<SceneBuilt>()
    .add_systems(Startup, crate::gui::view3d::meshes::spawn_lights)
    .add_systems(
        Update,
        (
            scene::build_scene,
            scene::follow_bodies,
            scene::colour_pads,
            follow_robot,
        )
            .chain(),
    );
    app.finish();
    app.cleanup();
    app
}

/// The video's app with an image of `size` to render into and a camera that follows robot
/// 0 from `view`.
fn following_app(session: SimSession, size: (u32, u32), view: VideoView) -> (App, Handle<Image>) {
    let mut app = video_app(session);
    let target = render_target(&mut app, size);
    let orbit = view.orbit();
    app.world_mut().spawn((
        Name::new("video camera"),
        VideoCamera,
        Camera3d::default(),
        RenderTarget::from(target.clone()),
        orbit.transform(),
        orbit,
    ));
    (app, target)
}

/// An image to render into.
fn render_target(app: &mut App, (width, height): (u32, u32)) -> Handle<Image> {
    let mut image = Image::new_uninit(
        Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        TextureFormat::Rgba8UnormSrgb,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.texture_descriptor.usage |= TextureUsages::RENDER_ATTACHMENT;
    app.world_mut().resource_mut::<Assets<Image>>().add(image)
}

/// One update, waiting for the GPU to finish it.
fn update(app: &mut App) -> Result<(), VideoError> {
    app.update();
    app.world()
        .resource::<RenderDevice>()
        .wgpu_device()
        .poll(PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .map(|_| ())
        .map_err(|e| VideoError::Renderer(format!("the renderer failed: {e}")))
}

/// Writes the frames that are next in order; returns the next frame expected.
fn drain(
    captured: &Arc<Mutex<Captured>>,
    sink: &mut VideoSink,
    mut next: u64,
) -> Result<u64, VideoError> {
    let mut c = captured
        .lock()
        .map_err(|_| VideoError::Renderer("a frame read-back panicked".into()))?;
    if let Some(e) = c.error.take() {
        return Err(e);
    }
    while let Some(frame) = c.frames.remove(&next) {
        sink.push(&frame)?;
        next += 1;
    }
    Ok(next)
}

/// Updates before a picture of a newly built scene is taken (the scene's meshes reach the
/// render world an update after the scene is built).
const WARM_UP: usize = 3;

/// Renders one frame into `image` after `warm_up` updates and reads it back (the gallery's
/// pictures, an environment's frames).
fn capture(app: &mut App, image: &Handle<Image>, warm_up: usize) -> Result<Frame, VideoError> {
    // The scene is rebuilt on the first update and its meshes are ready for the render
    // world an update later: a read-back spawned before then shows an empty frame.
    for _ in 0..warm_up {
        update(app)?;
    }
    let shot = Arc::new(Mutex::new(None));
    let shared = shot.clone();
    app.world_mut()
        .spawn(Screenshot::image(image.clone()))
        .observe(move |s: On<ScreenshotCaptured>| {
            if let Ok(mut slot) = shared.lock() {
                *slot = Some(to_frame(&s.image));
            }
        });
    for _ in 0..10 {
        update(app)?;
        let taken = shot
            .lock()
            .map_err(|_| VideoError::Renderer("a read-back panicked".into()))?
            .take();
        if let Some(frame) = taken {
            return frame;
        }
    }
    Err(VideoError::Renderer(
        "no picture came back from the renderer".into(),
    ))
}

/// A read-back image as RGBA bytes.
fn to_frame(image: &Image) -> Result<Frame, VideoError> {
    let rgba = image
        .clone()
        .try_into_dynamic()
        .map_err(|e| VideoError::Renderer(format!("a frame could not be read: {e}")))?
        .to_rgba8();
    Ok(Frame {
        width: rgba.width(),
        height: rgba.height(),
        rgba: rgba.into_raw(),
    })
}

/// Keeps robot 0's centre of mass in focus, smoothed over frames (as the window's follow
/// mode, but per frame, so the video does not depend on rendering speed).
fn follow_robot(
    session: NonSend<SimSession>,
    mut cameras: Query<(&mut OrbitCamera, &mut Transform), With<VideoCamera>>,
) {
    let Ok(com) = session.simulator.com(0) else {
        return;
    };
    for (mut orbit, mut t) in &mut cameras {
        let target = to_bevy(com);
        orbit.focus = orbit.focus.lerp(target, 0.2);
        *t = orbit.transform();
    }
}
