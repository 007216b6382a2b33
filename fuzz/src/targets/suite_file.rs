//! A task suite file from raw bytes (tasks, terrain families, difficulties, seeds, goals):
//! parsed, and when accepted, its first task's first train or test course generated under
//! the demo snake (the terrain generator's parameters fuzzed through it) and run.

use proleg::config::suite::parse_suite_file;

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let Some(text) = crate::text(data) else {
        return;
    };
    let Ok(suite) = parse_suite_file("fuzz.suite.xml", text) else {
        return;
    };
    let Some(task) = suite.tasks.first() else {
        return;
    };
    let Some(&seed) = task.train.first().or(task.test.first()) else {
        return;
    };
    let Some(demo) = crate::demo() else {
        return;
    };
    let suite_path = std::path::Path::new("/fuzz/configs/suites/fuzz.suite.xml");
    if let Ok(course) = demo.on_course(task, seed, suite_path) {
        crate::run_briefly(&course);
    }
}
