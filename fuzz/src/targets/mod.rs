//! The fuzz targets, one module each: `run` takes the fuzzer's bytes and panics on a
//! finding. The binaries in `fuzz/fuzz_targets/` hand them to libFuzzer; the regression
//! test (`fuzz/tests/regressions.rs`) replays the inputs of fixed findings through them.

pub mod actuation_file;
pub mod dashboard_request;
pub mod data_file;
pub mod dynamixel_bus;
pub mod environment_file;
pub mod kinbody_file;
pub mod mjcf_robot;
pub mod obj_mesh;
pub mod optimizer_file;
pub mod policy_weights;
pub mod remote_file;
pub mod robot_file;
pub mod roundtrip;
pub mod sensor_file;
pub mod simulation_file;
pub mod store_file;
pub mod suite_file;
pub mod urdf_import;

/// A target: the fuzzer's bytes in, a panic on a finding.
pub type Target = fn(&[u8]);

/// Every target by name (a binary of the same name runs it).
pub const ALL: &[(&str, Target)] = &[
    ("actuation_file", actuation_file::run),
    ("dashboard_request", dashboard_request::run),
    ("data_file", data_file::run),
    ("dynamixel_bus", dynamixel_bus::run),
    ("environment_file", environment_file::run),
    ("kinbody_file", kinbody_file::run),
    ("mjcf_robot", mjcf_robot::run),
    ("obj_mesh", obj_mesh::run),
    ("optimizer_file", optimizer_file::run),
    ("policy_weights", policy_weights::run),
    ("remote_file", remote_file::run),
    ("robot_file", robot_file::run),
    ("roundtrip", roundtrip::run),
    ("sensor_file", sensor_file::run),
    ("simulation_file", simulation_file::run),
    ("store_file", store_file::run),
    ("suite_file", suite_file::run),
    ("urdf_import", urdf_import::run),
];
