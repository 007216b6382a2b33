//! # proleg
//!
//! Design, simulate, optimize and drive the locomotion of chain-like modular robots
//! (snake and caterpillar robots built from modules joined by pitch/yaw hinge servos).
//!
//! ## Contents (the files of `src/`)
//! - [`bench`]: throughput figures of the reference scenario.
//! - [`calibrate`]: servo identification from real-robot recordings (`proleg calibrate`).
//! - [`cli`]: the command line's logic (each `proleg` subcommand as a function returning a
//!   typed report); `main.rs` only parses and prints.
//! - [`commands`]: the parsed command line (clap) and its dispatch to [`cli`] or a window.
//! - [`compose`]: composing configurations without XML — robot builder, behaviour
//!   groups, environment editor model, the wizard's pages, the expert composition.
//! - [`config`]: the XML configuration formats (simulation, robot, module parts, sensors,
//!   actuation, environment, optimizer), loading with includes, validation with
//!   located errors, writing back, and the `proleg check` summary.
//! - [`control`]: the actuation-module interface, the registry of module types, the
//!   standard module library, the control kernel, learned policies and what they observe.
//! - [`dashboard`]: `proleg dashboard`, a live read-only web page over any experiment store.
//! - [`data`]: recorded data: data handlers, ring buffers for live plots, the B.8 data file
//!   written and read back, exported and plotted.
//! - `gui` (feature `gui`): the control window, a Bevy 3D viewer with egui views on the
//!   same core.
//! - [`gym`]: reinforcement-learning environments over any simulation file (the
//!   Gymnasium shape, single and vectorized), for the Python package.
//! - [`interop`]: other robotics formats: URDF robots in, MuJoCo MJCF out.
//! - [`measure`]: formulas on positions shared by every layer (displacement, potential
//!   energy).
//! - [`optimize`]: parameter optimization: the search space, the optimizers (GA, great
//!   deluge, CMA-ES, OpenAI-ES, MAP-Elites), the evaluator, the experiment store (SQLite or
//!   a PostgreSQL store shared by workers on many hosts), replays and results.
//! - [`playback`]: a 3D replay in the browser: episodes recorded as pose streams and the
//!   three.js viewer page that plays them (`proleg run --html`, the dashboard).
//! - [`plugin_host`]: user actuation modules in runtime-loaded libraries (the
//!   `proleg-plugin-api` C ABI), their building and templates.
//! - [`remote`]: remote controls (gamepads) bound to module parameters.
//! - [`robot_io`]: real robots — the robot-control interface, the Dynamixel driver, an
//!   emulated bus, the real-robot mode.
//! - [`rng`]: the seeded random numbers of a run.
//! - [`sensing`]: sensor readings as modules see them, touch debouncing.
//! - [`signal`]: one process-wide Ctrl-C / SIGTERM handler handing out stop flags.
//! - [`suite`]: task suites run: a controller scored on held-out test courses of procedural
//!   terrains on both engines, journaled and resumable.
//! - [`sim`]: the simulated world as ECS (a physics engine, rapier or MuJoCo, behind one
//!   interface; servos; the fixed-step pipeline), the headless [`sim::Simulator`] and the
//!   one episode runner ([`sim::episode`]).
//!
//! Each folder's `//!` header is the one description of its files (`tests/module_map.rs`
//! fails when a `pub mod` is missing from it): read down from here.
//!
//! Pure logic stays free of rendering, so everything here runs and tests headless.

#![warn(missing_docs)]

/// Every Rust allocation of a program linking this library (the `proleg` binary, the
/// Python extension, the tests) goes to mimalloc, whose large regions the kernel backs by
/// transparent huge pages: with glibc's allocator the many small objects of 64 worlds
/// stepped in turn (a vector environment) spread over 4-KiB pages, and the TLB misses cost
/// a quarter of the speed (docs/MEASUREMENTS.md, "Python environments").
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

pub mod bench;
pub mod calibrate;
pub mod cli;
pub mod commands;
pub mod compose;
pub mod config;
pub mod control;
pub mod dashboard;
pub mod data;
#[cfg(feature = "gui")]
pub mod gui;
pub mod gym;
pub mod interop;
pub mod measure;
pub mod optimize;
pub mod playback;
pub mod plugin_host;
pub mod remote;
pub mod rng;
pub mod robot_io;
pub mod sensing;
pub mod signal;
pub mod sim;
pub mod suite;

/// The program's version (the workspace's, Cargo.toml): `proleg --version`, the Python
/// package's `__version__` and every run a store records ([`optimize::store::program_version`]).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
