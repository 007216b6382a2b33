//! An optimizer file from raw bytes, named by the demo in an optimization mode: loaded
//! (algorithm, genes, registered parameters, robustness, courses, morphology), its search
//! space and start candidate prepared, and the demo run.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Some(text) = proleg_fuzz::text(data)
        && let Some(sim) = proleg_fuzz::load_and_run(
            proleg_fuzz::OPTIMIZE,
            "optimizer/experiment1.cmaes.xml",
            text,
        )
    {
        // Prepared or refused; never a panic.
        let prepared = proleg::optimize::prepare::prepare(&sim, proleg_fuzz::registry());
        std::hint::black_box(prepared.is_ok());
    }
});
