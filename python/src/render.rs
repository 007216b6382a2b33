//! Pictures and videos of an environment's world through the off-screen renderer that
//! `proleg run --video` uses (`proleg::gui::video`): `Renderer` draws an `Env`'s world
//! as an RGB array, `VideoWriter` encodes frames with ffmpeg (or numbered PNG files).

use std::path::PathBuf;

use numpy::{PyArray1, PyArray3, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use proleg::gui::control::session::SimSession;
use proleg::gui::video::frames::FrameRenderer;
use proleg::gui::video::sink::{Frame, VideoSink};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use crate::errors::other;
use crate::simulation::{Env, engine};

/// An off-screen renderer of one simulation file's worlds (it lives on the thread that
/// made it: Bevy's renderer is not shared between threads).
#[pyclass(module = "proleg._native", unsendable)]
pub struct Renderer {
    renderer: FrameRenderer,
    /// The environment episode drawn last, to notice a new world.
    drawn: Option<u64>,
}

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(signature = (path, width=640, height=480, engine_name=None))]
    fn new(
        py: Python<'_>,
        path: PathBuf,
        width: u32,
        height: u32,
        engine_name: Option<&str>,
    ) -> PyResult<Renderer> {
        let kind = engine(engine_name)?;
        let registry = crate::modules::registry(py)?;
        let session = SimSession::open(&path, kind, registry).map_err(other)?;
        let renderer = FrameRenderer::new(session, (width, height)).map_err(other)?;
        Ok(Renderer {
            renderer,
            drawn: None,
        })
    }

    /// The picture of `env`'s world now: an (height, width, 3) uint8 array.
    fn frame<'py>(
        &mut self,
        py: Python<'py>,
        mut env: PyRefMut<'py, Env>,
    ) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let env = env.inner_mut()?;
        let episode = env.episodes();
        let rebuilt = self.drawn != Some(episode);
        let frame = self
            .renderer
            .frame(env.world_mut(), rebuilt)
            .map_err(other)?;
        self.drawn = Some(episode);
        let rgb: Vec<u8> = frame
            .rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        PyArray1::from_vec(py, rgb).reshape([frame.height as usize, frame.width as usize, 3])
    }
}

/// Frames into a video file (ffmpeg, by the file's extension) or a folder of PNG files.
#[pyclass(module = "proleg._native")]
pub struct VideoWriter {
    sink: Option<VideoSink>,
    size: (u32, u32),
}

#[pymethods]
impl VideoWriter {
    #[new]
    #[pyo3(signature = (path, width, height, fps=50))]
    fn new(path: PathBuf, width: u32, height: u32, fps: u32) -> PyResult<VideoWriter> {
        if fps == 0 || fps > 240 {
            return Err(PyValueError::new_err(format!("fps {fps}: give 1 to 240")));
        }
        let (sink, _notice) = VideoSink::open(&path, (width, height), fps).map_err(other)?;
        Ok(VideoWriter {
            sink: Some(sink),
            size: (width, height),
        })
    }

    /// Appends an (height, width, 3) uint8 frame.
    fn write(&mut self, frame: PyReadonlyArray3<'_, u8>) -> PyResult<()> {
        let (w, h) = self.size;
        let shape = frame.shape();
        if shape != [h as usize, w as usize, 3] {
            return Err(PyValueError::new_err(format!(
                "frame of shape {shape:?}, expected ({h}, {w}, 3)"
            )));
        }
        let rgb = frame.as_slice()?;
        let rgba: Vec<u8> = rgb
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect();
        let sink = self
            .sink
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("the video is closed"))?;
        sink.push(&Frame {
            width: w,
            height: h,
            rgba,
        })
        .map_err(other)
    }

    /// Finishes the file; returns its path and the frames written.
    fn close(&mut self) -> PyResult<(String, u64)> {
        let sink = self
            .sink
            .take()
            .ok_or_else(|| PyRuntimeError::new_err("the video is closed"))?;
        let written = sink.finish().map_err(other)?;
        Ok((written.path.display().to_string(), written.frames))
    }
}

/// The environment variable (name, value) to set before the first renderer starts on a
/// machine with no desktop session, or `None` (`proleg::gui::video::vulkan`); Python sets
/// it through `os.environ`, so its view of the environment stays true.
#[pyfunction]
pub fn headless_vulkan_setting() -> Option<(&'static str, &'static str)> {
    proleg::gui::video::vulkan::headless_setting_here()
}
