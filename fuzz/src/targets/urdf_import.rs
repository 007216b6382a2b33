//! URDF import from raw bytes with a mesh: the input is a URDF's text, a NUL, then a mesh
//! file's bytes, written as `mesh.obj`, `mesh.stl` and `mesh.dae` beside it (the URDF's
//! `<mesh filename="...">` picks the reader: OBJ, STL ASCII or binary, COLLADA), and
//! imported into a scratch folder. An import either is refused with an error naming the
//! file, or writes a robot and a simulation that load and run: an import that writes files
//! proleg then refuses is a finding, as is a panic. mesh-loader's readers panic on some
//! malformed files; the import catches that as the file's error, so panics located in
//! mesh-loader unwind to it here instead of aborting (libFuzzer's hook aborts on any).

use std::path::{Path, PathBuf};
use std::sync::{Once, OnceLock};

use proleg::config::{FsSource, load_simulation_with};
use proleg::interop::urdf::{ImportOptions, import_urdf_with};

/// The scratch folder of this process (`in/`: the URDF and its mesh, `out/`: the import).
fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        std::env::temp_dir().join(format!("proleg-fuzz-urdf-{}", std::process::id()))
    })
}

/// Lets a panic located in mesh-loader unwind to the import's catch; any other panic still
/// goes to the hook that was there (libFuzzer's: abort, a finding).
fn mesh_loader_panics_unwind() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let before = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !info
                .location()
                .is_some_and(|l| l.file().contains("/mesh-loader-"))
            {
                before(info);
            }
        }));
    });
}

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    mesh_loader_panics_unwind();
    let split = data.iter().position(|b| *b == 0).unwrap_or(data.len());
    let (urdf, mesh) = data.split_at(split);
    let mesh = mesh.get(1..).unwrap_or(&[]);
    let (input, out) = (scratch().join("in"), scratch().join("out"));
    if std::fs::create_dir_all(&input).is_err() {
        return;
    }
    if out.exists() && std::fs::remove_dir_all(&out).is_err() {
        return;
    }
    let file = input.join("robot.urdf");
    let written = std::fs::write(&file, urdf).is_ok()
        && ["obj", "stl", "dae"]
            .iter()
            .all(|ext| std::fs::write(input.join(format!("mesh.{ext}")), mesh).is_ok());
    if !written {
        return;
    }
    let Ok(import) = import_urdf_with(&file, &out, &ImportOptions::default()) else {
        return;
    };
    let Some(sim_file) = &import.simulation_file else {
        return;
    };
    match load_simulation_with(&FsSource, sim_file, crate::registry()) {
        Ok(sim) => crate::run_briefly(&sim),
        Err(e) => panic!("the import was accepted but what it wrote is refused: {e}"),
    }
}
