//! User actuation-module plugins end to end: the example plugins are built with
//! `proleg plugin build`, loaded, and drive robots; the plugin sine equals the built-in
//! sine step for step; a panicking plugin is disabled with its message while the run goes
//! on; libraries with a wrong ABI version or without proleg's symbols are skipped with a
//! clear message; `proleg plugin new` makes a crate that builds and loads.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use proleg::control::{ModuleRegistry, load_simulation_in};
use proleg::optimize::store::{ExperimentStore, SqliteStore};
use proleg::plugin_host::{self, PluginHost};
use proleg::sim::{BuildOptions, Simulator};

/// Runs `proleg` in the repository root with `PROLEG_PLUGINS` set to `plugins`.
fn proleg_with(plugins: &str, args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(args)
        .current_dir(common::root())
        .env(plugin_host::ENV_VAR, plugins)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The example plugins, built once per test binary into a fresh library folder with
/// `proleg plugin build`.
fn example_library() -> &'static Path {
    static LIB: OnceLock<PathBuf> = OnceLock::new();
    LIB.get_or_init(|| {
        let lib = common::scratch("plugin-examples");
        let (ok, out, err) = proleg_with("", &["plugin", "build", "--lib", lib.to_str().unwrap()]);
        assert!(ok, "plugin build failed:\n{out}\n{err}");
        for module in ["Square_wave", "Rectilinear", "Plugin_sine"] {
            assert!(out.contains(&format!("module {module}")), "{out}");
        }
        lib
    })
}

/// A host that loaded the example plugins, and its registry.
fn example_host() -> (PluginHost, ModuleRegistry) {
    let mut host = PluginHost::default();
    let report = host.scan(&[example_library().to_path_buf()]);
    assert!(report.skipped.is_empty(), "{:?}", report.messages());
    let registry = host.registry();
    (host, registry)
}

/// The broken test plugins (tests/plugins), built with cargo.
fn broken_library() -> PathBuf {
    let root = common::root();
    let target = root.join("target/plugin-tests");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args(["build", "--release", "--manifest-path"])
        .arg(root.join("tests/plugins/Cargo.toml"))
        .arg("--target-dir")
        .arg(&target)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lib = common::scratch("plugin-broken");
    for name in ["panicking", "wrong_abi", "no_symbol"] {
        let file = format!(
            "{}test_{name}{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        );
        std::fs::copy(target.join("release").join(&file), lib.join(&file)).unwrap();
    }
    std::fs::write(
        lib.join(format!("garbage.{}", std::env::consts::DLL_EXTENSION)),
        b"no",
    )
    .unwrap();
    lib
}

fn simulator(config: &Path, robots: usize, registry: &ModuleRegistry) -> Simulator {
    // The host's plugins make their modules: the registry is passed.
    let sim = load_simulation_in(config, registry).unwrap_or_else(|e| panic!("{e}"));
    Simulator::with_registry(
        &sim,
        &BuildOptions {
            robots,
            seed: 1,
            record: false,
            ..Default::default()
        },
        registry,
    )
    .unwrap()
}

#[test]
fn the_plugin_sine_drives_the_demo_exactly_like_the_built_in_sine() {
    let (_host, registry) = example_host();
    let root = common::root();
    let mut builtin = simulator(&root.join("configs/demo.simulation.xml"), 1, &registry);
    let mut plugin = simulator(
        &root.join("plugins/configs/snake5p_plugin_sine.simulation.xml"),
        1,
        &registry,
    );
    assert_eq!(
        plugin.kernel(0).unwrap().actuators()[0]
            .module
            .descriptor()
            .type_name,
        "Plugin_sine"
    );
    let start = plugin.com(0).unwrap();
    for _ in 0..4 {
        builtin.run_for(1.0);
        plugin.run_for(1.0);
        assert_eq!(builtin.com(0).unwrap(), plugin.com(0).unwrap());
    }
    let moved = plugin.com(0).unwrap()[1] - start[1];
    assert!(moved > 0.2, "the snake moved {moved} m");
    // Parameters are checked and changed like a standard module's.
    let k = plugin.kernel_mut(0).unwrap();
    assert!(matches!(
        k.set_parameter(0, "Amplitude", None, 120.0),
        Err(proleg::control::kernel::KernelError::Param {
            error: proleg::control::module::ParamError::OutOfRange { value: 120.0, .. },
            ..
        })
    ));
    k.set_parameter(0, "Amplitude", None, 20.0).unwrap();
    let a = &k.actuators()[0];
    assert_eq!(a.module.parameters().row(0), &[20.0; 5]);
    // The logged series come back from the library.
    let angle = a.module.internal_data().series(0).to_vec();
    assert_eq!(angle, a.output());
    assert!(plugin.kernel(0).unwrap().failures().next().is_none());
}

#[test]
fn the_rectilinear_plugin_crawls_the_long_snake_forward() {
    let (_host, registry) = example_host();
    let config = common::root().join("plugins/configs/snake16py_rectilinear.simulation.xml");
    let mut sim = simulator(&config, 1, &registry);
    let start = sim.com(0).unwrap();
    sim.run_for(10.0);
    let end = sim.com(0).unwrap();
    let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
    assert!(dy > 0.15, "forward {dy} m");
    assert!(dx.abs() < 0.05, "sideways {dx} m");
    // Only the pitch joints move: the yaw joints hold 0.
    let desired = sim.kernel(0).unwrap().desired().to_vec();
    assert!(
        desired.iter().skip(1).step_by(2).all(|a| *a == 0.0),
        "{desired:?}"
    );
}

#[test]
fn the_cli_builds_lists_and_runs_the_example_plugins() {
    let lib = example_library();
    let lib = lib.to_str().unwrap();
    let (ok, out, err) = proleg_with(lib, &["plugin", "list"]);
    assert!(ok, "{err}");
    for needle in [
        "Square_wave",
        "Sharpness=4 [0.1..50]",
        "Rectilinear",
        "Plugin_sine",
        "series: Angle, Phase",
    ] {
        assert!(out.contains(needle), "{needle} missing in\n{out}");
    }
    let config = "plugins/configs/snake5p_square_wave.simulation.xml";
    let (ok, out, err) = proleg_with(lib, &["run", config, "--duration", "4"]);
    assert!(ok, "{err}");
    let moved: f64 = out
        .lines()
        .find_map(|l| l.strip_prefix("displacement"))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap();
    assert!(moved > 0.1, "{out}");
    // The plugin's series are recorded like a standard module's.
    let data = common::scratch("plugin-data").join("square.data.xml");
    let data = data.to_str().unwrap();
    let (ok, _, err) = proleg_with(lib, &["run", config, "--duration", "1", "--data", data]);
    assert!(ok, "{err}");
    let (ok, out, err) = proleg_with(lib, &["data", "info", data]);
    assert!(ok, "{err}");
    assert!(
        out.contains("handler   Square_wave") && out.contains("  Angle [5]\n  Phase [5]"),
        "{out}"
    );
    // Without the library the module is unknown, with the file and line named.
    let (ok, _, err) = proleg_with("", &["check", config]);
    assert!(!ok);
    assert!(
        err.contains("snake5p_square_wave.actuation.xml:5") && err.contains("\"Square_wave\""),
        "{err}"
    );
}

#[test]
fn a_panicking_plugin_is_disabled_and_bad_libraries_are_skipped() {
    let lib = broken_library();
    let mut host = PluginHost::default();
    let report = host.scan(std::slice::from_ref(&lib));
    let loaded: Vec<&str> = report
        .loaded
        .iter()
        .map(|p| p.descriptor.type_name)
        .collect();
    assert_eq!(loaded, ["Panicky"]);
    let messages = report.messages().join("\n");
    for needle in [
        "libtest_wrong_abi.so: built for plugin ABI version 999, this proleg loads version 1",
        "libtest_no_symbol.so: missing symbol proleg_plugin_abi_version",
        "garbage.so: not a loadable library",
    ] {
        assert!(messages.contains(needle), "{needle} missing in\n{messages}");
    }

    // A run with the panicking module: it fails at 0.5 s, the run goes on, it outputs 0.
    let dir = common::scratch("plugin-panicky-run");
    std::fs::write(
        dir.join("panicky.actuation.xml"),
        r#"<actuation>
  <actuationModule name="Panicky">
    <jointConfiguration joints="11111"/>
    <parameter name="Panic_Time" value="0.5"/>
  </actuationModule>
</actuation>"#,
    )
    .unwrap();
    let demo = std::fs::read_to_string(common::root().join("configs/demo.simulation.xml"))
        .unwrap()
        .replace("robots/", "../../../configs/robots/")
        .replace("environments/", "../../../configs/environments/")
        .replace(
            "actuation/snake5p_sine40.actuation.xml",
            "panicky.actuation.xml",
        );
    let config = dir.join("panicky.simulation.xml");
    std::fs::write(&config, demo).unwrap();
    let mut sim = simulator(&config, 1, &host.registry());
    sim.run_for(0.4);
    assert!(sim.kernel(0).unwrap().failures().next().is_none());
    assert!(
        sim.kernel(0)
            .unwrap()
            .desired()
            .iter()
            .any(|a| a.abs() > 1.0)
    );
    sim.run_for(1.6);
    assert!((sim.clock().time() - 2.0).abs() < 1e-6);
    let kernel = sim.kernel(0).unwrap();
    let failures: Vec<(&str, &str)> = kernel.failures().collect();
    assert_eq!(failures.len(), 1);
    assert_eq!(failures[0].0, "Panicky");
    assert!(
        failures[0].1.contains(
            "panicked in compute: deliberate failure at t = 0.500 s; the module is disabled"
        ),
        "{}",
        failures[0].1
    );
    assert!(kernel.desired().iter().all(|a| *a == 0.0));

    // The command line reports it too, fails (the figures are not the file's control),
    // and warns about the skipped libraries.
    let (ok, _, err) = proleg_with(
        lib.to_str().unwrap(),
        &["run", config.to_str().unwrap(), "--duration", "1"],
    );
    assert!(!ok, "{err}");
    assert!(
        err.contains("module failed   Panicky")
            && err.contains("module Panicky failed during the run: plugin module Panicky")
            && err.contains("panicked in compute"),
        "{err}"
    );
    assert!(
        err.contains("warning: plugin") && err.contains("ABI version 999"),
        "{err}"
    );

    failed_modules_are_rejected_in_an_optimization(&lib, &dir, &config);
}

/// An optimization of the panicking module's `Panic_Time` (1-s episodes): a candidate whose
/// module fails within its episode is stored as rejected with the reason, at -inf, never
/// scored as if the module were not there.
fn failed_modules_are_rejected_in_an_optimization(lib: &Path, dir: &Path, config: &Path) {
    std::fs::write(
        dir.join("panicky.cmaes.xml"),
        r#"<cmaEvolutionStrategy>
  <properties>
    <popsize>6</popsize>
    <sigma>0.25</sigma>
    <maxEvaluations>12</maxEvaluations>
    <numOfParametersToOptimize>1</numOfParametersToOptimize>
    <registeredParameters>
      <parameter number="0" controlAlgorithm="Panicky" parameter="Panic_Time"/>
    </registeredParameters>
  </properties>
  <genomeConfig number="0" allJoints="1" genomeType="1" valueType="1" valueSpace="1" activeJoints="11111">
    <upperBounds>1.5</upperBounds>
    <lowerBounds>0.1</lowerBounds>
    <boundsIncrements>0.05</boundsIncrements>
    <lowerBoundTypes>1</lowerBoundTypes>
    <upperBoundTypes>1</upperBoundTypes>
    <uniform>1</uniform>
  </genomeConfig>
</cmaEvolutionStrategy>"#,
    )
    .unwrap();
    let text = std::fs::read_to_string(config)
        .unwrap()
        .replace(
            "<mode>Single Run Simulation</mode>",
            "<mode>CMA-ES optimization</mode>",
        )
        .replace(
            "<simulationProperties>",
            "<optimizer>panicky.cmaes.xml</optimizer>\n  <simulationProperties>",
        )
        .replace("<duration>30</duration>", "<duration>1</duration>");
    let optimized = dir.join("panicky_opt.simulation.xml");
    std::fs::write(&optimized, text).unwrap();
    let store = dir.join("panicky.sqlite");
    let (ok, _, err) = proleg_with(
        lib.to_str().unwrap(),
        &[
            "optimize",
            optimized.to_str().unwrap(),
            "--store",
            store.to_str().unwrap(),
            "--quiet",
        ],
    );
    assert!(ok, "{err}");
    let evaluations = SqliteStore::open(&store).unwrap().evaluations(1).unwrap();
    assert_eq!(evaluations.len(), 12);
    let mut failed = 0;
    for e in &evaluations {
        if e.values[0] < 1.0 {
            failed += 1;
            assert_eq!(e.score, f64::NEG_INFINITY, "{e:?}");
            let why = e.rejected.as_deref().unwrap_or("");
            assert!(
                why.contains("module Panicky failed during the episode: plugin module Panicky")
                    && why.contains("panicked in compute"),
                "{why}"
            );
        } else {
            assert!(e.score.is_finite() && e.rejected.is_none(), "{e:?}");
        }
    }
    assert!(failed > 0, "{evaluations:?}");
}

#[test]
fn plugin_new_makes_a_crate_that_builds_and_loads() {
    let ws = common::scratch("plugin-new-workspace");
    let root = common::root();
    common::plugin_workspace(&ws);
    let w = ws.to_str().unwrap();
    let (ok, out, err) = proleg_with(
        "",
        &[
            "plugin",
            "new",
            "TestGait",
            "--param",
            "amplitude=30",
            "--param",
            "period=1.0:0.1..10",
            "--data",
            "phase",
            "--helper",
            "smooth",
            "--workspace",
            w,
        ],
    );
    assert!(ok, "{err}");
    assert!(out.contains("test_gait"), "{out}");
    // A second one of the same name is refused.
    let (ok, _, err) = proleg_with("", &["plugin", "new", "TestGait", "--workspace", w]);
    assert!(!ok && err.contains("exists already"), "{err}");
    let lib = ws.join("lib");
    let (ok, out, err) = proleg_with(
        "",
        &[
            "plugin",
            "build",
            "test_gait",
            "--workspace",
            w,
            "--lib",
            lib.to_str().unwrap(),
            "--target-dir",
            root.join("target/plugin-tests-new").to_str().unwrap(),
        ],
    );
    assert!(ok, "{out}\n{err}");
    assert!(out.contains("module TestGait"), "{out}");
    let (ok, out, _) = proleg_with(lib.to_str().unwrap(), &["plugin", "list"]);
    assert!(ok);
    assert!(
        out.contains("TestGait")
            && out.contains("amplitude=30 [-300..300]")
            && out.contains("period=1 [0.1..10]")
            && out.contains("series: phase"),
        "{out}"
    );
}

#[test]
fn two_hosts_side_by_side_know_only_their_own_plugins() {
    // The loaded plugins were a process-wide list: every registry made anywhere offered
    // every module any part of the process had loaded.
    let (examples, with_examples) = example_host();
    let empty = PluginHost::default();
    assert!(with_examples.get("Square_wave").is_some());
    assert!(empty.registry().get("Square_wave").is_none());
    assert_eq!(
        empty.registry().names(),
        ModuleRegistry::standard().names(),
        "a host with nothing loaded offers the standard library"
    );
    let names: Vec<&str> = examples
        .loaded()
        .iter()
        .map(|p| p.descriptor.type_name)
        .collect();
    assert!(names.contains(&"Rectilinear"), "{names:?}");
    // A second host loads the same libraries on its own, and dropping it leaves the
    // first host's modules working.
    let (second, _) = example_host();
    drop(second);
    let config = common::root().join("plugins/configs/snake5p_plugin_sine.simulation.xml");
    let mut sim = simulator(&config, 1, &examples.registry());
    sim.run_for(0.5);
    assert!(sim.kernel(0).unwrap().failures().next().is_none());
}
