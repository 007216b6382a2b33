//! Running proleg's windows in tests: under `xvfb-run` with Mesa's software renderer when
//! there is no display, driven by a script; reading the state files and screenshots they
//! write.

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Longest the window may take (llvmpipe renders ~2 frames per second under load).
const WATCHDOG: Duration = Duration::from_secs(600);

pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("proleg-gui-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Runs `proleg ARGS --script SCRIPT` (under xvfb-run without a display); returns
/// whether it succeeded and what it printed.
pub fn run(args: &[&str], script: &Path) -> (bool, String) {
    run_env(args, script, &[])
}

/// [`run`] with these environment variables set for the window.
pub fn run_env(args: &[&str], script: &Path, env: &[(&str, &str)]) -> (bool, String) {
    let exe = env!("CARGO_BIN_EXE_proleg");
    let mut cmd = if std::env::var_os("DISPLAY").is_some() {
        Command::new(exe)
    } else {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1280x800x24", exe]);
        c
    };
    let runtime = scratch("xdg");
    cmd.args(args)
        .arg("--script")
        .arg(script)
        .env("XDG_RUNTIME_DIR", &runtime)
        .env("WGPU_BACKEND", "vulkan")
        .envs(env.iter().copied())
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd
        .spawn()
        .expect("start proleg gui (is xvfb-run installed?)");
    let started = Instant::now();
    loop {
        match child.try_wait().expect("wait for the window") {
            Some(_) => break,
            None if started.elapsed() > WATCHDOG => {
                let _ = child.kill();
                break;
            }
            None => std::thread::sleep(Duration::from_millis(200)),
        }
    }
    let out = child.wait_with_output().expect("window output");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// key = value lines of a state file.
pub fn state(path: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(path).expect("state file written");
    text.lines()
        .filter_map(|l| l.split_once(" = "))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

pub fn get<'a>(s: &'a [(String, String)], key: &str) -> &'a str {
    s.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
        .unwrap_or_else(|| panic!("no {key} in the state"))
}

/// Decodes a PNG: its pixels, width, height and bytes per pixel.
pub fn png_pixels(path: &Path) -> (Vec<u8>, u32, u32, usize) {
    let file = std::fs::File::open(path).expect("the PNG was written");
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("PNG frame");
    buf.truncate(info.buffer_size());
    let bpp = info.line_size / info.width as usize;
    (buf, info.width, info.height, bpp)
}

/// Decodes a PNG and counts its distinct colours (a blank or failed render has one).
pub fn png_colours(path: &Path) -> (u32, u32, usize) {
    let (buf, width, height, bpp) = png_pixels(path);
    let mut colours: Vec<&[u8]> = buf.chunks(bpp).collect();
    colours.sort();
    colours.dedup();
    (width, height, colours.len())
}

/// An Xvfb server on a display of its own, stopped when dropped.
pub struct Xvfb(Child, pub String);

impl Xvfb {
    /// Starts a server on a free display; returns once it accepts clients (`-displayfd`
    /// writes the display number then).
    pub fn start() -> Xvfb {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x800x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb (Debian's xvfb)");
        let stdout = child.stdout.take().expect("Xvfb's output");
        let mut line = String::new();
        std::io::BufReader::new(stdout)
            .read_line(&mut line)
            .expect("Xvfb's display");
        Xvfb(child, format!(":{}", line.trim()))
    }

    /// Runs xdotool on this display (at most 5 minutes: a window that never shows fails).
    pub fn xdotool(&self, args: &[&str]) -> String {
        let out = Command::new("timeout")
            .arg("300")
            .arg("xdotool")
            .args(args)
            .env("DISPLAY", &self.1)
            .output()
            .expect("xdotool (Debian's xdotool; scripts/test installs it)");
        assert!(
            out.status.success(),
            "xdotool {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}
