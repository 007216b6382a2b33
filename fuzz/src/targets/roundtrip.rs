//! The structured round trip: any configuration file a reader accepts, written and read
//! again, is equal to what was read (`read(write(read(x))) == read(x)`), for each of the
//! formats with a writer; the first byte picks the format.

use crate::round_trip;
use proleg::config::{
    actuation, environment, kinbody, optimizer, remote, robot, sensor, simulation, suite,
};

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let Some((&format, rest)) = data.split_first() else {
        return;
    };
    let Some(text) = crate::text(rest) else {
        return;
    };
    match format % 9 {
        0 => round_trip(
            text,
            simulation::parse_simulation_file,
            simulation::write_simulation_file,
        ),
        1 => round_trip(text, robot::parse_robot_file, robot::write_robot_file),
        2 => round_trip(
            text,
            kinbody::parse_kinbody_file,
            kinbody::write_kinbody_file,
        ),
        3 => round_trip(text, sensor::parse_sensor_file, sensor::write_sensor_file),
        4 => round_trip(
            text,
            actuation::parse_actuation_file,
            actuation::write_actuation_file,
        ),
        5 => round_trip(
            text,
            environment::parse_environment_file,
            environment::write_environment_file,
        ),
        6 => round_trip(
            text,
            optimizer::parse_optimizer_file,
            optimizer::write_optimizer_file,
        ),
        7 => round_trip(text, remote::parse_remote_file, remote::write_remote_file),
        _ => round_trip(text, suite::parse_suite_file, suite::write_suite_file),
    }
}
