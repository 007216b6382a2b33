//! Where video frames go: an ffmpeg process (MP4, WebM, GIF, ... by the file's extension)
//! fed raw RGBA frames on its standard input, or numbered PNG files in a folder when the
//! output is a folder or no ffmpeg is installed.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use crate::gui::video::VideoError;

/// A frame's pixels: width, height, RGBA bytes (row-major, no padding).
pub struct Frame {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub rgba: Vec<u8>,
}

/// An open video output.
pub enum VideoSink {
    /// ffmpeg encoding to a file.
    Ffmpeg {
        /// The encoder process.
        child: Child,
        /// Its standard input.
        stdin: Option<ChildStdin>,
        /// The video file.
        file: PathBuf,
        /// The frame size it was opened with.
        size: (u32, u32),
        /// Frames written.
        frames: u64,
    },
    /// Numbered PNG files.
    Pngs {
        /// The folder.
        dir: PathBuf,
        /// Frames written.
        frames: u64,
    },
}

/// What a finished sink wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The video file or the PNG folder.
    pub path: PathBuf,
    /// Frames written.
    pub frames: u64,
    /// Whether it is a folder of PNG frames.
    pub pngs: bool,
}

/// Whether an ffmpeg is installed.
pub fn have_ffmpeg() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

impl VideoSink {
    /// Opens `out` for frames of `size` at `fps`: a folder (no extension, or an existing
    /// folder) gets PNG frames, a file is encoded by ffmpeg; without ffmpeg the frames go
    /// to a folder named after the file (the notice says so).
    pub fn open(
        out: &Path,
        size: (u32, u32),
        fps: u32,
    ) -> Result<(VideoSink, Option<String>), VideoError> {
        let folder = out.is_dir() || out.extension().is_none();
        if folder || !have_ffmpeg() {
            let dir = if folder {
                out.to_path_buf()
            } else {
                out.with_extension("")
            };
            std::fs::create_dir_all(&dir).map_err(|source| VideoError::Io {
                what: "create the folder",
                path: dir.clone(),
                source,
            })?;
            let notice = (!folder).then(|| {
                format!(
                    "no ffmpeg installed (Debian: apt install ffmpeg): PNG frames go to {} instead of {}",
                    dir.display(),
                    out.display()
                )
            });
            return Ok((VideoSink::Pngs { dir, frames: 0 }, notice));
        }
        if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| VideoError::Io {
                what: "create the folder",
                path: dir.to_path_buf(),
                source,
            })?;
        }
        let gif = out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gif"));
        let mut cmd = Command::new("ffmpeg");
        cmd.args([
            "-y",
            "-loglevel",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgba",
        ])
        .args([
            "-s",
            &format!("{}x{}", size.0, size.1),
            "-r",
            &fps.to_string(),
            "-i",
            "-",
        ]);
        if !gif {
            // Even sizes for yuv420p, which every player decodes.
            cmd.args([
                "-vf",
                "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                "-pix_fmt",
                "yuv420p",
            ]);
        }
        let mut child = cmd
            .arg(out)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| VideoError::Ffmpeg(format!("cannot start it: {e}")))?;
        let stdin = child.stdin.take();
        Ok((
            VideoSink::Ffmpeg {
                child,
                stdin,
                file: out.to_path_buf(),
                size,
                frames: 0,
            },
            None,
        ))
    }

    /// Appends a frame; a frame of another size than the video's is refused.
    pub fn push(&mut self, frame: &Frame) -> Result<(), VideoError> {
        match self {
            VideoSink::Ffmpeg {
                stdin,
                size,
                frames,
                file,
                ..
            } => {
                if (frame.width, frame.height) != *size {
                    return Err(VideoError::FrameSize {
                        got: (frame.width, frame.height),
                        want: *size,
                    });
                }
                let pipe = stdin
                    .as_mut()
                    .ok_or_else(|| VideoError::Ffmpeg("the encoder is closed".into()))?;
                pipe.write_all(&frame.rgba).map_err(|e| {
                    VideoError::Ffmpeg(format!("{} stopped taking frames: {e}", file.display()))
                })?;
                *frames += 1;
            }
            VideoSink::Pngs { dir, frames } => {
                *frames += 1;
                let path = dir.join(format!("frame_{frames:05}.png"));
                let file = std::fs::File::create(&path).map_err(|source| VideoError::Io {
                    what: "write",
                    path: path.clone(),
                    source,
                })?;
                let mut png =
                    png::Encoder::new(std::io::BufWriter::new(file), frame.width, frame.height);
                png.set_color(png::ColorType::Rgba);
                png.write_header()
                    .and_then(|mut w| w.write_image_data(&frame.rgba))
                    .map_err(|e| VideoError::Io {
                        what: "write",
                        path: path.clone(),
                        source: std::io::Error::other(e),
                    })?;
            }
        }
        Ok(())
    }

    /// Closes the output (waits for ffmpeg to finish the file).
    pub fn finish(self) -> Result<Written, VideoError> {
        match self {
            VideoSink::Ffmpeg {
                child,
                stdin,
                file,
                frames,
                ..
            } => {
                drop(stdin);
                let out = child
                    .wait_with_output()
                    .map_err(|e| VideoError::Ffmpeg(e.to_string()))?;
                if !out.status.success() {
                    return Err(VideoError::Ffmpeg(format!(
                        "could not write {}: {}",
                        file.display(),
                        String::from_utf8_lossy(&out.stderr).trim()
                    )));
                }
                Ok(Written {
                    path: file,
                    frames,
                    pngs: false,
                })
            }
            VideoSink::Pngs { dir, frames } => Ok(Written {
                path: dir,
                frames,
                pngs: true,
            }),
        }
    }
}
