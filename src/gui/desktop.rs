//! What makes both windows behave like desktop applications rather than games:
//!
//! - **Reactive rendering.** A window redraws when input arrives, when egui asks for a
//!   repaint, or while it is [`Busy`] (a simulation runs, a script plays, an optimization or
//!   a recording is under way); otherwise winit sleeps and the process takes no CPU. Each
//!   window sets [`Busy`] every frame; [`apply_busy`] switches winit between continuous and
//!   reactive updates. bevy_egui's per-frame "modifiers changed" event, which made egui ask
//!   for a repaint every frame, is dropped when nothing changed ([`drop_unchanged_modifiers`]).
//! - **A clean exit on SIGTERM and Ctrl+C** within one frame: the handler raises a flag and
//!   wakes winit's loop (a sleeping reactive loop would otherwise notice only at its next
//!   timeout); the next update writes `AppExit`. Bevy's own Ctrl+C plugin is replaced (its
//!   flag is polled only when a frame runs).
//! - **Children reaped**: [`spawn_window`] starts another proleg window as a child process
//!   and a thread waits for it, so a closed child leaves no zombie.

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use bevy::prelude::*;
use bevy::winit::{EventLoopProxyWrapper, UpdateMode, WinitSettings, WinitUserEvent};
use bevy_egui::{EguiInput, EguiPreUpdateSet, egui};

/// Longest an idle window sleeps before a frame anyway (a safety net; input and egui's
/// repaint requests wake it at once).
const IDLE_WAKE: Duration = Duration::from_secs(60);

/// Whether a window's script still has commands to play (set by its script runner each
/// frame; never, in a build without the `scripts` feature).
#[derive(Resource, Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct ScriptPending(pub bool);

/// Whether the window must draw continuously this frame (set by each window every frame).
#[derive(Resource, Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Busy(pub bool);

/// The window's subscription to Ctrl-C / SIGTERM ([`crate::signal`]): once raised, the
/// window closes.
#[derive(Resource, Default)]
struct Terminate(Option<crate::signal::Subscription>);

/// Reactive rendering, the signal handler and the exit on it.
pub struct DesktopPlugin;

impl Plugin for DesktopPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(idle_settings())
            .init_resource::<Busy>()
            .init_resource::<ScriptPending>()
            .init_resource::<Terminate>()
            .add_systems(Startup, install_signal_handler)
            .add_systems(First, exit_on_signal)
            .add_systems(
                PreUpdate,
                drop_unchanged_modifiers
                    .after(EguiPreUpdateSet::ProcessInput)
                    .before(EguiPreUpdateSet::BeginPass),
            )
            .add_systems(Last, apply_busy);
    }
}

/// Winit's settings for a window with nothing to do: wake on input and repaint requests.
fn idle_settings() -> WinitSettings {
    WinitSettings {
        focused_mode: UpdateMode::reactive(IDLE_WAKE),
        unfocused_mode: UpdateMode::reactive_low_power(IDLE_WAKE),
    }
}

/// Switches winit to continuous updates while the window is [`Busy`], back to reactive
/// when it is not.
pub fn apply_busy(busy: Res<Busy>, mut settings: ResMut<WinitSettings>) {
    let want = if busy.0 {
        WinitSettings::continuous()
    } else {
        idle_settings()
    };
    if settings.focused_mode != want.focused_mode || settings.unfocused_mode != want.unfocused_mode
    {
        *settings = want;
    }
}

/// Drops the "modifiers changed" event bevy_egui adds to every frame's input when the
/// modifiers did not change: egui repaints at once whenever its input has an event, so
/// that event alone kept an idle window drawing as fast as it could.
pub fn drop_unchanged_modifiers(
    mut inputs: Query<&mut EguiInput>,
    mut last: Local<Option<egui::Modifiers>>,
) {
    for mut input in &mut inputs {
        let mut seen = *last;
        input.events.retain(|e| match e {
            egui::Event::ModifiersChanged(m) => {
                let changed = seen != Some(*m);
                seen = Some(*m);
                changed
            }
            _ => true,
        });
        *last = seen;
    }
}

/// Subscribes to SIGTERM / SIGINT: raise the flag, wake the event loop.
fn install_signal_handler(
    proxy: Option<Res<EventLoopProxyWrapper>>,
    mut terminate: ResMut<Terminate>,
) {
    let proxy = proxy.map(|p| (**p).clone());
    let subscribed = crate::signal::subscribe_with(move || {
        if let Some(p) = &proxy
            && p.send_event(WinitUserEvent::WakeUp).is_err()
        {
            // The event loop is gone: the window is closing already.
        }
    });
    match subscribed {
        Ok(s) => terminate.0 = Some(s),
        Err(e) => warn!("{e}; close the window from its title bar"),
    }
}

/// Closes the window once a signal arrived.
fn exit_on_signal(terminate: Res<Terminate>, mut exit: MessageWriter<AppExit>) {
    if terminate.0.as_ref().is_some_and(|s| s.is_raised()) {
        exit.write(AppExit::Success);
    }
}

/// What both windows are built on: Bevy's default plugins with a 1280x800 window titled
/// `title` (Bevy's own Ctrl+C handler replaced by [`DesktopPlugin`]'s), egui, mesh
/// picking, reactive rendering and ordered keys, on the windows' sky colour.
pub fn add_window_plugins(app: &mut App, title: String) {
    app.add_plugins(
        DefaultPlugins
            .set(bevy::window::WindowPlugin {
                primary_window: Some(Window {
                    title,
                    resolution: bevy::window::WindowResolution::new(1280, 800),
                    ..default()
                }),
                ..default()
            })
            .disable::<bevy::app::TerminalCtrlCHandlerPlugin>(),
    )
    .add_plugins((
        bevy_egui::EguiPlugin::default(),
        MeshPickingPlugin,
        DesktopPlugin,
        crate::gui::keyboard::OrderedKeysPlugin,
    ))
    .insert_resource(ClearColor(Color::srgb(0.62, 0.74, 0.86)));
}

/// Why another window could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum SpawnError {
    /// proleg's own executable was not found.
    #[error("cannot find proleg's executable: {0}")]
    Exe(std::io::Error),
    /// The process did not start.
    #[error("cannot open the {what}: {source}")]
    Start {
        /// The window asked for.
        what: &'static str,
        /// Why.
        source: std::io::Error,
    },
}

/// Starts `proleg ARGS… PATH` (another window, `what` in errors) as a child process; a
/// thread waits for it so that it is reaped when it closes. Returns its process id.
pub fn spawn_window(what: &'static str, args: &[&str], path: &Path) -> Result<u32, SpawnError> {
    let exe = std::env::current_exe().map_err(SpawnError::Exe)?;
    let mut child = Command::new(exe)
        .args(args)
        .arg(path)
        .spawn()
        .map_err(|source| SpawnError::Start { what, source })?;
    let id = child.id();
    std::thread::spawn(move || match child.wait() {
        Ok(status) if !status.success() => warn!("the {what} closed with {status}"),
        Ok(_) => {}
        Err(e) => warn!("cannot wait for the {what}: {e}"),
    });
    Ok(id)
}
