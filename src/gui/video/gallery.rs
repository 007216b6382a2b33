//! A gallery of a co-design run's best bodies (`proleg results STORE --gallery out.png`):
//! each design ([`crate::optimize::gallery::best_designs`]) replayed from the store with its
//! own body and gait to a moment of its episode, rendered off-screen by the video's scene
//! and camera, and the pictures laid out in a grid, each captioned with its rank, score,
//! evaluation and body.

use std::path::PathBuf;

use bevy::prelude::*;
use plotters::prelude::*;

use super::sink::Frame;
use super::{VideoCamera, VideoError, WARM_UP, capture, render_target, video_app};
use crate::control::ModuleRegistry;
use crate::gui::control::session::SimSession;
use crate::gui::view3d::orbit::{OrbitCamera, to_bevy};
use crate::optimize::gallery::{GalleryEntry, best_designs};
use crate::optimize::replay::{ReplayError, load_replay};
use crate::optimize::store::{Store, StoreLocation};

/// Height (px) of each picture's caption.
const CAPTION: u32 = 46;

/// What to render.
#[derive(Debug, Clone, PartialEq)]
pub struct GalleryRequest {
    /// The store (SQLite file or postgres:// URL).
    pub store: String,
    /// The co-design run.
    pub run: i64,
    /// How many designs (the best distinct bodies).
    pub count: usize,
    /// Each picture's width and height (px).
    pub tile: (u32, u32),
    /// The moment of each design's episode shown (simulated seconds; the episode's end at
    /// most).
    pub at: f64,
    /// The PNG written.
    pub out: PathBuf,
}

/// What was rendered.
#[derive(Debug, Clone, PartialEq)]
pub struct GalleryReport {
    /// The PNG.
    pub out: PathBuf,
    /// The designs shown, best first.
    pub designs: Vec<GalleryEntry>,
    /// What their scores are (the run's fitness).
    pub fitness: String,
    /// Columns and rows of the grid.
    pub grid: (u32, u32),
}

impl std::fmt::Display for GalleryReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "gallery of {} designs ({} x {}, scored by {}) written to {}",
            self.designs.len(),
            self.grid.0,
            self.grid.1,
            self.fitness,
            self.out.display()
        )?;
        for (rank, d) in self.designs.iter().enumerate() {
            writeln!(
                f,
                "  {:>2}. {:.4}  evaluation {}  {}",
                rank + 1,
                d.score,
                d.number,
                d.body
            )?;
        }
        Ok(())
    }
}

/// Renders `req`'s gallery.
pub fn render_gallery(
    req: &GalleryRequest,
    registry: &ModuleRegistry,
) -> Result<GalleryReport, VideoError> {
    check(req)?;
    let location = StoreLocation::parse(&req.store).map_err(|e| replay(e.into()))?;
    let mut store = Store::open_existing(&location).map_err(|e| replay(e.into()))?;
    let designs = best_designs(&mut store, req.run, req.count, registry)
        .map_err(|e| VideoError::Designs(Box::new(e)))?;
    if designs.is_empty() {
        return Err(VideoError::NoDesigns { run: req.run });
    }
    let fitness = store
        .run_spec(req.run)
        .map_err(|e| replay(e.into()))?
        .info
        .fitness;
    let mut pictures = Vec::with_capacity(designs.len());
    let rendered = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        render_designs(req, &mut store, &designs, registry, &mut pictures)
    }))
    .map_err(|_| {
        VideoError::Renderer(
            "rendering failed (no usable graphics driver? Debian: mesa-vulkan-drivers)".into(),
        )
    })?;
    rendered?;
    let grid = grid_of(designs.len());
    compose(req, &designs, &fitness, &pictures, grid)?;
    Ok(GalleryReport {
        out: req.out.clone(),
        designs,
        fitness,
        grid,
    })
}

/// A store or evaluation that cannot be replayed.
fn replay(e: ReplayError) -> VideoError {
    VideoError::Replay(Box::new(e))
}

fn check(req: &GalleryRequest) -> Result<(), VideoError> {
    let option = |option, value: String, want| {
        Err(VideoError::Option {
            option,
            value,
            want,
        })
    };
    if !(1..=36).contains(&req.count) {
        return option(
            "--gallery-count",
            req.count.to_string(),
            "give 1 to 36 designs",
        );
    }
    let (w, h) = req.tile;
    if !(64..=1920).contains(&w) || !(64..=1080).contains(&h) {
        return option(
            "--gallery-tile",
            format!("{w}x{h}"),
            "give 64x64 to 1920x1080 pixels",
        );
    }
    if !(req.at.is_finite() && req.at >= 0.0) {
        return option(
            "--gallery-at",
            req.at.to_string(),
            "give a time in seconds, 0 or more",
        );
    }
    Ok(())
}

/// Columns and rows for `n` pictures: as square as it gets, wider than tall.
fn grid_of(n: usize) -> (u32, u32) {
    let cols = (n as f64).sqrt().ceil().max(1.0) as u32;
    let rows = (n as u32).div_ceil(cols);
    (cols, rows)
}

/// Replays each design to the moment shown and renders it into `pictures`.
fn render_designs(
    req: &GalleryRequest,
    store: &mut Store,
    designs: &[GalleryEntry],
    registry: &ModuleRegistry,
    pictures: &mut Vec<Frame>,
) -> Result<(), VideoError> {
    let mut app: Option<App> = None;
    let mut target = None;
    for d in designs {
        let replay = load_replay(store, req.run, d.number, None, registry).map_err(replay)?;
        let at = req.at.min(replay.duration);
        let app = match app.as_mut() {
            Some(app) => {
                app.world_mut()
                    .non_send_mut::<SimSession>()
                    .try_load_replay(replay)
                    .map_err(|e| VideoError::Session(Box::new(e)))?;
                app
            }
            None => {
                let session = SimSession::open_replay(replay, registry)
                    .map_err(|e| VideoError::Session(Box::new(e)))?;
                let mut new = video_app(session);
                let image = render_target(&mut new, req.tile);
                new.world_mut().spawn((
                    Name::new("gallery camera"),
                    VideoCamera,
                    Camera3d::default(),
                    bevy::camera::RenderTarget::from(image.clone()),
                    OrbitCamera::default().transform(),
                    OrbitCamera::default(),
                ));
                target = Some(image);
                app.insert(new)
            }
        };
        let Some(image) = &target else {
            return Err(VideoError::Renderer("no render target".into()));
        };
        app.world_mut()
            .non_send_mut::<SimSession>()
            .step_to(at, u64::MAX);
        frame_robot(app)?;
        pictures.push(capture(app, image, WARM_UP)?);
    }
    Ok(())
}

/// Points the camera at robot 0, far enough back to hold its whole length.
fn frame_robot(app: &mut App) -> Result<(), VideoError> {
    let (com, length) = {
        let session = app.world().non_send::<SimSession>();
        let com = session.simulator.com(0)?;
        let ys = session
            .sim
            .robot
            .links
            .iter()
            .map(|l| l.pose.translation[1]);
        let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        });
        (com, (hi - lo).max(0.0))
    };
    let world = app.world_mut();
    let mut cameras =
        world.query_filtered::<(&mut OrbitCamera, &mut Transform), With<VideoCamera>>();
    for (mut orbit, mut t) in cameras.iter_mut(world) {
        orbit.focus = to_bevy(com);
        orbit.distance = (0.4 + 1.3 * length).max(0.6) as f32;
        *t = orbit.transform();
    }
    Ok(())
}

/// Lays the pictures out in `grid` with their captions and writes the PNG.
fn compose(
    req: &GalleryRequest,
    designs: &[GalleryEntry],
    fitness: &str,
    pictures: &[Frame],
    (cols, rows): (u32, u32),
) -> Result<(), VideoError> {
    let (tw, th) = req.tile;
    let (w, h) = (cols * tw, rows * (th + CAPTION));
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    for (k, p) in pictures.iter().enumerate() {
        let (x0, y0) = ((k as u32 % cols) * tw, (k as u32 / cols) * (th + CAPTION));
        for y in 0..p.height.min(th) {
            for x in 0..p.width.min(tw) {
                let from = ((y * p.width + x) * 4) as usize;
                let to = (((y0 + y) * w + x0 + x) * 3) as usize;
                rgb[to..to + 3].copy_from_slice(&p.rgba[from..from + 3]);
            }
        }
    }
    caption(&mut rgb, (w, h), req, designs, fitness, cols)?;
    write_png(&req.out, &rgb, (w, h))
}

/// Writes each picture's caption under it.
fn caption(
    rgb: &mut [u8],
    size: (u32, u32),
    req: &GalleryRequest,
    designs: &[GalleryEntry],
    fitness: &str,
    cols: u32,
) -> Result<(), VideoError> {
    let (tw, th) = req.tile;
    let fail = |e: &dyn std::fmt::Display| VideoError::Caption {
        file: req.out.clone(),
        message: e.to_string(),
    };
    let area = BitMapBackend::with_buffer(rgb, size).into_drawing_area();
    for (k, d) in designs.iter().enumerate() {
        let (x0, y0) = ((k as u32 % cols) * tw, (k as u32 / cols) * (th + CAPTION));
        let (x, y) = (x0 as i32 + 8, (y0 + th) as i32 + 4);
        let lines = [
            format!(
                "{}. {fitness} {:.3}  (evaluation {})",
                k + 1,
                d.score,
                d.number
            ),
            d.body.clone(),
        ];
        for (i, line) in lines.iter().enumerate() {
            area.draw(&Text::new(
                line.as_str(),
                (x, y + 20 * i as i32),
                ("sans-serif", 17).into_font().color(&BLACK),
            ))
            .map_err(|e| fail(&e))?;
        }
    }
    area.present().map_err(|e| fail(&e))
}

fn write_png(path: &std::path::Path, rgb: &[u8], (w, h): (u32, u32)) -> Result<(), VideoError> {
    let io = |source| VideoError::Io {
        what: "write the gallery",
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut png = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    png.set_color(png::ColorType::Rgb);
    let mut writer = png
        .write_header()
        .map_err(|e| io(std::io::Error::other(e)))?;
    writer
        .write_image_data(rgb)
        .map_err(|e| io(std::io::Error::other(e)))?;
    writer.finish().map_err(|e| io(std::io::Error::other(e)))
}

#[cfg(test)]
mod tests {
    use super::grid_of;

    #[test]
    fn the_grid_is_as_square_as_it_gets() {
        assert_eq!(grid_of(1), (1, 1));
        assert_eq!(grid_of(4), (2, 2));
        assert_eq!(grid_of(6), (3, 2));
        assert_eq!(grid_of(9), (3, 3));
        assert_eq!(grid_of(10), (4, 3));
    }
}
