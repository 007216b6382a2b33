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
fn a_video_on_a_machine_with_no_session_prints_nothing_that_looks_like_a_failure() {
    // No XDG_RUNTIME_DIR, as on a cluster node or in CI: Mesa's device-select layer would
    // have libwayland print "error: XDG_RUNTIME_DIR is invalid ..." twice.
    let video = scratch("video-no-session").join("demo.mp4");
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["run", "configs/demo.simulation.xml", "--duration", "0.2"])
        .args(["--size", "160x120", "--video", video.to_str().unwrap()])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .current_dir(common::root())
        .output()
        .expect("proleg");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        !err.to_lowercase().contains("error"),
        "a green run says no error: {err}"
    );
    assert_eq!(probe(&video).0, 6);
}

/// The first PNG frame of the demo rendered into `dir` (320x180), with `extra` options.
fn first_frame(dir: &Path, extra: &[&str]) -> (Vec<u8>, usize) {
    let mut args = vec![
        "run",
        "configs/demo.simulation.xml",
        "--video",
        dir.to_str().unwrap(),
        "--duration",
        "0.5",
        "--fps",
        "4",
        "--size",
        "320x180",
    ];
    args.extend(extra);
    run_offscreen(&args);
    let pngs = common::files_ending(dir, ".png");
    assert_eq!(pngs.len(), 2, "{pngs:?}");
    let (pixels, _, _, bpp) = common::window::png_pixels(&pngs[0]);
    (pixels, bpp)
}

#[test]
fn the_first_frame_shows_the_scene_and_the_ground_carries_a_metre_grid_unless_turned_off() {
    let dir = scratch("video-grid");
    let (grid, bpp) = first_frame(&dir.join("grid"), &[]);
    let (plain, _) = first_frame(&dir.join("plain"), &["--no-grid"]);
    let pixels = grid.len() / bpp;
    // Frame 0 is the scene at time 0, not a black or empty picture.
    let mean_green = grid.chunks(bpp).map(|p| f64::from(p[1])).sum::<f64>() / pixels as f64;
    assert!(
        mean_green > 120.0,
        "mean green {mean_green}: the ground is shown"
    );
    // The grid's lines: pixels darker with the grid than without it, the rest alike.
    let (mut darker, mut other) = (0usize, 0usize);
    for (a, b) in grid.chunks(bpp).zip(plain.chunks(bpp)) {
        let sum = |p: &[u8]| p[..3].iter().map(|&c| i32::from(c)).sum::<i32>();
        match sum(a) - sum(b) {
            d if d < -30 => darker += 1,
            d if d > 30 => other += 1,
            _ => {}
        }
    }
    assert!(
        darker > pixels / 200,
        "{darker} of {pixels} pixels darkened by grid lines"
    );
    assert!(other < darker / 10, "{other} pixels brighter with the grid");
}

#[test]
fn the_camera_option_moves_the_video_camera_back_and_round() {
    let dir = scratch("video-camera");
    // The robot's saturated blue modules, which neither the ground nor the sky has.
    let robot_pixels = |pixels: &[u8], bpp: usize| {
        pixels
            .chunks(bpp)
            .filter(|p| {
                i32::from(p[2]) > i32::from(p[1]) + 50 && i32::from(p[2]) > i32::from(p[0]) + 80
            })
            .count()
    };
    let (close, bpp) = first_frame(&dir.join("close"), &[]);
    let (far, _) = first_frame(&dir.join("far"), &["--camera", "4,-25,40"]);
    let (near, far) = (robot_pixels(&close, bpp), robot_pixels(&far, bpp));
    assert!(near > 1000, "{near} robot pixels in the default close view");
    assert!(
        far > 20 && far * 6 < near,
        "4 m back the robot covers {far} pixels, close up {near}"
    );
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
    for camera in ["4,-25", "0,0,30", "4,0,95", "4,NaN,30"] {
        let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
            .args(["run", "configs/demo.simulation.xml", "--video", "x.mp4"])
            .arg(format!("--camera={camera}"))
            .current_dir(common::root())
            .output()
            .expect("proleg");
        assert!(!out.status.success(), "--camera {camera} accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--camera") && err.contains(camera), "{err}");
    }
    // Without a video there is no camera to place: refused, not ignored.
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["run", "configs/demo.simulation.xml", "--camera", "3,0,30"])
        .current_dir(common::root())
        .output()
        .expect("proleg");
    assert!(!out.status.success(), "--camera without --video accepted");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--video"), "{err}");
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

#[test]
#[expect(
    clippy::too_many_lines,
    reason = "one scenario, read top to bottom (tests may run past 80 lines)"
)]
fn a_co_design_gallery_shows_each_best_body_rendered_and_captioned() {
    let dir = scratch("gallery");
    let store = dir.join("codesign.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/codesign_flat.simulation.xml",
        ("40", "1"),
        &store,
        &[],
    );
    assert!(ok, "{err}");
    let png = dir.join("gallery.png");
    let out = run_offscreen(&[
        "results",
        store.to_str().unwrap(),
        "--gallery",
        png.to_str().unwrap(),
        "--gallery-count",
        "4",
        "--gallery-tile",
        "160x120",
        "--gallery-at",
        "0.5",
    ]);
    // Four distinct bodies, best first, each with its stored evaluation.
    let ranked: Vec<(f64, String)> = out
        .lines()
        .skip_while(|l| !l.starts_with("gallery of 4 designs (2 x 2"))
        .skip(1)
        .map(|l| {
            let mut w = l.split_whitespace().skip(1);
            let score: f64 = w.next().unwrap().parse().unwrap();
            let body: Vec<&str> = w.skip(2).collect();
            (score, body.join(" "))
        })
        .collect();
    assert_eq!(ranked.len(), 4, "{out}");
    assert!(ranked.windows(2).all(|p| p[0].0 >= p[1].0), "{ranked:?}");
    let mut bodies: Vec<&String> = ranked.iter().map(|(_, b)| b).collect();
    bodies.dedup();
    assert_eq!(bodies.len(), 4, "{ranked:?}");
    // A 2 x 2 grid of 160 x 120 pictures, each over a 46-px caption; every picture
    // shows a scene (many colours, not an empty frame) and each differs from the others.
    let (pixels, w, h, channels) = common::window::png_pixels(&png);
    assert_eq!((w, h), (320, 2 * (120 + 46)));
    let tile = |k: u32| -> Vec<[u8; 3]> {
        let (x0, y0) = ((k % 2) * 160, (k / 2) * 166);
        let mut v = Vec::new();
        for y in y0..y0 + 120 {
            for x in x0..x0 + 160 {
                let i = ((y * w + x) as usize) * channels;
                v.push([pixels[i], pixels[i + 1], pixels[i + 2]]);
            }
        }
        v
    };
    let tiles: Vec<Vec<[u8; 3]>> = (0..4).map(tile).collect();
    for (k, t) in tiles.iter().enumerate() {
        let mut colours = t.clone();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 50, "picture {k}: {} colours", colours.len());
    }
    for a in 0..4 {
        for b in a + 1..4 {
            assert_ne!(tiles[a], tiles[b], "pictures {a} and {b}");
        }
    }

    // A run of one fixed body has no gallery: said plainly.
    let gait = dir.join("gait.sqlite");
    let (ok, _, err) = common::optimize(
        "configs/gait_flat.simulation.xml",
        ("10", "0.2"),
        &gait,
        &[],
    );
    assert!(ok, "{err}");
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["results", gait.to_str().unwrap(), "--gallery"])
        .arg(dir.join("none.png"))
        .current_dir(common::root())
        .output()
        .expect("proleg");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("a gallery shows the bodies of a co-design run"),
        "{err}"
    );
    assert!(!dir.join("none.png").exists());
}
