//! Runs a [`crate::gui::control::script`] in the window: each frame, commands are carried out until
//! one has to wait (frames, simulated time, a screenshot being written, an optimization).
//! A failing command prints `error: FILE:LINE: cause` and closes the window with a failure.

use std::fmt::Write as _;

use bevy::prelude::*;

use crate::data::export::resolve;
use crate::gui::control::optimizer_view::replay;
use crate::gui::control::plots::LiveSeries;
use crate::gui::control::results_view::replay_stored;
use crate::gui::control::scene::BodyVisual;
use crate::gui::control::script::{Command, ScriptRunner, state_report};
use crate::gui::control::script::{Panel, Record, WaitFor};
use crate::gui::control::session::SimSession;
use crate::gui::control::{Panels, Views};
use crate::gui::scripting::{CommandError, Flow, run_commands};

/// Carries out script commands (the `Script` set).
pub fn run_script(
    mut commands: Commands,
    mut runner: ResMut<ScriptRunner>,
    mut session: NonSendMut<SimSession>,
    mut views: Views,
    visuals: Query<(Entity, &BodyVisual)>,
    mut exit: MessageWriter<AppExit>,
) {
    run_commands(&mut runner.0, &mut exit, |c, script| {
        carry_out(c, &mut commands, script, &mut session, &mut views, &visuals)
    });
    let pending = runner.0.as_ref().is_some_and(|s| s.next < s.commands.len());
    views
        .script
        .set_if_neq(crate::gui::desktop::ScriptPending(pending));
}

/// One command, carried out by the function of its group.
fn carry_out(
    c: Command,
    commands: &mut Commands,
    script: &mut crate::gui::control::script::Script,
    session: &mut SimSession,
    views: &mut Views,
    visuals: &Query<(Entity, &BodyVisual)>,
) -> Result<Flow, CommandError> {
    use Command as C;
    match c {
        C::Wait { .. }
        | C::Start
        | C::Pause
        | C::Restart
        | C::Load { .. }
        | C::Engine { .. }
        | C::Continue
        | C::KeepTuned => simulation_command(c, script, session),
        C::RunUntil { .. }
        | C::StepTo { .. }
        | C::Speed { .. }
        | C::SlowFrames { .. }
        | C::Set { .. } => pace_command(c, script, session),
        C::Plot { .. }
        | C::Panel { .. }
        | C::PerJoint { .. }
        | C::Debug { .. }
        | C::SelectLink { .. }
        | C::MoveBy(_)
        | C::Inspect { .. } => view_command(c, session, views, visuals),
        C::Remote { .. }
        | C::RemoteSet { .. }
        | C::RemoteBind { .. }
        | C::RemoteRemove { .. }
        | C::RemoteLoad { .. }
        | C::RemoteSave { .. } => remote_command(c, views),
        C::Robot { .. }
        | C::RobotConnect { .. }
        | C::RobotTorque { .. }
        | C::RobotDrive { .. }
        | C::RobotTwin { .. }
        | C::RobotCalibrate { .. }
        | C::RobotDisconnect => robot_command(c, session, views),
        C::Module(_) | C::Assign { .. } | C::Weights { .. } => tool_command(c, session, views),
        C::Optimize { .. }
        | C::SaveBest { .. }
        | C::Attach { .. }
        | C::ReplayBest
        | C::Results { .. }
        | C::Replay { .. } => optimizer_command(c, session, views),
        C::Screenshot { .. } | C::State { .. } | C::Record(_) | C::WaitFor(_) | C::Quit => {
            output_command(c, commands, script, session, views)
        }
    }
}

/// Most steps `step-to` runs per frame (the window stays responsive).
const STEPS_PER_FRAME: u64 = 2000;

/// A command outside its group (cannot happen: [`carry_out`] dispatches by group).
fn misrouted(c: &Command) -> CommandError {
    CommandError::Misrouted(format!("{c:?}"))
}

/// Running, pausing, restarting, loading and the engine.
fn simulation_command(
    c: Command,
    script: &mut crate::gui::control::script::Script,
    session: &mut SimSession,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Wait { frames } => {
            script.pacing.waiting = frames;
            Flow::Yield
        }
        Command::Start => {
            session.running = true;
            Flow::Next
        }
        Command::Pause => {
            session.running = false;
            Flow::Next
        }
        Command::Restart => {
            session.restart();
            Flow::Next
        }
        Command::KeepTuned => {
            if session.tuned.is_none() {
                return Err(CommandError::NotNow(
                    "keep-tuned: no tuned values were set aside by a restart",
                ));
            }
            session.keep_tuned();
            Flow::Next
        }
        Command::Continue => {
            if session.halt.is_none() {
                return Err(CommandError::NotNow(
                    "continue: the run did not pause by itself",
                ));
            }
            session.continue_run();
            Flow::Next
        }
        Command::Load { file } => {
            session.load(&file);
            Flow::Next
        }
        Command::Engine { kind } => {
            session.set_engine(kind);
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// Running to a time, pacing and parameters.
fn pace_command(
    c: Command,
    script: &mut crate::gui::control::script::Script,
    session: &mut SimSession,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::RunUntil { seconds } if session.sim_time() + 1e-9 < seconds => {
            // Paced as the toolbar says, pausing exactly at t.
            session.pause_at = Some(seconds);
            session.running = true;
            Flow::Again
        }
        Command::RunUntil { .. } => {
            session.pause_at = None;
            Flow::Next
        }
        Command::StepTo { seconds } => {
            session.running = false;
            if session.step_to(seconds, STEPS_PER_FRAME) {
                Flow::Next
            } else {
                Flow::Again
            }
        }
        Command::Speed { factor } => {
            session.pacing.realtime_factor = factor.max(0.0);
            Flow::Next
        }
        Command::SlowFrames { ms } => {
            script.pacing.frame_delay = std::time::Duration::from_millis(u64::from(ms));
            Flow::Next
        }
        Command::Set {
            module,
            param,
            value,
            joint,
        } => {
            let k = session.simulator.kernel_mut(0)?;
            let a = k.find(&module).ok_or(CommandError::Missing {
                what: "module in this robot's actuation",
                name: module,
            })?;
            k.set_parameter(a, &param, joint.map(|j| j.saturating_sub(1)), value)?;
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// Plots, panels, the per-joint switch, the debug view, selection and data inspection.
fn view_command(
    c: Command,
    session: &mut SimSession,
    views: &mut Views,
    visuals: &Query<(Entity, &BodyVisual)>,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Plot { series: selectors } => {
            let log = session.simulator.data(0)?;
            let cols = resolve(&log.handlers, &selectors)?;
            let series = cols
                .into_iter()
                .map(|c| LiveSeries {
                    handler: log.handlers[c.handler].name.clone(),
                    column: c.value,
                    title: c.title,
                })
                .collect();
            views.plots.add(series);
            Flow::Next
        }
        Command::Panel { which } => {
            *views.panels = Panels {
                params: matches!(which, Panel::Params | Panel::All),
                plots: matches!(which, Panel::Plots | Panel::All),
            };
            Flow::Next
        }
        Command::PerJoint {
            actuator,
            param,
            state,
        } => {
            let k = session.simulator.kernel(0)?;
            let a = k.actuators().get(actuator).ok_or(CommandError::Missing {
                what: "module tab",
                name: actuator.to_string(),
            })?;
            let d = a.module.descriptor();
            let p = d
                .parameters
                .iter()
                .position(|p| p.answers_to(&param))
                .ok_or_else(|| CommandError::Missing {
                    what: "parameter of this module",
                    name: param.clone(),
                })?;
            views.params.tab = actuator;
            if state.on() {
                views.params.individual.insert((actuator, p));
            } else {
                views.params.individual.remove(&(actuator, p));
            }
            Flow::Next
        }
        Command::Debug { state } => {
            views.debug.0 = state.on();
            Flow::Next
        }
        Command::SelectLink { link } => {
            let (e, _) = visuals.iter().find(|(_, v)| v.link == Some(link)).ok_or(
                CommandError::Missing {
                    what: "link in the viewer",
                    name: link.to_string(),
                },
            )?;
            views.selection.body = Some(e);
            Flow::Next
        }
        Command::MoveBy(d) => {
            if views.selection.body.is_none() {
                return Err(CommandError::NotNow("nothing selected (select-link first)"));
            }
            views.selection.nudge(d.array());
            Flow::Yield
        }
        Command::Inspect { file, series } => {
            inspect(&mut views.inspect, &file, &series)?;
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// `inspect FILE SERIES...`: the data file inspection on `path` with a graph of `selectors`.
fn inspect(
    inspect: &mut crate::gui::control::inspect::InspectState,
    path: &std::path::Path,
    selectors: &[crate::data::export::SeriesSelector],
) -> Result<(), CommandError> {
    inspect.open = true;
    inspect.path = path.display().to_string();
    inspect.load(path);
    let Some((_, info)) = &inspect.file else {
        return Err(CommandError::Refused(inspect.message.clone()));
    };
    let cols = resolve(&info.handlers, selectors)?;
    let mut checked = std::collections::BTreeSet::new();
    for c in &cols {
        let h = &info.handlers[c.handler];
        if let Some(s) = (0..h.series.len()).rev().find(|s| h.offset(*s) <= c.value) {
            checked.insert((h.name.clone(), h.series[s].clone(), c.value - h.offset(s)));
        }
    }
    inspect.checked = checked;
    inspect
        .add_graph()
        .ok_or_else(|| CommandError::Refused(inspect.message.clone()))?;
    Ok(())
}

/// The remote dialog: bindings and injected gamepad values.
fn remote_command(c: Command, views: &mut Views) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Remote { state } => {
            views.remote.open = state.open();
            Flow::Next
        }
        Command::RemoteSet { element, value } => {
            views.remote.injected.set(&element, value);
            Flow::Next
        }
        Command::RemoteBind {
            element,
            mode,
            module,
            parameter,
            joints,
            scale,
        } => {
            views.remote.add_binding(
                &element,
                mode,
                crate::config::remote::BindTarget {
                    module,
                    parameter,
                    joints,
                    scale,
                    pos: crate::config::error::Pos::new(0, 0),
                },
            );
            Flow::Next
        }
        Command::RemoteRemove { index } => {
            views.remote.remove(index)?;
            Flow::Next
        }
        Command::RemoteLoad { file } => {
            views.remote.load(&file)?;
            Flow::Next
        }
        Command::RemoteSave { file } => {
            views.remote.save(&file)?;
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// The real-robot tab.
fn robot_command(
    c: Command,
    session: &mut SimSession,
    views: &mut Views,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Robot { state } => {
            views.robot.open = state.open();
            Flow::Next
        }
        Command::RobotConnect { port } => {
            views.robot.port = port;
            views.robot.connect(session)?;
            Flow::Next
        }
        Command::RobotTorque { state } => {
            views.robot.set_torque(state.on())?;
            Flow::Next
        }
        Command::RobotDrive { state } => {
            views.robot.drive = state.on();
            Flow::Next
        }
        Command::RobotTwin { state } => {
            views.robot.twin = state.on();
            Flow::Next
        }
        Command::RobotDisconnect => {
            views.robot.disconnect(session);
            Flow::Next
        }
        Command::RobotCalibrate { file } => {
            views.robot.open = true;
            views.robot.calibration.file = file.display().to_string();
            views.robot.calibration.start(&session.sim);
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// The module library, module assignment and weights files.
fn tool_command(
    c: Command,
    session: &mut SimSession,
    views: &mut Views,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Module(m) => {
            if crate::gui::module_editor::script::run(&mut views.modules, m)? {
                // A module just built is known to the next command (`assign`) at once,
                // not only after the next frame's `sync_modules`.
                session.sync_modules(views.modules.host.registry());
                Flow::Next
            } else {
                Flow::Again
            }
        }
        Command::Assign { module, mask } => {
            views.assign.module = module;
            views.assign.mask = mask;
            views.assign.assign(session)?;
            Flow::Next
        }
        Command::Weights { actuator, file } => {
            views.assign.weights = file.display().to_string();
            views.assign.load_weights(session, actuator)?;
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// The optimization view: attaching, optimizing, the best candidate, stored results.
fn optimizer_command(
    c: Command,
    session: &mut SimSession,
    views: &mut Views,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Attach {
            store,
            evaluations: n,
        } => {
            let o = &mut views.optimizer;
            if !o.attached {
                o.open = true;
                o.attach_to = store.clone();
                o.attach();
            }
            o.poll();
            if o.status.starts_with("cannot attach") || o.status.starts_with("--store") {
                return Err(CommandError::Refused(o.status.clone()));
            }
            if o.running() && (o.curve.len() as u64) < n {
                Flow::Again
            } else {
                Flow::Next
            }
        }
        Command::Optimize {
            evaluations: n,
            store,
        } => {
            if session.sim.optimizer.is_none() {
                return Err(CommandError::NotNow(
                    "this simulation's mode is not an optimization",
                ));
            }
            let o = &mut views.optimizer;
            if o.started.is_none() {
                o.open = true;
                o.max_evals = n;
                if let Some(s) = store {
                    o.store = s;
                }
                o.start(session);
            }
            o.poll();
            if o.running() { Flow::Again } else { Flow::Next }
        }
        Command::SaveBest { file } => {
            let space =
                crate::optimize::run::prepare(&session.sim, &session.registry).map(|(s, _)| s)?;
            let o = &mut views.optimizer;
            o.save_to = file.display().to_string();
            o.save_best(session, &space)?;
            Flow::Next
        }
        Command::ReplayBest => {
            let (genome, _) = views
                .optimizer
                .best
                .clone()
                .ok_or(CommandError::NotNow("no candidate evaluated yet"))?;
            replay(session, &genome);
            Flow::Next
        }
        Command::Results { store } => {
            let o = &mut views.optimizer;
            o.open = true;
            o.results.store = store;
            o.results.list();
            Flow::Next
        }
        Command::Replay {
            store,
            run,
            which,
            episode,
        } => {
            replay_stored(session, &store, run, which, episode)?;
            Flow::Next
        }
        other => return Err(misrouted(&other)),
    })
}

/// Writes `text` to `file` whole: into a file beside it, then renamed over it, so whoever
/// waits for `file` to appear (a test driving the window) never reads half of it.
fn write_whole(file: &std::path::Path, text: &str) -> std::io::Result<()> {
    let mut part = file.as_os_str().to_owned();
    part.push(".part");
    std::fs::write(&part, text)?;
    std::fs::rename(&part, file)
}

/// Screenshots, the state file and quitting.
fn output_command(
    c: Command,
    commands: &mut Commands,
    script: &mut crate::gui::control::script::Script,
    session: &mut SimSession,
    views: &mut Views,
) -> Result<Flow, CommandError> {
    Ok(match c {
        Command::Screenshot { file } => {
            script.pacing.screenshot(commands, file)?;
            Flow::Yield
        }
        Command::State { file } => {
            write_whole(&file, &state_lines(session, views))
                .map_err(|source| CommandError::Write { path: file, source })?;
            Flow::Next
        }
        Command::WaitFor(target) => {
            let (holds, frames, what) = match target {
                WaitFor::Running { frames } => (session.running, frames, "running".to_string()),
                WaitFor::Paused { frames } => (!session.running, frames, "paused".to_string()),
                WaitFor::Debug { frames } => (views.debug.0, frames, "debug".to_string()),
                WaitFor::Calibrated { frames } => {
                    views.robot.calibration.poll();
                    let c = &views.robot.calibration;
                    let done = !c.running() && (c.result.is_some() || c.error.is_some());
                    (done, frames, "a calibration".to_string())
                }
                WaitFor::File { path, frames } => {
                    (path.exists(), frames, path.display().to_string())
                }
            };
            script.pacing.poll(holds, frames, &what)?
        }
        Command::Record(Record::On { file }) => {
            views.recorder.start(&session.path, file);
            Flow::Next
        }
        Command::Record(Record::Off) => {
            views.recorder.stop();
            Flow::Next
        }
        Command::Quit => Flow::Quit,
        other => return Err(misrouted(&other)),
    })
}

/// The optimization view's and the replay's part of the state.
fn optimizer_pairs(pairs: &mut Vec<(&str, String)>, session: &SimSession, views: &Views) {
    let o = &views.optimizer;
    pairs.push(("optimizer_evaluations", o.curve.len().to_string()));
    pairs.push((
        "optimizer_best",
        o.best
            .as_ref()
            .map_or("none".into(), |b| format!("{:.6}", b.1)),
    ));
    pairs.push(("stored_runs", o.results.runs.len().to_string()));
    pairs.push(("optimizer_followed", o.followed_text()));
    pairs.push(("optimizer_status", o.status_line()));
    if let Some(r) = o.panel {
        pairs.push((
            "optimizer_panel",
            format!(
                "{:.0} {:.0} {:.0} {:.0}",
                r.min.x, r.min.y, r.max.x, r.max.y
            ),
        ));
    }
    if let Some(score) = session.replay_score() {
        pairs.push((
            "replay_score",
            score.map_or_else(|e| e.to_string(), |s| format!("{s:.9}")),
        ));
    }
}

/// Where the toolbar, the docked panels, the viewer and "Add plot" were drawn, as
/// `NAME_rect = LEFT TOP RIGHT BOTTOM` in points.
fn layout_pairs(pairs: &mut Vec<(&str, String)>, views: &Views) {
    let text = |r: &bevy_egui::egui::Rect| {
        format!(
            "{:.0} {:.0} {:.0} {:.0}",
            r.min.x, r.min.y, r.max.x, r.max.y
        )
    };
    for (name, r) in &views.toolbar.layout {
        let key: &'static str = match *name {
            "toolbar" => "toolbar_rect",
            "viewer" => "viewer_rect",
            "plots" => "plots_rect",
            "params" => "params_rect",
            _ => continue,
        };
        pairs.push((key, text(r)));
    }
    if let Some(r) = &views.plots.add_plot_rect {
        pairs.push(("add_plot_rect", text(r)));
    }
    if let Some(r) = &views.plots.first_series_rect {
        pairs.push(("first_series_rect", text(r)));
    }
}

/// The state a GUI test checks.
/// The real-robot tab's calibration: running, its error, the mean RMS before and after.
fn calibration_pairs(pairs: &mut Vec<(&str, String)>, views: &Views) {
    let c = &views.robot.calibration;
    pairs.push(("calibration_running", c.running().to_string()));
    pairs.push((
        "calibration_error",
        c.error
            .as_ref()
            .map(ToString::to_string)
            .unwrap_or_default(),
    ));
    if let Some(r) = &c.result {
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
        pairs.push((
            "calibration_rms",
            format!(
                "{:.4} {:.4}",
                mean(&r.report.rms_before),
                mean(&r.report.rms_after)
            ),
        ));
    }
}

fn state_lines(session: &SimSession, views: &Views) -> String {
    let mut pairs: Vec<(&str, String)> = vec![
        ("config", session.path.display().to_string()),
        ("config_field", views.toolbar.path.clone()),
        ("tuned_aside", session.tuned.is_some().to_string()),
        ("running", session.running.to_string()),
        ("generation", session.generation.to_string()),
        ("plots_shown", views.plots.plots.len().to_string()),
        ("series_ticked", views.plots.checked.len().to_string()),
        ("steps", session.steps().to_string()),
        ("sim_time", format!("{:.6}", session.sim_time())),
        ("real_time", format!("{:.6}", session.real_time)),
        ("fps", format!("{:.4}", views.toolbar.meter.fps())),
        ("factor", format!("{:.4}", views.toolbar.meter.factor())),
        (
            "speed_readout",
            views
                .toolbar
                .meter
                .readout(session.pacing.realtime_factor, session.running),
        ),
        (
            "halt",
            session
                .halt
                .as_ref()
                .map(|h| h.message())
                .unwrap_or_default(),
        ),
        ("engine", session.simulator.engine_kind().to_string()),
        ("plots", views.plots.plots.len().to_string()),
        ("params_panel", views.panels.params.to_string()),
        ("plots_panel", views.panels.plots.to_string()),
        ("debug_view", views.debug.0.to_string()),
        ("selected", views.selection.body.is_some().to_string()),
        (
            "camera",
            format!("{:.4} {:.4}", views.camera.yaw, views.camera.pitch),
        ),
        ("inspect_graphs", views.inspect.graphs.len().to_string()),
    ];
    optimizer_pairs(&mut pairs, session, views);
    layout_pairs(&mut pairs, views);
    pairs.push(("recording", views.recorder.recording().to_string()));
    calibration_pairs(&mut pairs, views);
    // One line per key: an error's "included from" lines are joined by \n.
    let error = session.error.clone().unwrap_or_default();
    pairs.push(("error", error.replace('\n', "\\n")));
    if let Some((file, frames)) = &views.recorder.last {
        pairs.push(("recording_file", file.display().to_string()));
        pairs.push(("recorded_frames", frames.to_string()));
    }
    if let Ok(c) = session.simulator.com(0) {
        pairs.push(("com", format!("{:.6} {:.6} {:.6}", c[0], c[1], c[2])));
    }
    if let Ok(h) = session.simulator.heading(0) {
        pairs.push(("heading", format!("{h:.3}")));
    }
    world_pairs(&mut pairs, session);
    device_pairs(&mut pairs, session, views);
    pairs.push(("parameters", parameters_line(session)));
    state_report(&pairs)
}

/// Where the first scenery body is.
fn world_pairs(pairs: &mut Vec<(&str, String)>, session: &SimSession) {
    let scenery = session.simulator.environment_bodies();
    if let Some(p) = scenery
        .first()
        .and_then(|b| session.simulator.body_position(b.body))
    {
        pairs.push((
            "environment_0",
            format!("{:.6} {:.6} {:.6}", p[0], p[1], p[2]),
        ));
    }
}

/// The remote dialog, the module library, module failures and the real robot.
fn device_pairs(pairs: &mut Vec<(&str, String)>, session: &SimSession, views: &Views) {
    pairs.push(("remote_open", views.remote.open.to_string()));
    pairs.push((
        "remote_bindings",
        views.remote.file.bindings.len().to_string(),
    ));
    pairs.push(("remote_actions", views.remote.actions.to_string()));
    pairs.extend(crate::gui::module_editor::script::state_pairs(
        &views.modules,
    ));
    let failures: Vec<String> = session
        .simulator
        .kernel(0)
        .map(|k| k.failures().map(|(n, c)| format!("{n}: {c}")).collect())
        .unwrap_or_default();
    pairs.push(("module_failures", failures.join(" | ")));
    let r = &views.robot;
    pairs.push(("robot_connected", r.connected().to_string()));
    pairs.push(("robot_torque", r.torque.to_string()));
    pairs.push(("robot_reads", r.reads.to_string()));
    pairs.push(("robot_writes", r.writes.to_string()));
    pairs.push((
        "robot_positions",
        r.readings
            .positions
            .iter()
            .map(|a| format!("{a:.2}"))
            .collect::<Vec<_>>()
            .join(" "),
    ));
    pairs.push(("robot_error", r.error.clone().unwrap_or_default()));
    pairs.push((
        "remote_error",
        views.remote.error.clone().unwrap_or_default(),
    ));
}

/// Every module parameter of robot 0's kernel: `i:Type:name=v,v,...;` each.
fn parameters_line(session: &SimSession) -> String {
    let mut params = String::new();
    if let Ok(k) = session.simulator.kernel(0) {
        for (i, a) in k.actuators().iter().enumerate() {
            let d = a.module.descriptor();
            for (pi, p) in d.parameters.iter().enumerate() {
                let vals: Vec<String> = a
                    .module
                    .parameters()
                    .row(pi)
                    .iter()
                    .map(|v| v.to_string())
                    .collect();
                let _ = write!(params, "{i}:{}:{}={};", d.type_name, p.name, vals.join(","));
            }
        }
    }
    params
}
