//! The stored results in the optimization window: the runs of a store (a SQLite file or a
//! `postgres://` URL), each with its best score, and **Replay**: any evaluation of a run
//! (its best by default, a randomized episode of a robust run) in the viewer, rebuilt from
//! the store exactly as the optimization scored it ([`crate::optimize::replay`]).

use bevy_egui::egui;

use crate::gui::control::session::SimSession;
use crate::optimize::replay::{Which, replay_from};
use crate::optimize::store::{RunRow, Store, StoreLocation};

/// The results section's state.
#[derive(Default)]
pub struct StoredResults {
    /// The store listed (a path or a postgres:// URL).
    pub store: String,
    /// Its runs, as last listed.
    pub runs: Vec<RunRow>,
    /// Evaluation to replay (`None`: the run's best).
    pub eval: Option<u64>,
    /// Episode of a robust run to replay.
    pub episode: u32,
    /// What the last action did, or why it failed.
    pub status: String,
}

impl StoredResults {
    /// Lists the runs of `self.store`.
    pub fn list(&mut self) {
        let listed = match StoreLocation::parse(self.store.trim()) {
            Ok(l) => Store::open_existing(&l)
                .and_then(|mut s| s.runs())
                .map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        };
        match listed {
            Ok(runs) => {
                self.status = format!("{} runs", runs.len());
                self.runs = runs;
            }
            Err(e) => self.status = e,
        }
    }
}

/// Replays `which` evaluation of `run` in `store` in the session (paused at its start).
pub fn replay_stored(
    session: &mut SimSession,
    store: &str,
    run: i64,
    which: Which,
    episode: Option<u32>,
) -> Result<(), crate::gui::error::GuiError> {
    let replay = replay_from(store, run, which, episode, &session.registry)?;
    session.try_load_replay(replay)
}

/// Draws the results section.
pub fn show(ui: &mut egui::Ui, session: &mut SimSession, r: &mut StoredResults) {
    ui.separator();
    ui.horizontal(|ui| {
        ui.label("stored results:");
        ui.add(
            egui::TextEdit::singleline(&mut r.store)
                .hint_text("results .sqlite file or postgres://user@host/db")
                .desired_width(260.0),
        );
        if ui.button("List runs").clicked() {
            r.list();
        }
    });
    ui.horizontal(|ui| {
        let mut best = r.eval.is_none();
        ui.checkbox(&mut best, "best");
        let mut n = r.eval.unwrap_or(0);
        ui.add_enabled(!best, egui::DragValue::new(&mut n).prefix("evaluation "));
        r.eval = (!best).then_some(n);
        ui.add(egui::DragValue::new(&mut r.episode).prefix("episode "));
    });
    let mut chosen = None;
    egui::ScrollArea::vertical()
        .max_height(140.0)
        .show(ui, |ui| {
            for run in &r.runs {
                ui.horizontal(|ui| {
                    ui.monospace(format!(
                        "run {:>3} {} seed {} {} evals best {}",
                        run.id,
                        run.info.algorithm,
                        run.info.seed,
                        run.evaluations,
                        run.best_score.map_or("-".into(), |s| format!("{s:.4}"))
                    ));
                    if ui.button("Replay").clicked() {
                        chosen = Some(run.id);
                    }
                });
            }
        });
    if let Some(run) = chosen {
        let which = r.eval.map_or(Which::Best, Which::Number);
        let episode = (r.episode > 0).then_some(r.episode);
        r.status = match replay_stored(session, r.store.trim(), run, which, episode) {
            Ok(()) => session
                .replay
                .as_ref()
                .map_or(String::new(), |p| p.label.clone()),
            Err(e) => e.to_string(),
        };
    }
    if !r.status.is_empty() {
        ui.label(&r.status);
    }
}
