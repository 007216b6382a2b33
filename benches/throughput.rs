//! `cargo bench --no-default-features`: the throughput figures of `proleg bench` on the
//! reference scenario (robot-steps per second, real-time factors, batching), and, when the
//! example plugins are built (`proleg plugin build`), the plugin sine against the built-in
//! sine (`proleg bench --module Plugin_sine`).

fn main() {
    let config =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/demo.simulation.xml");
    match proleg::bench::report(&config, 10.0, &[8, 31], "", None) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
    let (host, scan) = proleg::plugin_host::PluginHost::scan_default();
    for message in scan.messages() {
        eprintln!("warning: {message}");
    }
    let registry = host.registry();
    if registry.get("Plugin_sine").is_none() {
        println!(
            "(build the example plugins with `proleg plugin build` to compare a plugin module)"
        );
        return;
    }
    match proleg::bench::modules::report(
        &config,
        10.0,
        "PatternGenerator_sinusoidal",
        "Plugin_sine",
        &registry,
    ) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
