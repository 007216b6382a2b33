//! Dependencies point one way (docs/DESIGN.md): each top-level module of the library may
//! use only the modules listed for it here. A `use crate::…` (or a path `crate::…` in code)
//! outside the list fails this test, naming the file and line.

use std::path::Path;

/// Module -> the modules it may use. Leaves first; each layer may use those above it. The
/// windows (`gui`) use no command line (`cli`, `commands`): the dispatcher `commands`
/// uses both.
const ALLOWED: &[(&str, &[&str])] = &[
    ("measure", &[]),
    ("rng", &[]),
    ("sensing", &[]),
    ("data", &[]),
    ("signal", &[]),
    ("config", &["rng"]),
    ("control", &["config", "measure", "rng", "sensing"]),
    ("plugin_host", &["config", "control", "rng"]),
    ("remote", &["config", "control"]),
    (
        "sim",
        &[
            "config", "control", "data", "measure", "rng", "sensing", "signal",
        ],
    ),
    ("playback", &["config", "signal", "sim"]),
    (
        "robot_io",
        &[
            "config", "control", "data", "measure", "rng", "sensing", "sim",
        ],
    ),
    (
        "optimize",
        &[
            "config", "control", "data", "measure", "playback", "rng", "signal", "sim",
        ],
    ),
    (
        "compose",
        &["config", "control", "measure", "optimize", "sim"],
    ),
    ("interop", &["config", "sim"]),
    (
        "gym",
        &[
            "config", "control", "measure", "optimize", "playback", "rng", "sensing", "sim",
        ],
    ),
    (
        "calibrate",
        &[
            "config", "control", "data", "measure", "optimize", "rng", "sim",
        ],
    ),
    (
        "suite",
        &["config", "control", "optimize", "rng", "signal", "sim"],
    ),
    (
        "bench",
        &[
            "config", "control", "data", "measure", "rng", "sim", "suite",
        ],
    ),
    (
        "dashboard",
        &[
            "config", "control", "data", "optimize", "playback", "signal",
        ],
    ),
    (
        "gui",
        &[
            "calibrate",
            "compose",
            "config",
            "control",
            "data",
            "measure",
            "optimize",
            "plugin_host",
            "remote",
            "robot_io",
            "rng",
            "sensing",
            "signal",
            "sim",
        ],
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
            "dashboard",
            "playback",
            "suite",
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

/// Each engine's types stay inside its own module (docs/architecture.md, "Two engines behind one interface"): rapier's under
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

/// The module path (`["optimize", "store", "pg"]`) of a source file under `src`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The source file of the longest prefix of `path` that is a file under `src`.
fn file_of(src: &Path, path: &[String]) -> Option<std::path::PathBuf> {
    (1..=path.len()).rev().find_map(|k| {
        let base = path[..k].iter().fold(src.to_path_buf(), |p, s| p.join(s));
        let file = base.with_extension("rs");
        let module = base.join("mod.rs");
        [file, module].into_iter().find(|f| f.is_file())
    })
}

/// The paths of a `use` tree (`a::{b, c::{d, e}}` -> `a::b`, `a::c::d`, `a::c::e`).
fn expand_use(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![tree.split(" as ").next().unwrap_or("").trim().to_string()];
    };
    let close = tree.rfind('}').filter(|c| *c > open).unwrap_or(tree.len());
    let (prefix, inner) = (&tree[..open], &tree[open + 1..close]);
    let (mut parts, mut depth, mut current) = (Vec::new(), 0, String::new());
    for c in inner.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if c == ',' && depth == 0 {
            parts.push(std::mem::take(&mut current));
        } else {
            current.push(c);
        }
    }
    parts.push(current);
    parts
        .iter()
        .filter(|p| !p.trim().is_empty())
        .flat_map(|p| expand_use(p))
        .map(|p| format!("{prefix}{p}"))
        .collect()
}

/// The modules `code` declares (`mod x;`, `pub mod x;`).
fn declared_modules(code: &str) -> Vec<String> {
    code.split(';')
        .filter_map(|st| {
            let (before, name) = st.trim().rsplit_once("mod ")?;
            let before = before.lines().last().unwrap_or("").trim();
            let name = name.trim();
            (before.is_empty() || before.starts_with("pub") || before.ends_with(']'))
                .then(|| name.to_string())
                .filter(|n| n.chars().all(|c| c.is_alphanumeric() || c == '_'))
        })
        .collect()
}

/// A file's code without its tests and comments.
fn code_of(file: &Path) -> String {
    let text = std::fs::read_to_string(file).unwrap();
    text.split("#[cfg(test)]")
        .next()
        .unwrap_or("")
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The `use` trees of `code`, expanded, each with whether it is a re-export (`pub use`,
/// `pub(crate) use`): only visibility words before `use`, only a path tree after it.
fn use_paths(code: &str) -> Vec<(bool, String)> {
    let mut paths = Vec::new();
    for statement in code.split(';') {
        if let Some(at) = statement.find("use ")
            && statement[..at]
                .trim()
                .chars()
                .all(|c| c.is_alphanumeric() || "()_ ".contains(c))
            && statement[at + 4..]
                .chars()
                .all(|c| c.is_alphanumeric() || "_:{},* \n\t".contains(c))
        {
            let public = statement[..at].contains("pub");
            paths.extend(
                expand_use(&statement[at + 4..])
                    .into_iter()
                    .map(|p| (public, p)),
            );
        }
    }
    paths
}

/// The full module path (from the crate root) of `path` written in the file of module
/// `me` that declares `children`, or `None` for a path outside the crate.
fn absolute(me: &[String], children: &[String], path: &str) -> Option<Vec<String>> {
    let segments: Vec<String> = path.split("::").map(|s| s.trim().to_string()).collect();
    match segments.first().map(String::as_str) {
        Some("crate") => Some(segments[1..].to_vec()),
        Some("super") => {
            let ups = segments.iter().take_while(|s| *s == "super").count();
            let mut base = me[..me.len().saturating_sub(ups)].to_vec();
            base.extend(segments[ups..].iter().cloned());
            Some(base)
        }
        Some("self") => Some(
            me.iter()
                .cloned()
                .chain(segments[1..].iter().cloned())
                .collect(),
        ),
        // A path from a child module this file declares (`use fit::GroupFit`).
        Some(child) if children.iter().any(|c| c == child) => {
            Some(me.iter().cloned().chain(segments.iter().cloned()).collect())
        }
        _ => None,
    }
}

/// What a file offers through `pub use`: the name it offers -> the full path it stands for.
type Reexports = std::collections::HashMap<String, Vec<String>>;

fn reexports_of(src: &Path, file: &Path) -> Reexports {
    let code = code_of(file);
    let me = module_of(src, file);
    let children = declared_modules(&code);
    use_paths(&code)
        .into_iter()
        .filter(|(public, _)| *public)
        .filter_map(|(_, p)| {
            let (path, alias) = match p.split_once(" as ") {
                Some((path, alias)) => (path.trim().to_string(), alias.trim().to_string()),
                None => (
                    p.clone(),
                    p.rsplit("::").next().unwrap_or("").trim().to_string(),
                ),
            };
            Some((alias, absolute(&me, &children, &path)?))
        })
        .collect()
}

/// The file that defines what `full` names: the file of its longest prefix, and through
/// that file's `pub use` on to the file the name is re-exported from (a facade is not
/// a dependency: what is imported through it is).
fn defining_file(
    src: &Path,
    reexports: &std::collections::HashMap<std::path::PathBuf, Reexports>,
    full: &[String],
) -> Option<std::path::PathBuf> {
    let mut full = full.to_vec();
    let mut file = file_of(src, &full)?;
    for _ in 0..8 {
        let module = module_of(src, &file);
        let Some(name) = full.get(module.len()) else {
            break;
        };
        let Some(target) = reexports.get(&file).and_then(|r| r.get(name)) else {
            break;
        };
        let next: Vec<String> = target
            .iter()
            .chain(&full[module.len() + 1..])
            .cloned()
            .collect();
        match file_of(src, &next) {
            Some(f) if f != file => {
                file = f;
                full = next;
            }
            _ => break,
        }
    }
    Some(file)
}

/// The files of `src` that `file` imports: its `use` trees (paths from `crate`, `super`,
/// `self` or a child module it declares) and `crate::`/`super::` paths in its code, tests
/// left out; each resolved to the file that defines the item. Its own `pub use`
/// re-exports are what it offers, not what it depends on.
fn imports_of(
    src: &Path,
    reexports: &std::collections::HashMap<std::path::PathBuf, Reexports>,
    file: &Path,
) -> Vec<std::path::PathBuf> {
    let code = code_of(file);
    let mut paths: Vec<String> = use_paths(&code)
        .into_iter()
        .filter(|(public, _)| !public)
        .map(|(_, p)| p.split(" as ").next().unwrap_or("").trim().to_string())
        .collect();
    for start in ["crate::", "super::"] {
        for (at, _) in code.match_indices(start) {
            if at > 0 && code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':')
            {
                continue;
            }
            // A path inside a `pub use` is a re-export, read above.
            let line_start = code[..at].rfind('\n').map_or(0, |i| i + 1);
            if code[line_start..at].trim_start().starts_with("pub") {
                continue;
            }
            let path: String = code[at..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            paths.push(path);
        }
    }
    let me = module_of(src, file);
    let children = declared_modules(&code);
    let mut out: Vec<std::path::PathBuf> = paths
        .iter()
        .filter_map(|p| absolute(&me, &children, p))
        .filter_map(|full| defining_file(src, reexports, &full))
        .filter(|f| f != file)
        .collect();
    out.sort();
    out.dedup();
    out
}

/// The strongly connected components (Tarjan) of more than `most` files in `graph`.
fn circles(graph: &[(std::path::PathBuf, Vec<usize>)], most: usize) -> Vec<Vec<usize>> {
    struct T<'a> {
        g: &'a [(std::path::PathBuf, Vec<usize>)],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        stack: Vec<usize>,
        on: Vec<bool>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T<'_>, v: usize) {
        t.index[v] = Some(t.next);
        t.low[v] = t.next;
        t.next += 1;
        t.stack.push(v);
        t.on[v] = true;
        for &w in &t.g[v].1 {
            match t.index[w] {
                None => {
                    visit(t, w);
                    t.low[v] = t.low[v].min(t.low[w]);
                }
                Some(i) if t.on[w] => t.low[v] = t.low[v].min(i),
                Some(_) => {}
            }
        }
        if Some(t.low[v]) == t.index[v] {
            let mut component = Vec::new();
            while let Some(w) = t.stack.pop() {
                t.on[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            t.out.push(component);
        }
    }
    let n = graph.len();
    let mut t = T {
        g: graph,
        index: vec![None; n],
        low: vec![0; n],
        stack: Vec::new(),
        on: vec![false; n],
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            visit(&mut t, v);
        }
    }
    t.out.into_iter().filter(|c| c.len() > most).collect()
}

/// The files of `src` as a graph of their imports.
fn import_graph(src: &Path) -> Vec<(std::path::PathBuf, Vec<usize>)> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let reexports = files
        .iter()
        .map(|f| (f.clone(), reexports_of(src, f)))
        .collect();
    files
        .iter()
        .map(|f| {
            let edges = imports_of(src, &reexports, f)
                .iter()
                .filter_map(|t| files.iter().position(|g| g == t))
                .collect();
            (f.clone(), edges)
        })
        .collect()
}

/// Nowhere in `src/` do files import each other in a circle of more than two (a pair that
/// shares types is tolerated): the files go one way, so a newcomer can read them leaves
/// first.
#[test]
fn no_import_circle_of_more_than_two_files_in_the_crate() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = import_graph(&src);
    assert!(
        graph.iter().filter(|(_, e)| !e.is_empty()).count() > graph.len() / 2,
        "most files import another: the reader is broken"
    );
    let found: Vec<String> = circles(&graph, 2)
        .iter()
        .map(|c| {
            let names: Vec<String> = c
                .iter()
                .map(|&i| graph[i].0.strip_prefix(&src).unwrap().display().to_string())
                .collect();
            names.join(" <-> ")
        })
        .collect();
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

/// The circle finder finds a circle of three injected into a graph, and not a pair.
#[test]
fn the_circle_finder_sees_an_injected_circle_of_three() {
    let node = |name: &str, to: &[usize]| (std::path::PathBuf::from(name), to.to_vec());
    let pair = [node("a", &[1]), node("b", &[0]), node("c", &[0])];
    assert!(circles(&pair, 2).is_empty(), "a pair is tolerated");
    let three = [
        node("a", &[1]),
        node("b", &[2]),
        node("c", &[0]),
        node("d", &[0]),
    ];
    let found = circles(&three, 2);
    assert_eq!(found.len(), 1);
    let mut members = found[0].clone();
    members.sort();
    assert_eq!(members, [0, 1, 2]);
}

/// An import through a folder's facade (`pub use read::parse_optimizer_file` in
/// `config/optimizer/mod.rs`) is read as an import of the file that defines the item.
#[test]
fn an_import_through_a_facade_is_an_import_of_the_defining_file() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = import_graph(&src);
    let edges_of = |name: &str| -> Vec<std::path::PathBuf> {
        let (_, edges) = graph
            .iter()
            .find(|(f, _)| f.ends_with(name))
            .unwrap_or_else(|| panic!("{name} is not in src/"));
        edges.iter().map(|&i| graph[i].0.clone()).collect()
    };
    let resolve = edges_of("config/resolve/mod.rs");
    assert!(
        resolve
            .iter()
            .any(|f| f.ends_with("config/optimizer/read.rs")),
        "config::optimizer::parse_optimizer_file resolved to {resolve:?}"
    );
}
