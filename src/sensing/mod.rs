//! Sensors as the control kernel sees them: the latest readings of a robot's sensors,
//! handed to sensing modules through the step context (thesis 5.2.1, listing A.3), and the
//! pure logic that turns raw contacts into debounced touch states ([`debounce`]).

pub mod debounce;

pub use debounce::Debounce;

/// The latest readings of one robot's sensors, in the robot's sensor order per kind.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SensorData {
    /// Debounced touch state of each tactile pad.
    pub tactile: Vec<bool>,
    /// Contact normal of each pad (unit, pointing from the touched surface into the pad;
    /// zero while released).
    pub tactile_normals: Vec<[f64; 3]>,
    /// Ranges (m) of each laser's beams, from its minimum to its maximum angle.
    pub laser: Vec<Vec<f64>>,
    /// The robot's centre of mass in world coordinates (m). In simulation this is ground
    /// truth; a real robot would get it from odometry or an external tracker.
    pub position: [f64; 3],
    /// Each robot joint's angular speed (degrees/s).
    pub joint_speeds: Vec<f64>,
    /// Gravity's direction in the head link's frame (unit; zero where unknown, as on a
    /// real robot without an inertial sensor).
    pub gravity_head: [f64; 3],
    /// The robot's tail-to-head heading in the ground plane (degrees from +x).
    pub heading: f64,
}

impl SensorData {
    /// Room for `tactile` pads, all released, and lasers with these beam counts.
    pub fn new(tactile: usize, beams: &[usize]) -> Self {
        SensorData {
            tactile: vec![false; tactile],
            tactile_normals: vec![[0.0; 3]; tactile],
            laser: beams.iter().map(|n| vec![0.0; *n]).collect(),
            position: [0.0; 3],
            joint_speeds: Vec::new(),
            gravity_head: [0.0; 3],
            heading: 0.0,
        }
    }

    /// Number of pads pressed.
    pub fn pressed(&self) -> usize {
        self.tactile.iter().filter(|p| **p).count()
    }
}
