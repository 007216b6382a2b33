//! Videos for real: `proleg run --video` renders off-screen (no display) with Mesa's
//! software renderer, and the control window's Record button records under Xvfb; ffprobe
//! (Debian's ffmpeg, installed by the test command) decodes what they wrote.
#![cfg(feature = "gui")]

mod common;

use std::path::Path;
use std::process::Command;

use common::window::{get, scratch, state};

/// ffprobe's frame count, width and height of a video.
fn probe(video: &Path) -> (u64, u32, u32) {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=nb_read_frames,width,height",
            "-of",
            "csv=p=0",
        ])
        .arg(video)
        .output()
        .expect("ffprobe (Debian's ffmpeg; scripts/test installs it)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let v: Vec<u64> = text
        .trim()
        .split(',')
        .map(|x| x.parse().expect("number"))
        .collect();
    (v[2], v[0] as u32, v[1] as u32)
}

/// `proleg run ARGS` without a display; its output.
fn run_offscreen(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("XDG_RUNTIME_DIR", scratch("video-xdg"))
        .current_dir(common::root())
        .output()
        .expect("proleg");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

#[test]
fn a_run_renders_off_screen_into_a_video_with_one_frame_per_tick() {
    let dir = scratch("video");
    let video = dir.join("demo.mp4");
    let text = run_offscreen(&[
        "run",
        "configs/demo.simulation.xml",
        "--video",
        video.to_str().unwrap(),
        "--duration",
        "2",
        "--fps",
        "12",
        "--size",
        "320x240",
    ]);
    assert!(text.contains("24 frames, 320x240 at 12 fps"), "{text}");
    assert_eq!(probe(&video), (24, 320, 240));
    // A folder gets PNG frames; the camera follows the robot, so each shows it.
    let frames = dir.join("frames");
    run_offscreen(&[
        "run",
        "configs/demo.simulation.xml",
        "--video",
        frames.to_str().unwrap(),
        "--duration",
        "0.5",
        "--fps",
        "8",
        "--size",
        "160x120",
    ]);
    let pngs = common::files_ending(&frames, ".png");
    assert_eq!(pngs.len(), 4, "{pngs:?}");
    let (w, h, colours) = common::window::png_colours(&pngs[3]);
    assert_eq!((w, h), (160, 120));
    assert!(colours > 20, "the last frame has only {colours} colours");
}

#[test]
fn bad_video_requests_are_refused_with_the_reason() {
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args([
            "run",
            "configs/demo.simulation.xml",
            "--video",
            "x.mp4",
            "--size",
            "big",
        ])
        .current_dir(common::root())
        .output()
        .expect("proleg");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--size") && err.contains("WIDTHxHEIGHT"),
        "{err}"
    );
}

#[test]
fn the_record_button_records_what_the_window_shows() {
    let dir = scratch("record");
    let (video, st) = (dir.join("take.mp4"), dir.join("state.txt"));
    let script = dir.join("record.script");
    std::fs::write(
        &script,
        format!(
            "wait 2\nstart\nrecord on {}\nwait 8\nrecord off\nwait 2\nstate {}\nquit\n",
            video.display(),
            st.display()
        ),
    )
    .expect("script");
    let (ok, out) = common::window::run(&["gui", "configs/demo.simulation.xml"], &script);
    assert!(ok, "the window failed:\n{out}");
    let s = state(&st);
    assert_eq!(get(&s, "recording"), "false");
    assert_eq!(get(&s, "recording_file"), video.display().to_string());
    let frames: u64 = get(&s, "recorded_frames").parse().expect("frames");
    assert!(frames >= 4, "{frames} frames recorded in 8 window frames");
    assert_eq!(probe(&video), (frames, 1280, 800));
}
