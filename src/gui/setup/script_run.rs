//! Runs a [`crate::gui::setup::script`] in the configuration window: each frame, commands
//! are carried out until one has to wait (frames, a screenshot being written). A failing
//! command prints `error: FILE:LINE: cause` and closes the window with a failure.

use std::path::PathBuf;

use bevy::prelude::*;

use crate::compose::env_edit::{EnvEditor, Selected};
use crate::compose::expert::Part;
use crate::compose::library::LibraryItem;
use crate::compose::optimization::ValueSet;
use crate::compose::wizard::{RegisterSpec, Wizard};
use crate::gui::control::script::state_report;
use crate::gui::module_editor::ModuleEditor;
use crate::gui::scripting::{CommandError, Flow, run_commands};
use crate::gui::setup::editor::view::preview;
use crate::gui::setup::script::{
    Command, Script, SetupScript, Sharing, ToolName, WaitFor, WizardField,
};
use crate::gui::setup::state::{SetupState, Status, Tool};

/// Carries out script commands (before the views update).
pub fn run_script(
    mut commands: Commands,
    mut runner: ResMut<SetupScript>,
    mut state: ResMut<SetupState>,
    mut modules: ResMut<ModuleEditor>,
    mut exit: MessageWriter<AppExit>,
    mut pending: ResMut<crate::gui::desktop::ScriptPending>,
) {
    run_commands(&mut runner.0, &mut exit, |c, script| {
        carry_out(c, &mut commands, script, &mut state, &mut modules)
    });
    let playing = runner.0.as_ref().is_some_and(|s| s.next < s.commands.len());
    pending.set_if_neq(crate::gui::desktop::ScriptPending(playing));
}

fn item(state: &SetupState, name: &str) -> Result<LibraryItem, CommandError> {
    state
        .library
        .iter()
        .find(|i| i.label().eq_ignore_ascii_case(name))
        .cloned()
        .or_else(|| LibraryItem::parse(name))
        .ok_or_else(|| CommandError::Missing {
            what: "library item",
            name: name.to_string(),
        })
}

fn carry_out(
    c: Command,
    commands: &mut Commands,
    script: &mut Script,
    state: &mut SetupState,
    modules: &mut ModuleEditor,
) -> Result<Flow, CommandError> {
    match c {
        Command::Wait { frames } => {
            script.pacing.waiting = frames;
            return Ok(Flow::Yield);
        }
        Command::SlowFrames { ms } => {
            script.pacing.frame_delay = std::time::Duration::from_millis(u64::from(ms));
        }
        Command::WaitFor(WaitFor::File { path, frames }) => {
            let what = path.display().to_string();
            return script.pacing.poll(path.exists(), frames, &what);
        }
        Command::Tool { tool } => {
            state.tool = match tool {
                ToolName::Wizard => Tool::Wizard,
                ToolName::Expert => Tool::Expert,
                ToolName::Editor => Tool::Editor,
            }
        }
        Command::Set(field) => set_field(&mut state.wizard, field)?,
        Command::Next => state.wizard.next_page()?,
        Command::Back => state.wizard.back(),
        Command::Skip => state.wizard.skip()?,
        Command::Save => {
            let p = state.wizard.save()?;
            state.status = Some(Status::Info(format!("saved {}", p.display())));
        }
        Command::Add { .. }
        | Command::Drop { .. }
        | Command::Select { .. }
        | Command::MoveTo(_)
        | Command::MoveBy(_)
        | Command::DragTo { .. }
        | Command::Rotate { .. }
        | Command::Yaw { .. }
        | Command::Scale { .. }
        | Command::Friction { .. }
        | Command::Dynamic { .. }
        | Command::Mass { .. }
        | Command::Colour { .. }
        | Command::Delete
        | Command::Undo
        | Command::Redo
        | Command::EnvSave { .. }
        | Command::EnvLoad { .. } => return editor_command(c, state),
        Command::Expert { .. }
        | Command::ExpertSave { .. }
        | Command::ExpertEdit
        | Command::ExpertOpen { .. } => expert_command(c, state)?,
        Command::OpenControl { file } => {
            crate::gui::setup::open_control_window(state, &file);
            if let Some(Status::Error(e)) = &state.status {
                return Err(CommandError::Refused(e.clone()));
            }
        }
        Command::Preview => {
            preview(state);
            if let Some(Err(e)) = &state.preview {
                return Err(CommandError::Refused(e.to_string()));
            }
        }
        Command::Zoom { height } => state.ortho_height = (height as f32).clamp(0.05, 40.0),
        Command::Screenshot { file } => {
            script.pacing.screenshot(commands, file)?;
            return Ok(Flow::Yield);
        }
        Command::State { file } => {
            crate::gui::control::widgets::ensure_parent(&file);
            std::fs::write(&file, state_lines(state, modules))
                .map_err(|source| CommandError::Write { path: file, source })?;
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

/// `set FIELD VALUE...`: the wizard's typed setter of the field (or the plain field).
fn set_field(w: &mut Wizard, field: WizardField) -> Result<(), CommandError> {
    match field {
        WizardField::RobotName { name } => w.set_robot_name(&name)?,
        WizardField::Topology { letters } => w.set_topology(&letters.concat())?,
        WizardField::Parts { parts } => w.set_parts(parts),
        WizardField::Build => w.build_robot(),
        WizardField::Existing { file } => w.use_existing_robot(&file)?,
        WizardField::Simple { module } => w.set_simple_behaviour(&module)?,
        WizardField::ClearGroups => w.behaviour.groups.clear(),
        WizardField::Group { mask, modules } => w.add_group(&mask, &modules)?,
        WizardField::GroupParam {
            group,
            module,
            param,
            values,
        } => w.set_group_param(group, &module, &param, &values)?,
        WizardField::Mode { mode } => w.set_mode(mode.mode()),
        WizardField::Step { seconds } => w.props.step_width = seconds,
        WizardField::Accuracy { steps } => w.props.accuracy = steps,
        WizardField::Duration { seconds } => w.props.duration = seconds,
        WizardField::Seed { seed } => w.props.seed = seed,
        WizardField::Storing { on } => w.props.storing_data = on == 1,
        WizardField::Viewer { on } => w.props.show_viewer = on == 1,
        WizardField::Description { words } => w.description = words.join(" "),
        WizardField::Register {
            module,
            param,
            joints,
            sharing,
            values,
        } => w.register(RegisterSpec {
            module,
            parameter: param,
            joints: (joints != "all").then_some(joints),
            uniform: sharing == Sharing::Uniform,
            values: value_set(&values)?,
        })?,
        WizardField::ClearRegistrations => w.optimization.params.clear(),
        WizardField::Popsize { size } => w.optimization.ga.popsize = size,
        WizardField::MaxEvals { evaluations } => w.optimization.max_evaluations = Some(evaluations),
        WizardField::Fitness { fitness } => w.optimization.fitness = fitness,
        WizardField::Morphology {
            min,
            max,
            orientations,
            parts,
            motif,
        } => w
            .optimization
            .set_morphology(Some(crate::config::morphology::Morphology {
                modules: [min, max],
                orientations,
                motif,
                parts,
                pos: crate::config::error::Pos::new(0, 0),
            })),
        WizardField::FixedBody => w.optimization.set_morphology(None),
    }
    Ok(())
}

/// `LO HI INC` or `list v1,v2,...`.
fn value_set(words: &[String]) -> Result<ValueSet, CommandError> {
    let number = |w: &str| crate::gui::scripting::finite(w.trim());
    Ok(match words {
        [list, values] if list == "list" => {
            ValueSet::List(values.split(',').map(number).collect::<Result<_, _>>()?)
        }
        [lower, upper, increment] => ValueSet::Range {
            lower: number(lower)?,
            upper: number(upper)?,
            increment: number(increment)?,
        },
        _ => {
            return Err(CommandError::NotNow(
                "opt.register: give LO HI INC or list v1,v2,...",
            ));
        }
    })
}

/// The environment editor's commands (the editor tool, or the wizard's environment page):
/// adding, dropping and selecting here, the rest in [`edit_command`].
fn editor_command(c: Command, state: &mut SetupState) -> Result<Flow, CommandError> {
    let env_only = |state: &SetupState| {
        if state.editing_env() {
            Ok(())
        } else {
            Err(CommandError::NotNow(
                "not in the environment editor (tool editor, or the wizard's environment page)",
            ))
        }
    };
    match c {
        Command::Add { item: name, x, y } => {
            env_only(state)?;
            let it = item(state, &name)?;
            let env = state.env_mut();
            let [x, y] = match (x, y) {
                (Some(x), Some(y)) => [x, y],
                _ => {
                    let r = env.robot_pose;
                    let a = r.rotate([0.0, 1.0, 0.0]);
                    [r.translation[0] + a[0], r.translation[1] + a[1]]
                }
            };
            env.add(&it, x, y);
        }
        Command::Drop { item: name, px, py } => {
            env_only(state)?;
            state.drop = Some((item(state, &name)?, Vec2::new(px, py)));
            // The drop is placed by the picking system this frame.
            return Ok(Flow::Yield);
        }
        Command::Select { what } => {
            env_only(state)?;
            let sel = match what.as_str() {
                "robot" => Some(Selected::Robot),
                "none" => None,
                n => Some(Selected::Object(n.parse().map_err(|_| {
                    CommandError::Missing {
                        what: "object (a number, robot or none)",
                        name: n.to_string(),
                    }
                })?)),
            };
            state.env_mut().select(sel)?;
        }
        other => edit_command(other, state)?,
    }
    Ok(Flow::Next)
}

/// The editor's commands on the selection, undo and redo, saving and loading.
fn edit_command(c: Command, state: &mut SetupState) -> Result<(), CommandError> {
    match c {
        Command::MoveTo(p) => state.env_mut().move_to(p.array())?,
        Command::MoveBy(d) => state.env_mut().move_by(d.array())?,
        Command::DragTo { x, y } => {
            let env = state.env_mut();
            env.begin_drag();
            let r = env.drag_to(x, y);
            env.end_drag();
            r?
        }
        Command::Rotate { degrees } => state.env_mut().rotate_by(degrees)?,
        Command::Yaw { degrees } => state.env_mut().set_yaw(degrees)?,
        Command::Scale { x, y, z } => state.env_mut().scale([x, y.unwrap_or(x), z.unwrap_or(x)])?,
        Command::Friction { mu } => state.env_mut().set_friction(mu)?,
        Command::Dynamic { state: on } => state.env_mut().set_dynamic(on.on())?,
        Command::Mass { kg } => state.env_mut().set_mass(kg)?,
        Command::Colour { r, g, b } => state.env_mut().set_colour([r, g, b])?,
        Command::Delete => state.env_mut().delete()?,
        Command::Undo => {
            if !state.env_mut().undo() {
                return Err(CommandError::NotNow("nothing to undo"));
            }
        }
        Command::Redo => {
            if !state.env_mut().redo() {
                return Err(CommandError::NotNow("nothing to redo"));
            }
        }
        Command::EnvSave { file } => {
            state.editor_path = file.display().to_string();
            state.env_mut().save(&file)?;
            state.status = Some(Status::Info(format!("saved {}", file.display())));
        }
        Command::EnvLoad { file } => {
            state.editor = EnvEditor::load(&file)?;
            state.editor_path = file.display().to_string();
        }
        other => return Err(CommandError::Misrouted(format!("{other:?}"))),
    }
    Ok(())
}

/// The expert composition's commands.
fn expert_command(c: Command, state: &mut SetupState) -> Result<(), CommandError> {
    match c {
        Command::Expert { part, file } => {
            let c = &mut state.expert.composition;
            let p = (file != "none").then(|| PathBuf::from(&file));
            let part = Part::ALL
                .into_iter()
                .find(|k| k.label().eq_ignore_ascii_case(&part))
                .ok_or(CommandError::Missing {
                    what: "part (robot, actuation, environment or optimizer)",
                    name: part,
                })?;
            match (part, p) {
                (Part::Robot, Some(p)) => c.robot = p,
                (Part::Actuation, Some(p)) => c.actuation = p,
                (Part::Environment, p) => c.environment = p,
                (Part::Optimizer, p) => c.optimizer = p,
                (_, None) => {
                    return Err(CommandError::NotNow(
                        "the robot and the actuation cannot be none",
                    ));
                }
            }
        }
        Command::ExpertSave { file } => {
            state.expert.path = file.display().to_string();
            state
                .expert
                .composition
                .save(&file, &state.wizard.registry)?;
            state.expert.check = Some(
                state
                    .expert
                    .composition
                    .check(&file, &state.wizard.registry)
                    .map_err(|e| e.to_string()),
            );
        }
        Command::ExpertOpen { file } => {
            state.expert.path = file.display().to_string();
            crate::gui::setup::expert_view::open(state, &file);
        }
        Command::ExpertEdit => {
            crate::gui::setup::expert_view::edit_in_wizard(state);
            if let Some(Status::Error(e)) = &state.status {
                return Err(CommandError::Refused(e.clone()));
            }
        }
        other => return Err(CommandError::Misrouted(format!("{other:?}"))),
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
            w.joint_count()
                .map_or_else(|e| e.to_string(), |n| n.to_string()),
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
    editor_pairs(state.env_mut(), &mut pairs);
    pairs.extend(crate::gui::module_editor::script::state_pairs(modules));
    pairs.push(("registry_modules", state.wizard.registry.names().join(",")));
    state_report(&pairs)
}

/// The environment editor's part of the state: objects, undo, the selection and its
/// properties, the robot's pose.
fn editor_pairs(env: &mut EnvEditor, pairs: &mut Vec<(&str, String)>) {
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
        if let Some(t) = &p.terrain {
            pairs.push(("selected_terrain", t.label()));
        }
    }
    let rp = env.robot_pose.translation;
    pairs.push((
        "robot_pose",
        format!("{:.4} {:.4} {:.4}", rp[0], rp[1], rp[2]),
    ));
}
