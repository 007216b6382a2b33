//! An optimizer file from raw bytes, named by the demo in an optimization mode: loaded
//! (algorithm, genes, registered parameters, robustness, courses, morphology), its search
//! space and start candidate prepared, and the demo run.

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    if let Some(text) = crate::text(data)
        && let Some(sim) =
            crate::load_and_run(crate::OPTIMIZE, "optimizer/experiment1.cmaes.xml", text)
    {
        // Prepared or refused; never a panic.
        let prepared = proleg::optimize::prepare::prepare(&sim, crate::registry());
        std::hint::black_box(prepared.is_ok());
    }
}
