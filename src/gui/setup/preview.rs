//! Previews of what the wizard composes: the robot's links for the 3D view (built in
//! memory, nothing written), and a short headless run of the whole configuration in its
//! scene ("Preview": how far does the robot get?).

use std::path::{Path, PathBuf};

use crate::compose::paths::OverlaySource;
use crate::compose::wizard::{RobotChoice, Wizard};
use crate::config::resolve::robot::{RobotModel, resolve_robot};
use crate::config::robot::{parse_robot_file, write_robot_file};
use crate::config::source::FsSource;
use crate::control::load_simulation_in;
use crate::gui::error::GuiError;
use crate::sim::{BuildOptions, Simulator};

/// A key that changes whenever the robot the wizard describes changes.
pub fn robot_key(w: &Wizard) -> String {
    match &w.robot {
        RobotChoice::Build(s) => format!("{}:{}:{:?}", s.name, w.topology(), s.parts),
        RobotChoice::Existing(p) => p.display().to_string(),
    }
}

/// The robot's links (robot frame), resolved the way a simulation resolves them.
pub fn robot_model(w: &Wizard) -> Result<RobotModel, GuiError> {
    match &w.robot {
        RobotChoice::Build(spec) => {
            spec.validate()?;
            let path = w
                .files()
                .robot
                .unwrap_or_else(|| w.out_dir.join("preview.robot.xml"));
            let parts =
                crate::compose::paths::relative_path(&w.out_dir, &w.configs_dir.join("parts"));
            let file = spec.to_robot_file(&parts);
            let mut src = OverlaySource::default();
            src.unsaved.insert(&path, write_robot_file(&file));
            Ok(resolve_robot(&src, &path, &file)?)
        }
        RobotChoice::Existing(p) => robot_file_model(p),
    }
}

/// The links of a robot file.
pub fn robot_file_model(p: &Path) -> Result<RobotModel, GuiError> {
    let text = std::fs::read_to_string(p).map_err(GuiError::io(p))?;
    let file = parse_robot_file(&p.display().to_string(), &text)?;
    Ok(resolve_robot(&FsSource, p, &file)?)
}

/// Samples of robot 0's path a preview keeps per simulated second.
const TRACK_RATE: f64 = 10.0;

/// What a preview run showed.
#[derive(Debug, Clone, PartialEq)]
pub struct PreviewRun {
    /// The simulation file written for it.
    pub sim: PathBuf,
    /// How far robot 0 crawled (eq. 3.7, m).
    pub distance: f64,
    /// Robot 0's centre of mass every 0.1 s (m, z up), drawn in the 3D views.
    pub track: Vec<[f64; 3]>,
}

/// Writes the configuration into a preview folder (`.preview/` in the output folder) and
/// runs it headless for `seconds`: the simulation file, the distance robot 0 crawled
/// (eq. 3.7) and its path.
pub fn run_preview(w: &Wizard, seconds: f64) -> Result<PreviewRun, GuiError> {
    let mut p = w.clone();
    // Beside the real files, so meshes and parts are found the same way.
    p.out_dir = w.out_dir.join(".preview");
    p.stamp = "preview".into();
    // Preview in the single-run mode whatever the wizard's mode.
    p.props.mode = crate::config::simulation::Mode::SingleRun;
    let sim_path = p.save()?;
    let sim = load_simulation_in(&sim_path, &w.registry)?;
    let opts = BuildOptions {
        robots: 1,
        seed: sim.files.simulation.properties.seed,
        record: false,
        ..Default::default()
    };
    let mut s = Simulator::with_registry(&sim, &opts, &w.registry)?;
    let start = s.com(0)?;
    let mut track = vec![start];
    let samples = (seconds * TRACK_RATE).ceil().max(1.0) as usize;
    for _ in 0..samples {
        s.run_for(seconds / samples as f64);
        track.push(s.com(0)?);
    }
    let end = track.last().copied().unwrap_or(start);
    Ok(PreviewRun {
        sim: sim_path,
        distance: crate::measure::ground_distance(start, end),
        track,
    })
}
