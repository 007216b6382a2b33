//! The wizard's simulation page: mode, step width, sampling, duration.

use crate::compose::optimization::Method;
use crate::compose::wizard::Wizard;
use crate::config::simulation::Mode;
use bevy_egui::egui;

pub(super) fn simulation_page(ui: &mut egui::Ui, w: &mut Wizard) {
    crate::gui::setup::properties_view::show(ui, &mut w.props, &mut w.description);
    match w.props.mode {
        Mode::GeneticAlgorithm => w.optimization.method = Method::Genetic,
        Mode::GreatDeluge => w.optimization.method = Method::GreatDeluge,
        Mode::CmaEs => w.optimization.method = Method::CmaEs,
        Mode::MapElites => w.optimization.method = Method::MapElites,
        _ => {}
    }
}
