//! proleg's configuration files: the thesis's XML formats (appendix B) and our
//! extensions, read into typed models, written back, and checked.
//!
//! - [`simulation`]: `*.simulation.xml`, the top-level file naming the others (B.1)
//! - [`robot`], [`kinbody`], [`body`], [`sensor`]: robots, module parts, sensors (B.2-B.4)
//! - [`actuation`]: which modules drive which joints (B.5)
//! - [`environment`]: physics and terrain (B.6); [`terrain`]: procedural courses (families,
//!   difficulty, seed) generated into an environment's bodies; [`suite`]: task suites
//!   (tasks on terrain families with train and held-out test seeds)
//! - [`optimizer`]: the optimizer file (B.7: the GA and great deluge, and our CMA-ES,
//!   evolution strategy and MAP-Elites); [`fitness`]: the names of the fitness functions
//!   they choose from; our extensions of it: [`cross_engine`] (scores on several engines),
//!   [`robustness`] (randomized episodes), [`courses`] (a suite's train courses as the
//!   episodes' worlds), [`morphology`] (co-design's bodies)
//! - [`module_types`]: what the loader knows of actuation-module types (parameters,
//!   ranges, series) to check files against
//! - [`remote`]: remote (gamepad) bindings to module parameters (our extension)
//! - [`servos`]: the real robot's servos on the bus (our extension of robot files)
//! - [`contact`]: an environment's contact model in physical units (our extension)
//! - [`robot_builder`]: a chain robot from its topology and a part set (thesis 4.4.3)
//! - [`mask`]: joint masks; [`transform`]: poses; [`mesh`]: OBJ meshes and height maps
//! - [`source`]: where files come from (the disk, or files in memory)
//! - [`xml`]: the XML plumbing every format shares; [`error`]: located errors
//! - [`resolve`]: loading a simulation with all its includes into checked models
//! - [`start_clearance`]: whether a robot's start pose is free of itself and the scenery
//! - [`bundle`]: a configuration's files written into a folder that stands alone
//! - [`summary`]: what `proleg check` prints of a loaded simulation
//!
//! Every error names the file, line and column and says what was expected
//! ([`ConfigError`]). Each `parse_*_file` / `write_*_file` pair round-trips: writing a
//! model and reading it back gives an equal model.

pub mod actuation;
pub mod body;
pub mod bundle;
pub mod contact;
pub mod courses;
pub mod cross_engine;
pub mod environment;
pub mod error;
pub mod fitness;
pub mod kinbody;
pub mod mask;
pub mod mesh;
pub mod module_types;
pub mod morphology;
pub mod optimizer;
pub mod remote;
pub mod resolve;
pub mod robot;
pub mod robot_builder;
pub mod robustness;
pub mod sensor;
pub mod servos;
pub mod simulation;
pub mod source;
pub mod start_clearance;
pub mod suite;
pub mod summary;
pub mod terrain;
pub mod transform;
pub mod xml;

pub use error::{ConfigError, ConfigResult, ErrorKind, Pos};
pub use resolve::{Simulation, load_simulation_with};
pub use source::{FileSource, FsSource, MemSource, RecordingSource};
