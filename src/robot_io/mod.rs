//! Real robots (thesis 4.3.3, 5.3, listing A.4): the robot-control interface every
//! driver implements, the Dynamixel driver, an emulated Dynamixel bus for testing without
//! hardware, and the real-robot mode that runs the control kernel on a robot.
//!
//! - [`RobotControl`]: connect / disconnect, enable servos, send a command (to all or one
//!   servo), request information by type, the metadata of the robot; every failure is a
//!   [`RobotError`], never a panic.
//! - [`dynamixel`]: Dynamixel servos (Protocol 2.0) over a serial port with the
//!   `dynamixel2` crate: sync-write of goal positions, sync-read of present current,
//!   velocity and position.
//! - [`emulator`]: N emulated Dynamixel servos answering on a pseudo-terminal.
//! - [`real_mode`]: the control loop in real time (kernel -> servos, readings -> kernel
//!   and data file), servos disabled on exit or error.

pub mod dynamixel;
pub mod emulator;
pub mod real_mode;

/// Which servos a command goes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Every servo.
    All,
    /// One servo by bus id.
    Id(u8),
}

/// The kinds of information a robot can be asked for (one value per joint).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Info {
    /// Joint angles (degrees).
    Positions,
    /// Servo currents (A).
    Currents,
    /// Joint speeds (degrees/s).
    Speeds,
    /// Servo temperatures (°C).
    Temperatures,
    /// Hardware error flags (0: none).
    Errors,
    /// Torque on (1) or off (0).
    Torque,
}

impl Info {
    /// Every kind of information, in table order.
    pub const ALL: [Info; 6] = [
        Info::Positions,
        Info::Currents,
        Info::Speeds,
        Info::Temperatures,
        Info::Errors,
        Info::Torque,
    ];

    /// The name commands and the GUI use.
    pub fn name(self) -> &'static str {
        match self {
            Info::Positions => "positions",
            Info::Currents => "currents",
            Info::Speeds => "speeds",
            Info::Temperatures => "temperatures",
            Info::Errors => "errors",
            Info::Torque => "torque",
        }
    }

    /// The kind named `s` (as in `requestInformation("positions")`).
    pub fn parse(s: &str) -> Option<Info> {
        Info::ALL
            .into_iter()
            .find(|i| i.name().eq_ignore_ascii_case(s.trim()))
    }
}

/// What a robot is (A.4's metadata).
#[derive(Debug, Clone, PartialEq)]
pub struct RobotMeta {
    /// Joints (servos) of the robot.
    pub joints: usize,
    /// Sensor modules on the robot (tactile pads read by the driver).
    pub sensor_modules: usize,
    /// `PYPYP`-style letters, one per joint.
    pub topology: String,
    /// Bus id of each joint's servo.
    pub ids: Vec<u8>,
}

/// The readings of one read-back: one value per joint.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Readings {
    /// Joint angles (degrees).
    pub positions: Vec<f64>,
    /// Servo currents (A).
    pub currents: Vec<f64>,
    /// Joint speeds (degrees/s).
    pub speeds: Vec<f64>,
}

impl Readings {
    /// Readings of `joints` joints, all 0.
    pub fn new(joints: usize) -> Self {
        Readings {
            positions: vec![0.0; joints],
            currents: vec![0.0; joints],
            speeds: vec![0.0; joints],
        }
    }
}

/// Why a robot operation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RobotError {
    /// The port could not be opened.
    #[error("cannot open {port}: {cause}")]
    Port {
        /// The port.
        port: String,
        /// Why it failed.
        cause: String,
    },
    /// A servo did not answer in time.
    #[error("servo {id} did not answer (timeout)")]
    Timeout {
        /// The servo.
        id: u8,
    },
    /// An answer came from another servo than asked.
    #[error("asked servo {expected}, servo {got} answered")]
    WrongId {
        /// The id asked.
        expected: u8,
        /// The id that answered.
        got: u8,
    },
    /// A servo answered with an error status.
    #[error("servo {id} reports error {code} ({})", servo_error(*code))]
    Servo {
        /// The servo.
        id: u8,
        /// Its error code.
        code: u8,
    },
    /// The bus failed (I/O, a garbled answer).
    #[error("bus error: {0}")]
    Bus(String),
    /// No connection (connect first).
    #[error("not connected to the robot")]
    NotConnected,
    /// A command or value the driver does not know.
    #[error("{0}")]
    Command(String),
}

/// The Protocol 2.0 status error numbers.
pub fn servo_error(code: u8) -> &'static str {
    match code & 0x7f {
        1 => "result fail",
        2 => "instruction error",
        3 => "CRC error",
        4 => "data range error",
        5 => "data length error",
        6 => "data limit error",
        7 => "access error",
        _ => "unknown error",
    }
}

/// A robot the control kernel can drive (thesis listing A.4).
pub trait RobotControl: Send {
    /// Opens the connection and checks that every servo answers.
    fn connect(&mut self) -> Result<(), RobotError>;
    /// Closes the connection (torque is left as it is: call `enable_servos(false)` first).
    fn disconnect(&mut self);
    /// Whether the robot is connected.
    fn is_connected(&self) -> bool;
    /// Torque on or off for every servo.
    fn enable_servos(&mut self, on: bool) -> Result<(), RobotError>;
    /// One control step: the goal angle (degrees) of every joint, in joint order.
    fn set_joint_angles(&mut self, angles: &[f64]) -> Result<(), RobotError>;
    /// A driver command with values, to every servo or one (A.4 `sendCommand`); the
    /// driver documents its commands.
    fn send_command(
        &mut self,
        command: &str,
        values: &[f64],
        target: Target,
    ) -> Result<(), RobotError>;
    /// One kind of information, one value per joint into `out` (A.4 `requestInformation`).
    fn request(&mut self, info: Info, out: &mut [f64]) -> Result<(), RobotError>;
    /// Positions, currents and speeds in one go (the control loop's read-back).
    fn read(&mut self, readings: &mut Readings) -> Result<(), RobotError>;
    /// The robot's joints, sensor modules, topology and servo ids.
    fn meta(&self) -> &RobotMeta;
}
