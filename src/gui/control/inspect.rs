//! Data file inspection (thesis 4.5.6): load a recorded data file, choose the x series
//! (simulated time, real time, step count or sample index) and y series from a tree per
//! handler and part, add graphs (box-zoom with a right drag, reset with a double click),
//! save a graph as PNG or export its series as TSV — with the same code as `proleg data
//! plot` and `proleg data export`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use bevy::prelude::*;
use bevy_egui::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints};

use crate::data::export::{SeriesSelector, XAxis, export, for_each_row};
use crate::data::read::{DataInfo, info};
use crate::gui::control::widgets::{ensure_parent, set_checkbox};

/// A graph of chosen series.
#[derive(Debug, Clone)]
pub struct Graph {
    /// Identifies the graph's plot widget.
    pub id: u64,
    /// The x axis.
    pub x: XAxis,
    /// The series shown.
    pub selectors: Vec<SeriesSelector>,
    /// Each series' title and points.
    pub lines: Vec<(String, Vec<[f64; 2]>)>,
}

/// The inspection window's state.
#[derive(Resource, Debug, Clone)]
pub struct InspectState {
    /// Whether the window is shown.
    pub open: bool,
    /// The data file path typed.
    pub path: String,
    /// The loaded file and its summary.
    pub file: Option<(PathBuf, DataInfo)>,
    /// The x axis of new graphs.
    pub x: XAxis,
    /// Checked (handler, series, part).
    pub checked: BTreeSet<(String, String, usize)>,
    /// The graphs drawn.
    pub graphs: Vec<Graph>,
    next_id: u64,
    /// Where "Save PNG" / "Export TSV" write (the extension is replaced).
    pub out_stem: String,
    /// The last message (an error, what was exported).
    pub message: String,
}

impl Default for InspectState {
    fn default() -> Self {
        InspectState {
            open: false,
            path: "out/demo.data.xml".into(),
            file: None,
            x: XAxis::SimTime,
            checked: BTreeSet::new(),
            graphs: Vec::new(),
            next_id: 0,
            out_stem: "out/graph".into(),
            message: String::new(),
        }
    }
}

impl InspectState {
    /// Reads the header and extent of `path`.
    pub fn load(&mut self, path: &Path) {
        match info(path) {
            Ok(i) => {
                self.message = format!(
                    "{} handlers, {} rounds{}",
                    i.handlers.len(),
                    i.rounds,
                    if i.cut {
                        " (cut: the run did not finish)"
                    } else {
                        ""
                    }
                );
                self.file = Some((path.to_path_buf(), i));
                self.checked.clear();
            }
            Err(e) => self.message = e.to_string(),
        }
    }

    /// Adds a graph of the checked series; returns its id.
    pub fn add_graph(&mut self) -> Option<u64> {
        let (path, _) = self.file.as_ref()?;
        let selectors: Vec<SeriesSelector> = self
            .checked
            .iter()
            .map(|(h, s, k)| SeriesSelector {
                handler: h.clone(),
                series: s.clone(),
                parts: Some((*k, *k)),
            })
            .collect();
        let mut lines: Vec<(String, Vec<[f64; 2]>)> = Vec::new();
        let read = for_each_row(path, self.x, &selectors, |cols, x, values| {
            if lines.is_empty() {
                lines = cols.iter().map(|c| (c.title.clone(), Vec::new())).collect();
            }
            for (l, v) in lines.iter_mut().zip(values) {
                l.1.push([x, *v]);
            }
            Ok(())
        });
        match read {
            Ok((rows, _, _)) => {
                let id = self.next_id;
                self.next_id += 1;
                self.message = format!("graph {}: {rows} rows", id + 1);
                self.graphs.push(Graph {
                    id,
                    x: self.x,
                    selectors,
                    lines,
                });
                Some(id)
            }
            Err(e) => {
                self.message = e.to_string();
                None
            }
        }
    }

    /// Graph `id`, its data file and the output path with extension `ext`.
    fn output(&self, id: u64, ext: &str) -> Option<(&Graph, &Path, PathBuf)> {
        let g = self.graphs.iter().find(|g| g.id == id)?;
        let (path, _) = self.file.as_ref()?;
        let out = PathBuf::from(format!("{}-{}.{ext}", self.out_stem, id + 1));
        ensure_parent(&out);
        Some((g, path, out))
    }

    /// Saves graph `id` as `<out_stem>-<id>.png` with the headless plotter.
    pub fn save_png(&mut self, id: u64) {
        let Some((g, path, out)) = self.output(id, "png") else {
            return;
        };
        self.message = match crate::data::plot::plot(path, g.x, &g.selectors, &out, (1200, 700)) {
            Ok(s) => format!("wrote {} ({} rows)", out.display(), s.rows),
            Err(e) => e.to_string(),
        };
    }

    /// Exports graph `id`'s series as `<out_stem>-<id>.tsv`.
    pub fn export_tsv(&mut self, id: u64) {
        let Some((g, path, out)) = self.output(id, "tsv") else {
            return;
        };
        let result = std::fs::File::create(&out)
            .map_err(|e| format!("{}: {e}", out.display()))
            .and_then(|f| {
                let mut w = std::io::BufWriter::new(f);
                export(path, g.x, &g.selectors, '\t', &mut w).map_err(|e| e.to_string())
            });
        self.message = match result {
            Ok(s) => format!("wrote {} ({} rows)", out.display(), s.rows),
            Err(e) => e,
        };
    }
}

/// Draws the inspection window.
pub fn show(ctx: &egui::Context, state: &mut InspectState) {
    let mut open = state.open;
    egui::Window::new("Data file inspection")
        .open(&mut open)
        .default_size([900.0, 520.0])
        .show(ctx, |ui| {
            ui.horizontal(|ui| {
                ui.label("Data file:");
                ui.add(egui::TextEdit::singleline(&mut state.path).desired_width(320.0));
                if ui.button("Load").clicked() {
                    let p = PathBuf::from(state.path.trim());
                    state.load(&p);
                }
                ui.label("x:");
                for (name, axis) in XAxis::NAMES.iter().zip([
                    XAxis::SimTime,
                    XAxis::RealTime,
                    XAxis::StepCount,
                    XAxis::Index,
                ]) {
                    ui.selectable_value(&mut state.x, axis, *name);
                }
            });
            ui.label(&state.message);
            ui.separator();
            ui.horizontal_top(|ui| {
                ui.vertical(|ui| {
                    ui.set_width(260.0);
                    tree(ui, state);
                });
                ui.separator();
                ui.vertical(|ui| graphs(ui, state));
            });
        });
    state.open = open;
}

/// The series tree and "Add graph".
fn tree(ui: &mut egui::Ui, state: &mut InspectState) {
    let Some((_, info)) = &state.file else {
        ui.label("Load a data file (proleg run --data FILE writes one).");
        return;
    };
    let handlers = info.handlers.clone();
    egui::ScrollArea::vertical()
        .max_height(380.0)
        .show(ui, |ui| {
            for h in &handlers {
                egui::CollapsingHeader::new(&h.name).show(ui, |ui| {
                    for (s, name) in h.series.iter().enumerate() {
                        ui.horizontal_wrapped(|ui| {
                            ui.label(name);
                            for k in 0..h.parts[s] {
                                let key = (h.name.clone(), name.clone(), k);
                                let text = if h.parts[s] > 1 {
                                    k.to_string()
                                } else {
                                    String::new()
                                };
                                set_checkbox(ui, &mut state.checked, key, text);
                            }
                        });
                    }
                });
            }
        });
    ui.horizontal(|ui| {
        if ui
            .add_enabled(!state.checked.is_empty(), egui::Button::new("Add graph"))
            .clicked()
        {
            state.add_graph();
        }
        ui.label("save as");
        ui.add(egui::TextEdit::singleline(&mut state.out_stem).desired_width(100.0));
    });
}

/// The graphs with their buttons.
fn graphs(ui: &mut egui::Ui, state: &mut InspectState) {
    let mut action: Option<(u64, &str)> = None;
    egui::ScrollArea::vertical().show(ui, |ui| {
        for g in &state.graphs {
            ui.horizontal(|ui| {
                ui.label(format!("graph {}", g.id + 1));
                for a in ["Save PNG", "Export TSV", "Delete"] {
                    if ui.small_button(a).clicked() {
                        action = Some((g.id, a));
                    }
                }
            });
            Plot::new(("data graph", g.id))
                .height(220.0)
                .legend(Legend::default())
                .allow_boxed_zoom(true)
                .x_axis_label(g.x.title())
                .show(ui, |p| {
                    for (name, pts) in &g.lines {
                        p.line(Line::new(name.clone(), PlotPoints::from(pts.clone())));
                    }
                });
        }
    });
    match action {
        Some((id, "Save PNG")) => state.save_png(id),
        Some((id, "Export TSV")) => state.export_tsv(id),
        Some((id, _)) => state.graphs.retain(|g| g.id != id),
        None => {}
    }
}

/// The data file inspection's state.
pub struct InspectPlugin;

impl Plugin for InspectPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<InspectState>();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loads_graphs_saves_and_exports_the_thesis_data_file() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let out = std::env::temp_dir().join(format!("proleg-inspect-{}", std::process::id()));
        let mut s = InspectState {
            out_stem: out.join("g").display().to_string(),
            ..InspectState::default()
        };
        s.load(&root.join("tests/fixtures/thesis/data/B.8.data.xml"));
        assert!(s.file.is_some(), "{}", s.message);
        s.checked
            .insert(("PatternGenerator_sinusoidal".into(), "Angle".into(), 2));
        s.checked
            .insert(("Global_Adaptive_Touch".into(), "desired_angle".into(), 0));
        let id = s.add_graph().expect("graph");
        let g = &s.graphs[0];
        assert_eq!(g.lines.len(), 2);
        assert!(
            g.lines.iter().all(|(_, pts)| pts.len() == 2),
            "{:?}",
            g.lines
        );
        // Same titles as `proleg data` columns.
        assert!(
            g.lines
                .iter()
                .any(|(t, _)| t == "PatternGenerator_sinusoidal/Angle[2]")
        );
        s.export_tsv(id);
        let tsv = std::fs::read_to_string(out.join("g-1.tsv")).expect("tsv written");
        assert_eq!(tsv.lines().count(), 3, "{tsv}");
        s.save_png(id);
        assert!(out.join("g-1.png").exists(), "{}", s.message);
        // A missing file is a message, not a panic, and keeps nothing loaded.
        let mut bad = InspectState::default();
        bad.load(Path::new("no/such.data.xml"));
        assert!(
            bad.file.is_none() && bad.message.contains("no/such.data.xml"),
            "{}",
            bad.message
        );
        assert!(bad.add_graph().is_none());
    }
}
