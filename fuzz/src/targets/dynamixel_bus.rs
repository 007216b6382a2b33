//! The Dynamixel driver over an emulated bus of three servos whose line drops, cuts short,
//! corrupts, repeats, splits or prefixes with noise the servos' answers (the fuzzer's
//! bytes, three per answer: `LineFault::from_bytes`): connect (a ping each), torque on,
//! goals, read-backs of positions, currents and speeds, temperatures and error flags, an
//! LED command and a reboot, until the first call that fails. Each call answers or fails
//! with a robot error: a panic, a hang (past libFuzzer's second) or a reading that is not
//! a number is a finding.

use proleg::config::resolve::ServoMap;
use proleg::robot_io::dynamixel::DynamixelChain;
use proleg::robot_io::emulator::EmulatedBus;
use proleg::robot_io::emulator::line::LineFault;
use proleg::robot_io::{Info, Readings, RobotControl, RobotError, Target};

/// The servos on the bus (ids 1, 2, 3).
const SERVOS: usize = 3;

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let Ok(bus) = EmulatedBus::start(&[1, 2, 3], 120.0) else {
        return;
    };
    bus.set_faults(LineFault::from_bytes(data));
    let mut chain = DynamixelChain::new(
        bus.path(),
        Some(1_000_000),
        ServoMap::default_for(SERVOS),
        "PPP",
    );
    std::hint::black_box(drive(&mut chain).is_ok());
    chain.disconnect();
}

/// The calls a run on the real robot makes, in its order; the first failure ends them.
fn drive(chain: &mut DynamixelChain) -> Result<(), RobotError> {
    chain.connect()?;
    chain.enable_servos(true)?;
    let mut readings = Readings::new(SERVOS);
    let mut out = [0.0; SERVOS];
    for step in 0..2_u8 {
        chain.set_joint_angles(&[f64::from(step) * 20.0, -15.0, 5.0])?;
        chain.read(&mut readings)?;
        for values in [&readings.positions, &readings.currents, &readings.speeds] {
            assert!(values.iter().all(|v| v.is_finite()), "{readings:?}");
        }
        for info in [Info::Temperatures, Info::Errors, Info::Torque] {
            chain.request(info, &mut out)?;
            assert!(out.iter().all(|v| v.is_finite()), "{info:?}: {out:?}");
        }
    }
    chain.send_command("led", &[1.0], Target::All)?;
    chain.send_command("reboot", &[], Target::Id(2))
}
