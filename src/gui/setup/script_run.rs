//! Runs a [`crate::gui::setup::script`] in the configuration window: each frame, commands
//! are carried out until one has to wait (frames, a screenshot being written). A failing
//! command prints `error: FILE:LINE: cause` and closes the window with a failure.

use std::path::PathBuf;

use bevy::prelude::*;

use crate::compose::env_edit::{EnvEditor, Selected};
use crate::compose::expert::Part;
use crate::compose::library::LibraryItem;
use crate::gui::control::script::state_report;
use crate::gui::module_editor::ModuleEditor;
use crate::gui::scripting::{Flow, run_commands};
use crate::gui::setup::editor_view::preview;
use crate::gui::setup::script::{Command, Script, SetupScript};
use crate::gui::setup::state::{SetupState, Status, Tool};

/// Carries out script commands (before the views update).
pub fn run_script(
    mut commands: Commands,
    mut runner: ResMut<SetupScript>,
    mut state: ResMut<SetupState>,
    mut modules: ResMut<ModuleEditor>,
    mut exit: MessageWriter<AppExit>,
) {
    run_commands(&mut runner.0, &mut exit, |c, script| {
        carry_out(c, &mut commands, script, &mut state, &mut modules)
    });
}

fn item(state: &SetupState, name: &str) -> Result<LibraryItem, String> {
    state
        .library
        .iter()
        .find(|i| i.label().eq_ignore_ascii_case(name))
        .cloned()
        .or_else(|| LibraryItem::parse(name))
        .ok_or_else(|| {
            let names: Vec<String> = state.library.iter().map(|i| i.label()).collect();
            format!(
                "no library item {name:?}; the library holds: {}",
                names.join(", ")
            )
        })
}

fn carry_out(
    c: Command,
    commands: &mut Commands,
    script: &mut Script,
    state: &mut SetupState,
    modules: &mut ModuleEditor,
) -> Result<Flow, String> {
    match c {
        Command::Wait(n) => {
            script.pacing.waiting = n;
            return Ok(Flow::Yield);
        }
        Command::SlowFrames(ms) => {
            script.pacing.frame_delay = std::time::Duration::from_millis(u64::from(ms));
        }
        Command::WaitForFile(path, frames) => {
            let what = path.display().to_string();
            return script.pacing.poll(path.exists(), frames, &what);
        }
        Command::Tool(t) => {
            state.tool = match t.as_str() {
                "wizard" => Tool::Wizard,
                "expert" => Tool::Expert,
                "editor" => Tool::Editor,
                other => return Err(format!("tool {other:?}: expected wizard, expert or editor")),
            }
        }
        Command::Set(k, v) => state.wizard.set(&k, &v)?,
        Command::Next => state.wizard.next_page()?,
        Command::Back => state.wizard.back(),
        Command::Skip => state.wizard.skip()?,
        Command::Save => {
            let p = state.wizard.save()?;
            state.status = Some(Status::Info(format!("saved {}", p.display())));
        }
        Command::Add(..)
        | Command::Drop(..)
        | Command::Select(_)
        | Command::MoveTo(_)
        | Command::MoveBy(_)
        | Command::DragTo(_)
        | Command::Rotate(_)
        | Command::Yaw(_)
        | Command::Scale(_)
        | Command::Friction(_)
        | Command::Dynamic(_)
        | Command::Mass(_)
        | Command::Colour(_)
        | Command::Delete
        | Command::Undo
        | Command::Redo
        | Command::EnvSave(_)
        | Command::EnvLoad(_) => return editor_command(c, state),
        Command::Expert(..)
        | Command::ExpertSave(_)
        | Command::ExpertEdit
        | Command::ExpertOpen(_) => expert_command(c, state)?,
        Command::OpenControl(p) => {
            crate::gui::setup::open_control_window(state, &p);
            if let Some(Status::Error(e)) = &state.status {
                return Err(e.clone());
            }
        }
        Command::Preview => {
            preview(state);
            if let Some(Err(e)) = &state.preview {
                return Err(e.clone());
            }
        }
        Command::Zoom(h) => state.ortho_height = h.clamp(0.05, 40.0),
        Command::Screenshot(path) => {
            script.pacing.screenshot(commands, path);
            return Ok(Flow::Yield);
        }
        Command::State(path) => {
            crate::gui::control::widgets::ensure_parent(&path);
            std::fs::write(&path, state_lines(state, modules))
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        Command::Module(m) => {
            if !crate::gui::module_editor::script::run(modules, m)? {
                return Ok(Flow::Again);
            }
            state.sync_modules(modules);
        }
        Command::Quit => return Ok(Flow::Quit),
    }
    Ok(Flow::Next)
}

/// The environment editor's commands (the editor tool, or the wizard's environment page).
fn editor_command(c: Command, state: &mut SetupState) -> Result<Flow, String> {
    let env_only = |state: &SetupState| {
        if state.editing_env() {
            Ok(())
        } else {
            Err(
                "not in the environment editor (tool editor, or the wizard's environment page)"
                    .to_string(),
            )
        }
    };
    match c {
        Command::Add(name, at) => {
            env_only(state)?;
            let it = item(state, &name)?;
            let env = state.env_mut();
            let [x, y] = at.unwrap_or_else(|| {
                let r = env.robot_pose;
                let a = r.rotate([0.0, 1.0, 0.0]);
                [r.translation[0] + a[0], r.translation[1] + a[1]]
            });
            env.add(&it, x, y);
        }
        Command::Drop(name, [x, y]) => {
            env_only(state)?;
            state.drop = Some((item(state, &name)?, Vec2::new(x, y)));
            // The drop is placed by the picking system this frame.
            return Ok(Flow::Yield);
        }
        Command::Select(s) => {
            env_only(state)?;
            let sel = match s.as_str() {
                "robot" => Some(Selected::Robot),
                "none" => None,
                n => Some(Selected::Object(n.parse().map_err(|_| {
                    format!("select {n:?}: expected an object number, robot or none")
                })?)),
            };
            state.env_mut().select(sel)?;
        }
        Command::MoveTo(p) => state.env_mut().move_to(p)?,
        Command::MoveBy(d) => state.env_mut().move_by(d)?,
        Command::DragTo([x, y]) => {
            let env = state.env_mut();
            env.begin_drag();
            let r = env.drag_to(x, y);
            env.end_drag();
            r?
        }
        Command::Rotate(d) => state.env_mut().rotate_by(d)?,
        Command::Yaw(d) => state.env_mut().set_yaw(d)?,
        Command::Scale(f) => state.env_mut().scale(f)?,
        Command::Friction(mu) => state.env_mut().set_friction(mu)?,
        Command::Dynamic(on) => state.env_mut().set_dynamic(on)?,
        Command::Mass(kg) => state.env_mut().set_mass(kg)?,
        Command::Colour(rgb) => state.env_mut().set_colour(rgb)?,
        Command::Delete => state.env_mut().delete()?,
        Command::Undo => {
            if !state.env_mut().undo() {
                return Err("nothing to undo".into());
            }
        }
        Command::Redo => {
            if !state.env_mut().redo() {
                return Err("nothing to redo".into());
            }
        }
        Command::EnvSave(p) => {
            state.editor_path = p.display().to_string();
            state.env_mut().save(&p)?;
            state.status = Some(Status::Info(format!("saved {}", p.display())));
        }
        Command::EnvLoad(p) => {
            state.editor = EnvEditor::load(&p)?;
            state.editor_path = p.display().to_string();
        }
        other => return Err(format!("internal: {other:?} is not an editor command")),
    }
    Ok(Flow::Next)
}

/// The expert composition's commands.
fn expert_command(c: Command, state: &mut SetupState) -> Result<(), String> {
    match c {
        Command::Expert(part, path) => {
            let c = &mut state.expert.composition;
            let p = (path != "none").then(|| PathBuf::from(&path));
            let part = Part::ALL
                .into_iter()
                .find(|k| k.label().eq_ignore_ascii_case(&part))
                .ok_or_else(|| {
                    format!("part {part:?}: expected robot, actuation, environment or optimizer")
                })?;
            match (part, p) {
                (Part::Robot, Some(p)) => c.robot = p,
                (Part::Actuation, Some(p)) => c.actuation = p,
                (Part::Environment, p) => c.environment = p,
                (Part::Optimizer, p) => c.optimizer = p,
                (k, None) => return Err(format!("the {} cannot be none", k.label())),
            }
        }
        Command::ExpertSave(p) => {
            state.expert.path = p.display().to_string();
            state.expert.composition.save(&p, &state.wizard.registry)?;
            state.expert.check = Some(state.expert.composition.check(&p, &state.wizard.registry));
        }
        Command::ExpertOpen(p) => {
            state.expert.path = p.display().to_string();
            crate::gui::setup::expert_view::open(state, &p);
        }
        Command::ExpertEdit => {
            crate::gui::setup::expert_view::edit_in_wizard(state);
            if let Some(Status::Error(e)) = &state.status {
                return Err(e.clone());
            }
        }
        other => return Err(format!("internal: {other:?} is not an expert command")),
    }
    Ok(())
}

/// The state a GUI test checks.
fn state_lines(state: &mut SetupState, modules: &ModuleEditor) -> String {
    let (i, n) = state.wizard.progress();
    let w = &state.wizard;
    let mut pairs: Vec<(&str, String)> = vec![
        ("tool", format!("{:?}", state.tool).to_lowercase()),
        ("page", w.page.title().to_string()),
        ("page_number", format!("{i}/{n}")),
        ("robot", w.robot_name()),
        (
            "joints",
            w.joint_count().map_or_else(|e| e, |n| n.to_string()),
        ),
        ("topology", w.topology()),
        ("groups", w.behaviour.groups.len().to_string()),
        (
            "saved",
            w.saved
                .as_ref()
                .map_or(String::new(), |p| p.display().to_string()),
        ),
        (
            "preview_track",
            match &state.preview {
                Some(Ok(run)) => run.track.len().to_string(),
                _ => String::new(),
            },
        ),
        (
            "preview_displacement",
            match &state.preview {
                Some(Ok(run)) => format!("{:.4}", run.distance),
                _ => String::new(),
            },
        ),
        (
            "status",
            match &state.status {
                Some(Status::Info(s)) => s.clone(),
                Some(Status::Error(s)) => format!("error: {}", s.replace('\n', "\\n")),
                None => String::new(),
            },
        ),
        (
            "expert_robot",
            state.expert.composition.robot.display().to_string(),
        ),
        (
            "expert_check",
            match &state.expert.check {
                Some(Ok(s)) => s.clone(),
                Some(Err(e)) => format!("error: {}", e.replace('\n', "\\n")),
                None => String::new(),
            },
        ),
    ];
    let env = state.env_mut();
    pairs.push(("env_objects", env.objects.len().to_string()));
    pairs.push(("env_undo", env.can_undo().to_string()));
    let sel = env.selected;
    pairs.push((
        "selected",
        match sel {
            Some(Selected::Robot) => "robot".into(),
            Some(Selected::Object(i)) => i.to_string(),
            None => "none".into(),
        },
    ));
    if let Some(p) = sel.and_then(|s| env.props(s)) {
        let f = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.4}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        pairs.push(("selected_name", p.name));
        pairs.push(("selected_position", f(&p.position)));
        pairs.push(("selected_yaw", format!("{:.2}", p.yaw_deg)));
        pairs.push(("selected_size", f(&p.size)));
        pairs.push((
            "selected_friction",
            p.friction.map_or(String::new(), |v| format!("{v}")),
        ));
    }
    let rp = env.robot_pose.translation;
    pairs.push((
        "robot_pose",
        format!("{:.4} {:.4} {:.4}", rp[0], rp[1], rp[2]),
    ));
    pairs.extend(crate::gui::module_editor::script::state_pairs(modules));
    pairs.push(("registry_modules", state.wizard.registry.names().join(",")));
    state_report(&pairs)
}
