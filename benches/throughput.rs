//! `cargo bench --no-default-features`: the throughput figures of `proleg bench` on the
//! reference scenario (robot-steps per second, real-time factors, batching).

fn main() {
    let config =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/demo.simulation.xml");
    match proleg::bench::report(&config, 10.0, &[8, 31]) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
