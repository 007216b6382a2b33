//! A task suite file from raw bytes (tasks, terrain families, difficulties, seeds, goals):
//! parsed, and when accepted, its first task's first train or test course generated under
//! the demo snake (the terrain generator's parameters fuzzed through it) and run.
#![no_main]

use libfuzzer_sys::fuzz_target;
use proleg::config::suite::parse_suite_file;

fuzz_target!(|data: &[u8]| {
    let Some(text) = proleg_fuzz::text(data) else {
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
    let Some(demo) = proleg_fuzz::demo() else {
        return;
    };
    let suite_path = std::path::Path::new("/fuzz/configs/suites/fuzz.suite.xml");
    if let Ok(course) = demo.on_course(task, seed, suite_path) {
        proleg_fuzz::run_briefly(&course);
    }
});
