//! Live plots (thesis 4.5.2): a selector with a tab per data handler (each actuation
//! module, each sensor type, the robot), check boxes per series and joint, "Add plot" for a
//! live plot of the checked series and "Delete" per plot; a toolbar with auto-scroll,
//! refresh rate, sampling, window length (zoom) and the distortion frame (a constant
//! offset added to a module's output, 5.2.1). Plots read the robot's ring buffers, so a
//! hidden plot costs nothing and the simulation never waits for them.

use std::collections::BTreeSet;

use bevy::prelude::*;
use bevy_egui::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints};

use crate::gui::control::session::SimSession;
use crate::gui::control::widgets::set_checkbox;
use crate::sim::datalog::DataLog;

/// A series checked in the selector: (handler name, series index, part index).
pub type SeriesRef = (String, usize, usize);

/// One plotted series: a value column of a handler's frames.
#[derive(Debug, Clone, PartialEq)]
pub struct LiveSeries {
    /// The data handler.
    pub handler: String,
    /// Index in the handler's frame values.
    pub column: usize,
    /// The legend title.
    pub title: String,
}

/// A live plot and its latest points.
#[derive(Debug, Clone)]
pub struct LivePlot {
    /// Identifies the plot widget.
    pub id: u64,
    /// Its series.
    pub series: Vec<LiveSeries>,
    points: Vec<(String, Vec<[f64; 2]>)>,
}

/// The plot selector, the plots and their toolbar.
#[derive(Resource, Debug, Clone)]
pub struct PlotsState {
    /// Selected handler tab.
    pub tab: usize,
    /// The series ticked for the next plot.
    pub checked: BTreeSet<SeriesRef>,
    /// The plots shown.
    pub plots: Vec<LivePlot>,
    next_id: u64,
    /// Follow the newest samples.
    pub auto: bool,
    /// Redraw the points every this many frames.
    pub refresh_frames: u32,
    /// Plot every this many samples.
    pub sampling: usize,
    /// Seconds of history shown.
    pub window_s: f64,
    frame: u64,
    /// Distortion frame: actuator, joint (None: all its joints), degrees.
    pub distortion: (usize, Option<usize>, f64),
    /// Where "Add plot" was drawn last frame (for the GUI tests' real clicks).
    pub add_plot_rect: Option<egui::Rect>,
    /// Where the shown tab's first series check box was drawn last frame.
    pub first_series_rect: Option<egui::Rect>,
}

impl Default for PlotsState {
    fn default() -> Self {
        PlotsState {
            tab: 0,
            checked: BTreeSet::new(),
            plots: Vec::new(),
            next_id: 0,
            auto: true,
            refresh_frames: 1,
            sampling: 1,
            window_s: 10.0,
            frame: 0,
            distortion: (0, None, 0.0),
            add_plot_rect: None,
            first_series_rect: None,
        }
    }
}

impl PlotsState {
    /// Adds a live plot of `series`; returns its id.
    pub fn add(&mut self, series: Vec<LiveSeries>) -> u64 {
        let id = self.next_id;
        self.next_id += 1;
        self.plots.push(LivePlot {
            id,
            series,
            points: Vec::new(),
        });
        id
    }

    /// Removes plot `id`.
    pub fn delete(&mut self, id: u64) {
        self.plots.retain(|p| p.id != id);
    }

    /// Reads the plots' points from the ring buffers (every `refresh_frames` frames).
    pub fn refresh(&mut self, log: Option<&DataLog>, now: f64) {
        self.frame += 1;
        if !self.frame.is_multiple_of(self.refresh_frames.max(1) as u64) {
            return;
        }
        let Some(log) = log else {
            return;
        };
        let from = if self.auto {
            now - self.window_s
        } else {
            f64::NEG_INFINITY
        };
        let every = self.sampling.max(1);
        for plot in &mut self.plots {
            plot.points.clear();
            for series in &plot.series {
                let Some(h) = log.handlers.iter().position(|h| h.name == series.handler) else {
                    continue;
                };
                let col = series.column;
                let pts: Vec<[f64; 2]> = log.rings[h]
                    .iter()
                    .step_by(every)
                    .map(|(m, v)| {
                        [
                            m.simtime_ms / 1000.0,
                            v.get(col).copied().unwrap_or(f64::NAN),
                        ]
                    })
                    .filter(|p| p[0] >= from)
                    .collect();
                plot.points.push((series.title.clone(), pts));
            }
        }
    }
}

/// The plotted series for checked `(handler, series, part)` triples: the same titles and
/// columns as `proleg data` selectors (`Handler/series[part]`, parts from 0).
pub fn live_series(
    handlers: &[crate::data::handler::HandlerSpec],
    checked: impl IntoIterator<Item = SeriesRef>,
) -> Vec<LiveSeries> {
    checked
        .into_iter()
        .filter_map(|(handler, s, part)| {
            let spec = handlers.iter().find(|h| h.name == handler)?;
            let name = spec.series.get(s)?;
            let n = *spec.parts.get(s)?;
            let title = if n > 1 {
                format!("{handler}/{name}[{part}]")
            } else {
                format!("{handler}/{name}")
            };
            Some(LiveSeries {
                column: spec.offset(s) + part,
                handler,
                title,
            })
        })
        .collect()
}

/// Draws the toolbar, the selector and the plots.
pub fn show(ui: &mut egui::Ui, session: &mut SimSession, state: &mut PlotsState) {
    toolbar(ui, session, state);
    ui.separator();
    let Ok(log) = session.simulator.data(0) else {
        ui.label("no data handlers");
        return;
    };
    let specs = log.handlers.clone();
    ui.horizontal_top(|ui| {
        ui.vertical(|ui| {
            ui.set_width(300.0);
            selector(ui, &specs, state);
        });
        ui.separator();
        egui::ScrollArea::horizontal().show(ui, |ui| {
            ui.horizontal_top(|ui| {
                let mut delete = None;
                for plot in &state.plots {
                    ui.vertical(|ui| {
                        ui.horizontal(|ui| {
                            ui.label(format!("plot {}", plot.id + 1));
                            if ui.small_button("Delete").clicked() {
                                delete = Some(plot.id);
                            }
                        });
                        let (lo, hi) = y_span(plot);
                        Plot::new(("live plot", plot.id))
                            .include_y(lo)
                            .include_y(hi)
                            .width(420.0)
                            .height(ui.available_height().max(120.0))
                            .legend(Legend::default())
                            .x_axis_label("simulated time (s)")
                            .show(ui, |p| {
                                for (name, pts) in &plot.points {
                                    p.line(Line::new(name.clone(), PlotPoints::from(pts.clone())));
                                }
                            });
                    });
                }
                if let Some(id) = delete {
                    state.delete(id);
                }
            });
        });
    });
}

/// The plot toolbar and the distortion frame.
fn toolbar(ui: &mut egui::Ui, session: &mut SimSession, state: &mut PlotsState) {
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut state.auto, "follow newest")
            .on_hover_text("the plots scroll with the simulation, showing the last window (s)");
        ui.label("refresh every");
        ui.add(egui::DragValue::new(&mut state.refresh_frames).range(1..=120));
        ui.label("frames, sampling 1 in");
        ui.add(egui::DragValue::new(&mut state.sampling).range(1..=100));
        ui.label("window (s)");
        ui.add(
            egui::DragValue::new(&mut state.window_s)
                .range(0.5..=600.0)
                .speed(0.5),
        );
        ui.separator();
        ui.label("Distortion: module");
        let Ok(kernel) = session.simulator.kernel(0) else {
            return;
        };
        let n = kernel.actuators().len();
        let (a, joint, deg) = &mut state.distortion;
        ui.add(egui::DragValue::new(a).range(0..=n.saturating_sub(1)));
        let joints = kernel
            .actuators()
            .get(*a)
            .map(|x| x.joints.clone())
            .unwrap_or_default();
        egui::ComboBox::from_id_salt("distortion joint")
            .selected_text(joint.map_or("all joints".to_string(), |j| format!("J{}", j + 1)))
            .show_ui(ui, |ui| {
                ui.selectable_value(joint, None, "all joints");
                for j in &joints {
                    ui.selectable_value(joint, Some(*j), format!("J{}", j + 1));
                }
            });
        ui.add(egui::DragValue::new(deg).range(-90.0..=90.0).suffix("°"));
        let (a, joint, deg) = (*a, *joint, *deg);
        if ui.button("Apply").clicked()
            && let Ok(k) = session.simulator.kernel_mut(0)
            && let Err(e) = k.set_distortion(a, joint, deg)
        {
            session.error = Some(e.to_string());
        }
    });
}

/// The y range a plot must show at least: its values' span, widened to ±1 around a
/// constant (all values equal, e.g. zero at the start, drew an axis labelled only "0").
fn y_span(plot: &LivePlot) -> (f64, f64) {
    let (lo, hi) = plot
        .points
        .iter()
        .flat_map(|(_, pts)| pts.iter().map(|p| p[1]))
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        (-1.0, 1.0)
    } else if hi - lo < 1e-9 {
        (lo - 1.0, hi + 1.0)
    } else {
        (lo, hi)
    }
}

/// Handler tabs, series check boxes and "Add plot".
fn selector(ui: &mut egui::Ui, log: &[crate::data::handler::HandlerSpec], state: &mut PlotsState) {
    if log.is_empty() {
        return;
    }
    state.tab = state.tab.min(log.len() - 1);
    ui.horizontal_wrapped(|ui| {
        for (i, h) in log.iter().enumerate() {
            ui.selectable_value(&mut state.tab, i, h.name.as_str());
        }
    });
    let h = &log[state.tab];
    state.first_series_rect = None;
    egui::ScrollArea::vertical()
        .max_height(ui.available_height() - 30.0)
        .show(ui, |ui| {
            for (s, name) in h.series.iter().enumerate() {
                let parts = h.parts.get(s).copied().unwrap_or(1);
                ui.horizontal_wrapped(|ui| {
                    ui.label(name);
                    for part in 0..parts {
                        let key = (h.name.clone(), s, part);
                        let text = if parts > 1 {
                            format!("{part}")
                        } else {
                            String::new()
                        };
                        let rect = set_checkbox(ui, &mut state.checked, key, text);
                        state.first_series_rect.get_or_insert(rect);
                    }
                });
            }
        });
    // The buttons first, the count after them: a count that appears or grows moves no
    // button from under the pointer.
    ui.horizontal(|ui| {
        let any = !state.checked.is_empty();
        let add = ui.add_enabled(any, egui::Button::new("Add plot"));
        state.add_plot_rect = Some(add.rect);
        if add.clicked() {
            let series = live_series(log, std::mem::take(&mut state.checked));
            state.add(series);
        }
        if ui.button("Clear").clicked() {
            state.checked.clear();
        }
        if any {
            ui.label(format!("{} series ticked", state.checked.len()));
        }
    });
}

/// The live plots' state.
pub struct PlotsPlugin;

impl Plugin for PlotsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PlotsState>();
    }
}
