//! The gamepad remote without hardware: a synthetic gamepad in a headless Bevy App (the
//! messages gilrs would send), read by `GamepadRemotePlugin`, applied with the default
//! binding to the 8-module pitch-yaw robot's kernel. The stick steers the robot left and
//! right, the frequency axis changes its speed, parameters stop at their limits.
#![cfg(feature = "gui")]

use bevy::input::InputPlugin;
use bevy::input::gamepad::{
    GamepadAxis, GamepadButton, GamepadConnection, GamepadConnectionEvent,
    RawGamepadAxisChangedEvent, RawGamepadButtonChangedEvent, RawGamepadEvent,
};
use bevy::prelude::*;
use proleg::config::remote::{RemoteAction, default_gamepad_bindings};
use proleg::config::resolve::robot::JointOrientation;
use proleg::remote::gamepad::{GamepadRemote, GamepadRemotePlugin};
use proleg::remote::{Remote, RemoteMapper};
use proleg::sim::{BuildOptions, Simulator};

const CONFIG: &str = "configs/snake8py_remote.simulation.xml";

/// A headless App with one synthetic gamepad connected to the remote.
fn pad_app() -> (App, Entity) {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, InputPlugin, GamepadRemotePlugin));
    let pad = app.world_mut().spawn_empty().id();
    app.world_mut().write_message(GamepadConnectionEvent::new(
        pad,
        GamepadConnection::Connected {
            name: "synthetic pad".into(),
            vendor_id: None,
            product_id: None,
        },
    ));
    app.update();
    app.update();
    let mut remote = app.world_mut().resource_mut::<GamepadRemote>();
    remote.connect().expect("the synthetic pad is seen");
    assert_eq!(remote.name(), "synthetic pad");
    (app, pad)
}

fn stick(app: &mut App, pad: Entity, axis: GamepadAxis, value: f32) {
    app.world_mut()
        .write_message(RawGamepadEvent::Axis(RawGamepadAxisChangedEvent::new(
            pad, axis, value,
        )));
}

fn button(app: &mut App, pad: Entity, b: GamepadButton, value: f32) {
    app.world_mut()
        .write_message(RawGamepadEvent::Button(RawGamepadButtonChangedEvent::new(
            pad, b, value,
        )));
}

struct Drive {
    sim: Simulator,
    mapper: RemoteMapper,
}

impl Drive {
    fn new() -> Self {
        let model = proleg::control::load_simulation(CONFIG).expect("config");
        let orientations: Vec<JointOrientation> =
            model.robot.joints.iter().map(|j| j.orientation).collect();
        let sim = Simulator::new(&model, &BuildOptions::default()).expect("world");
        let mapper = RemoteMapper::new(
            &default_gamepad_bindings(),
            "default",
            sim.kernel(0).expect("kernel"),
            &orientations,
        )
        .expect("the default binding fits the robot");
        Drive { sim, mapper }
    }

    /// One 50 ms frame: the App reads the pad, the binding changes the kernel, the
    /// simulation runs 50 steps.
    fn frame(&mut self, app: &mut App) -> Vec<RemoteAction> {
        app.update();
        let data = app.world_mut().resource_mut::<GamepadRemote>().read_all();
        let kernel = self.sim.kernel_mut(0).expect("kernel");
        let actions = self.mapper.apply(&data, 0.05, kernel).expect("apply");
        self.sim.run_steps(50);
        actions
    }

    fn param(&self, name: &str, joint: usize) -> f64 {
        self.sim
            .kernel(0)
            .expect("kernel")
            .parameter(0, name, Some(joint))
            .expect("parameter")
    }
}

/// Heading change (degrees, unwrapped) over `seconds` with the left stick held at `x`.
fn steer(x: f32, seconds: f64) -> f64 {
    let (mut app, pad) = pad_app();
    let mut d = Drive::new();
    stick(&mut app, pad, GamepadAxis::LeftStickX, x);
    let mut last = d.sim.heading(0).expect("heading");
    let mut turned = 0.0;
    for _ in 0..(seconds / 0.05) as usize {
        d.frame(&mut app);
        let h = d.sim.heading(0).expect("heading");
        turned += (h - last + 540.0).rem_euclid(360.0) - 180.0;
        last = h;
    }
    turned
}

#[test]
fn the_left_stick_steers_left_and_right() {
    let right = steer(1.0, 8.0);
    let left = steer(-1.0, 8.0);
    let straight = steer(0.0, 8.0);
    eprintln!("8 s: stick right {right:.1} deg, left {left:.1} deg, centred {straight:.1} deg");
    assert!(
        right < -20.0,
        "stick right: turned {right} deg (should turn right)"
    );
    assert!(
        left > 20.0,
        "stick left: turned {left} deg (should turn left)"
    );
    assert!(
        straight.abs() < 10.0,
        "stick centred: turned {straight} deg"
    );
}

/// Distance crawled in `seconds` after holding the right stick at `y` for 1 s.
fn crawl_after_frequency(y: f32, seconds: f64) -> (f64, f64) {
    let (mut app, pad) = pad_app();
    let mut d = Drive::new();
    stick(&mut app, pad, GamepadAxis::RightStickY, y);
    for _ in 0..20 {
        d.frame(&mut app);
    }
    stick(&mut app, pad, GamepadAxis::RightStickY, 0.0);
    let f = d.param("Frequency", 0);
    let start = d.sim.com(0).expect("com");
    for _ in 0..(seconds / 0.05) as usize {
        d.frame(&mut app);
    }
    let end = d.sim.com(0).expect("com");
    (f, (end[0] - start[0]).hypot(end[1] - start[1]))
}

#[test]
fn the_frequency_axis_changes_the_speed() {
    let (f_slow, slow) = crawl_after_frequency(-1.0, 6.0);
    let (f_fast, fast) = crawl_after_frequency(1.0, 6.0);
    eprintln!("6 s at {f_slow:.2} Hz: {slow:.3} m; at {f_fast:.2} Hz: {fast:.3} m");
    assert!(
        (f_slow - 0.5).abs() < 0.06,
        "frequency after 1 s down: {f_slow}"
    );
    assert!(
        (f_fast - 1.5).abs() < 0.06,
        "frequency after 1 s up: {f_fast}"
    );
    assert!(
        fast > 1.5 * slow,
        "1.5 Hz crawled {fast:.3} m, 0.5 Hz {slow:.3} m in 6 s"
    );
}

#[test]
fn parameters_stop_at_their_limits_and_buttons_act_once() {
    let (mut app, pad) = pad_app();
    let mut d = Drive::new();
    stick(&mut app, pad, GamepadAxis::LeftStickY, -1.0);
    for _ in 0..80 {
        d.frame(&mut app);
    }
    assert_eq!(d.param("Amplitude", 0), 0.0, "amplitude stops at 0");
    assert_eq!(
        d.param("Amplitude", 1),
        0.0,
        "the yaw joints were never touched"
    );
    stick(&mut app, pad, GamepadAxis::LeftStickY, 0.0);
    button(&mut app, pad, GamepadButton::DPadUp, 1.0);
    d.frame(&mut app);
    d.frame(&mut app);
    assert_eq!(
        d.param("Amplitude", 2),
        5.0,
        "one step per press, not per frame"
    );
    button(&mut app, pad, GamepadButton::DPadUp, 0.0);
    button(&mut app, pad, GamepadButton::Start, 1.0);
    assert_eq!(d.frame(&mut app), vec![RemoteAction::Pause]);
    assert!(d.frame(&mut app).is_empty());
    // A disconnected remote reads nothing.
    app.world_mut().resource_mut::<GamepadRemote>().disconnect();
    stick(&mut app, pad, GamepadAxis::LeftStickY, 1.0);
    d.frame(&mut app);
    assert_eq!(d.param("Amplitude", 2), 5.0);
}
