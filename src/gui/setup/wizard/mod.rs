//! The beginner wizard's pages (thesis 4.4.1, figs. 4.10-4.14): robot (topology, part set,
//! or an existing robot), behaviour (simple or grouped actuation, joints chosen in a
//! topological strip), environment (the editor), simulation properties, optimization
//! (registered parameters, algorithm settings) and the summary that saves and opens the
//! result. Every page explains itself; "Next" validates first.
//!
//! One file per page: [`robot`], [`behaviour`], [`simulation`], [`optimization`],
//! [`summary`]; the environment page is the editor ([`crate::gui::setup::editor::view`]).

pub mod behaviour;
pub mod optimization;
pub mod robot;
pub mod simulation;
pub mod summary;

use crate::compose::wizard::Page;
use crate::gui::setup::state::{SetupState, Status};
use bevy_egui::egui;

/// What each page is for.
fn explanation(page: Page) -> &'static str {
    match page {
        Page::Robot => {
            "Describe the robot: how many joints it has and whether each turns up and down (pitch) or left and right (yaw). Choose the module parts; the touch set carries 12 pads under the links, which sensing modules need. Or pick a robot that already exists."
        }
        Page::Behaviour => {
            "Choose how the joints move. Simple: one module drives every joint. Grouped: select joints in the strip, make a group of them, and give it one or more modules (their outputs add up)."
        }
        Page::Environment => {
            "Build the terrain: drag objects from the library onto the views, click to select, drag to move. The yellow arrow is the robot's start pose. You may skip this page: the robot then crawls on a flat floor."
        }
        Page::Simulation => {
            "How the simulation runs: the mode (a single run or an optimization), the physics step width, how often data is sampled, how long a run lasts. You may skip this page to keep the defaults."
        }
        Page::Optimization => {
            "Register the module parameters the optimizer may change, the joints they apply to, and the values they may take. The algorithm settings start at the thesis's values."
        }
        Page::Summary => {
            "The files below will be written. Save them, then open the simulation in the control window."
        }
    }
}

/// The current page with its navigation.
pub fn show(ui: &mut egui::Ui, state: &mut SetupState) {
    let (i, n) = state.wizard.progress();
    let page = state.wizard.page;
    ui.heading(format!("Step {i} of {n}: {}", page.title()));
    ui.label(explanation(page));
    ui.separator();
    egui::ScrollArea::vertical()
        .max_height(ui.available_height() - 40.0)
        .show(ui, |ui| match page {
            Page::Robot => robot::robot_page(ui, &mut state.wizard),
            Page::Behaviour => behaviour::behaviour_page(ui, &mut state.wizard),
            Page::Environment => {
                ui.label(format!(
                    "{} objects in the scene; the library is on the left, the selection's properties on the right.",
                    state.wizard.env.objects.len()
                ));
            }
            Page::Simulation => simulation::simulation_page(ui, &mut state.wizard),
            Page::Optimization => optimization::optimization_page(ui, &mut state.wizard),
            Page::Summary => summary::summary_page(ui, state),
        });
    ui.separator();
    ui.horizontal(|ui| {
        if ui.add_enabled(i > 1, egui::Button::new("◀ Back")).clicked() {
            state.wizard.back();
        }
        if page.optional() && ui.button("Skip").clicked() {
            let r = state.wizard.skip();
            state.report(r, |_| "page skipped: defaults kept".into());
        }
        if page != Page::Summary && ui.button("Next ▶").clicked() {
            let r = state.wizard.next_page();
            state.report(r, |_| String::new());
            if matches!(state.status, Some(Status::Info(ref s)) if s.is_empty()) {
                state.status = None;
            }
        }
    });
}
