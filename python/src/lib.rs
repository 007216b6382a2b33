//! The `proleg._native` extension module: the library's simulations, environments and
//! stores behind pyo3. It converts arrays and errors and holds no logic of its own: every
//! rule lives in the `proleg` crate (`proleg::gym` for the environments), the Python part
//! of the package (`python/proleg/`) makes the Gymnasium classes of them.
//!
//! Work that steps worlds runs with the interpreter detached (`Python::detach`), so other
//! Python threads run meanwhile; every Rust error becomes a Python exception with the same
//! message (`errors`).

mod bench;
mod errors;
mod modules;
mod options;
mod policy;
mod render;
mod replay;
mod simulation;
mod store;
mod vector;

use pyo3::prelude::*;

/// Where the scenarios this module was built with live (the checkout's `configs/`).
const CONFIGS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../configs");

/// The native module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<simulation::Env>()?;
    m.add_class::<vector::VecEnv>()?;
    m.add_class::<policy::PolicyNet>()?;
    m.add_class::<render::Renderer>()?;
    m.add_class::<render::VideoWriter>()?;
    m.add_class::<replay::Replay>()?;
    m.add_function(wrap_pyfunction!(simulation::load, m)?)?;
    m.add_function(wrap_pyfunction!(store::read_store, m)?)?;
    m.add_function(wrap_pyfunction!(replay::write_html, m)?)?;
    m.add_function(wrap_pyfunction!(render::headless_vulkan_setting, m)?)?;
    m.add_function(wrap_pyfunction!(bench::pipeline_rate, m)?)?;
    m.add_function(wrap_pyfunction!(bench::export_mjcf_file, m)?)?;
    m.add("CONFIGS", CONFIGS)?;
    m.add("ENV_OPTIONS", options::documented())?;
    m.add("VERSION", proleg::VERSION)?;
    m.add(
        "MUJOCO_LIBRARY",
        proleg::sim::engine::mujoco::library::library_file_name(),
    )?;
    Ok(())
}
