//! Dependencies point one way (docs/DESIGN.md §1): each top-level module of the library may
//! use only the modules listed for it here. A `use crate::…` (or a path `crate::…` in code)
//! outside the list fails this test, naming the file and line.

use std::path::Path;

/// Module -> the modules it may use. Leaves first; each layer may use those above it.
const ALLOWED: &[(&str, &[&str])] = &[
    ("measure", &[]),
    ("rng", &[]),
    ("sensing", &[]),
    ("data", &[]),
    ("signal", &[]),
    ("config", &[]),
    ("control", &["config", "measure", "rng", "sensing"]),
    ("plugin_host", &["config", "control", "rng"]),
    ("remote", &["config", "control"]),
    (
        "sim",
        &["config", "control", "data", "measure", "rng", "sensing"],
    ),
    (
        "robot_io",
        &[
            "config", "control", "data", "measure", "rng", "sensing", "sim",
        ],
    ),
    ("optimize", &["config", "control", "measure", "rng", "sim"]),
    (
        "compose",
        &["config", "control", "measure", "optimize", "sim"],
    ),
    ("interop", &["config", "sim"]),
    (
        "gym",
        &[
            "config", "control", "measure", "optimize", "rng", "sensing", "sim",
        ],
    ),
    (
        "calibrate",
        &[
            "config", "control", "data", "measure", "optimize", "rng", "sim",
        ],
    ),
    (
        "bench",
        &["config", "control", "data", "measure", "rng", "sim"],
    ),
    (
        "cli",
        &[
            "config",
            "control",
            "data",
            "measure",
            "optimize",
            "plugin_host",
            "robot_io",
            "rng",
            "signal",
            "sim",
            "bench",
            "interop",
            "calibrate",
            "gym",
        ],
    ),
];

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn dependencies_point_one_way() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut wrong = Vec::new();
    for (module, allowed) in ALLOWED {
        let mut files = Vec::new();
        let dir = src.join(module);
        if dir.is_dir() {
            rust_files(&dir, &mut files);
        } else {
            files.push(src.join(format!("{module}.rs")));
        }
        assert!(!files.is_empty(), "no source for module {module}");
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for (n, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or("");
                for (at, _) in code.match_indices("crate::") {
                    let used: String = code[at + 7..]
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    if used != *module && !allowed.contains(&used.as_str()) {
                        wrong.push(format!("{}:{}: {module} uses {used}", f.display(), n + 1));
                    }
                }
            }
        }
    }
    assert!(wrong.is_empty(), "layering broken:\n{}", wrong.join("\n"));
}

/// Each engine's types stay inside its own module (docs/DESIGN.md §4): rapier's under
/// `src/sim/engine/rapier/`, MuJoCo's (its bindings, `mjModel`, `mjData`) under
/// `src/sim/engine/mujoco/`. Everything else reaches physics through `PhysicsEngine` and
/// the neutral doors of `sim::engine` (`EngineSettings`, `ready`, `mjcf_export`): no
/// path into an engine's module and none of its types or constants outside
/// `src/sim/engine/`, but for `SimError` wrapping MuJoCo's error.
#[test]
fn engine_types_stay_in_their_engine_module() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let engines: [(&str, &[&str]); 2] = [
        (
            "sim/engine/rapier/",
            &[
                "rapier3d",
                "rp::",
                "engine::rapier",
                "PhysicsSettings",
                "MOTOR_DAMPING",
            ],
        ),
        (
            "sim/engine/mujoco/",
            &[
                "mjModel",
                "mjData",
                "mujoco::ffi",
                "mjContact",
                "engine::mujoco",
                "MujocoSettings",
            ],
        ),
    ];
    // The sim layer's error carries the engine's own (MuJoCo's library, its refusals).
    let allowed = |rel: &str, code: &str| {
        rel == "sim/error.rs" && code.contains("engine::mujoco::MujocoError")
    };
    let mut wrong = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let text = std::fs::read_to_string(f).unwrap();
        for (home, words) in engines {
            // The engines' parent chooses between them.
            if rel.starts_with(home) || rel == "sim/engine/mod.rs" {
                continue;
            }
            for (n, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or("");
                if let Some(w) = words.iter().find(|w| code.contains(*w))
                    && !allowed(&rel, code)
                {
                    wrong.push(format!("src/{rel}:{}: {w} outside {home}", n + 1));
                }
            }
        }
    }
    assert!(files.len() > 50, "found only {} source files", files.len());
    assert!(
        wrong.is_empty(),
        "engine types leaked:\n{}",
        wrong.join("\n")
    );
}
