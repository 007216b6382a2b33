//! The fuzz targets' shared harness (docs/development.md, "Fuzzing"). A configuration set
//! lives in memory (the repository's demo snake and touch snake, their parts, sensors,
//! control, floor and optimizer, compiled in), and a target replaces one of its files by
//! the fuzzer's bytes; every configuration target then makes the same check: the input
//! either loads and runs as written, or is refused with an error. A panic, a hang (more
//! than a second: `-timeout=1`) or a run above 2 GiB (`-rss_limit_mb=2048`) is a finding.

pub mod targets;

use std::path::Path;
use std::sync::OnceLock;

use proleg::config::{MemSource, Simulation, load_simulation_with};
use proleg::control::ModuleRegistry;
use proleg::sim::{BuildOptions, Simulator};

/// Where the in-memory configuration set lies.
pub const ROOT: &str = "/fuzz/configs";

/// Physics steps a loaded input runs (a tenth of a second at the demo's step).
pub const STEPS: u64 = 100;

macro_rules! repo {
    ($path:literal) => {
        ($path, include_str!(concat!("../../configs/", $path)))
    };
}

/// The configuration set: path under [`ROOT`] and text.
pub const FILES: &[(&str, &str)] = &[
    repo!("demo.simulation.xml"),
    repo!("experiment2_adaptive.simulation.xml"),
    repo!("robots/snake5p.robot.xml"),
    repo!("robots/tactile5p.robot.xml"),
    repo!("parts/TailP.kinbody.xml"),
    repo!("parts/PP.kinbody.xml"),
    repo!("parts/HeadP.kinbody.xml"),
    repo!("parts/TailPTouch.kinbody.xml"),
    repo!("parts/PPTouch.kinbody.xml"),
    repo!("parts/HeadPTouch.kinbody.xml"),
    repo!("sensors/tactile.sensor.xml"),
    repo!("sensors/laser.sensor.xml"),
    repo!("actuation/snake5p_sine40.actuation.xml"),
    repo!("actuation/tactile5p_sine30_adaptive.actuation.xml"),
    repo!("environments/flat.env.xml"),
    repo!("optimizer/experiment1.cmaes.xml"),
];

/// The demo in an optimization mode: CMA-ES over its sine's amplitudes.
pub const OPTIMIZE: &str = "optimize.simulation.xml";

/// Experiment 2's touch snake and adaptive module on the flat floor.
pub const TOUCH: &str = "touch.simulation.xml";

/// The module types every target loads against (the standard library).
pub fn registry() -> &'static ModuleRegistry {
    static REGISTRY: OnceLock<ModuleRegistry> = OnceLock::new();
    REGISTRY.get_or_init(ModuleRegistry::standard)
}

/// The configuration set with `replaced` (a path under [`ROOT`]) holding `text`.
pub fn source_with(replaced: &str, text: &str) -> MemSource {
    let mut src = MemSource::new();
    for (path, body) in FILES {
        src.insert(format!("{ROOT}/{path}"), *body);
    }
    let demo = FILES[0].1;
    src.insert(
        format!("{ROOT}/{OPTIMIZE}"),
        demo.replace(
            "<mode>Single Run Simulation</mode>",
            "<mode>CMA-ES optimization</mode>",
        )
        .replace(
            "<simulationProperties>",
            "<optimizer>optimizer/experiment1.cmaes.xml</optimizer>\n  <simulationProperties>",
        ),
    );
    src.insert(
        format!("{ROOT}/{TOUCH}"),
        FILES[1].1.replace(
            "environments/irregular.env.xml",
            "environments/flat.env.xml",
        ),
    );
    src.insert(format!("{ROOT}/{replaced}"), text);
    src
}

/// Loads simulation `top` of the set with `replaced` holding `text`; what loads runs
/// [`STEPS`] steps. Returns the simulation when it loaded.
pub fn load_and_run(top: &str, replaced: &str, text: &str) -> Option<Simulation> {
    let src = source_with(replaced, text);
    let sim = load_simulation_with(&src, Path::new(&format!("{ROOT}/{top}")), registry()).ok()?;
    run_briefly(&sim);
    Some(sim)
}

/// The demo as the configuration set holds it (loaded once per process).
pub fn demo() -> Option<&'static Simulation> {
    static DEMO: OnceLock<Option<Simulation>> = OnceLock::new();
    DEMO.get_or_init(|| {
        let src = source_with("unused.xml", "");
        load_simulation_with(
            &src,
            Path::new(&format!("{ROOT}/demo.simulation.xml")),
            registry(),
        )
        .ok()
    })
    .as_ref()
}

/// Builds `sim`'s world and runs [`STEPS`] steps, unless the world is refused.
pub fn run_briefly(sim: &Simulation) {
    let opts = BuildOptions {
        record: false,
        ..BuildOptions::default()
    };
    if let Ok(mut world) = Simulator::with_registry(sim, &opts, registry()) {
        world.run_steps(STEPS);
    }
}

/// The fuzzer's bytes as text, when they are UTF-8 (a configuration file that is not is
/// refused by the reader before any parsing: nothing to fuzz there).
pub fn text(data: &[u8]) -> Option<&str> {
    std::str::from_utf8(data).ok()
}

/// Reads `text` with `parse`, and when it is accepted, checks that `write`'s writing of it
/// reads back equal (`read(write(read(x))) == read(x)`); panics, saying what differs, when
/// it does not or when the writing is refused.
pub fn round_trip<T, E>(
    text: &str,
    parse: impl Fn(&str, &str) -> Result<T, E>,
    write: impl Fn(&T) -> String,
) where
    T: PartialEq + std::fmt::Debug,
    E: std::fmt::Display,
{
    let Ok(first) = parse("fuzz.xml", text) else {
        return;
    };
    let written = write(&first);
    match parse("written.xml", &written) {
        Ok(again) => assert!(
            again == first,
            "read back differs, {}:\n{written}",
            first_difference(&first, &again)
        ),
        Err(e) => panic!("the writing of an accepted file is refused: {e}\n{written}"),
    }
}

/// The first line where two values' pretty `Debug` forms differ, to say what a round trip
/// changed; source positions (`line:` and `col:` of a `Pos`, which equality ignores) are
/// left out.
pub fn first_difference(a: &impl std::fmt::Debug, b: &impl std::fmt::Debug) -> String {
    let (a, b) = (format!("{a:#?}"), format!("{b:#?}"));
    let kept = |l: &&str| {
        let t = l.trim_start();
        !t.starts_with("line: ") && !t.starts_with("col: ")
    };
    let (a, b): (Vec<&str>, Vec<&str>) = (
        a.lines().filter(kept).collect(),
        b.lines().filter(kept).collect(),
    );
    match a.iter().zip(&b).position(|(x, y)| x != y) {
        Some(n) => format!(
            "read {:?}, read back {:?} after {:?}",
            a[n].trim(),
            b[n].trim(),
            a[n.saturating_sub(3)..n]
                .iter()
                .map(|l| l.trim())
                .collect::<Vec<_>>()
        ),
        None => format!("{} lines read, {} read back", a.len(), b.len()),
    }
}
