//! [`DynamixelChain`]: a chain of Dynamixel servos on one serial port, driven with the
//! `dynamixel2` crate. Joint ids, offsets and directions come from the robot file's
//! `<Servos>` ([`crate::config::resolve::ServoMap`]). Each control step is one sync-write
//! of the goal positions; a read-back is one sync-read of the present current, velocity
//! and position block. Nothing is allocated per step.
//!
//! Commands (`send_command`): `torque 0|1`, `led 0|1`, `goal DEG` (a joint angle),
//! `reboot`; to every servo or one id.

use std::path::{Path, PathBuf};

use dynamixel2::instructions::SyncWriteData;
use dynamixel2::{Bus, ReadError, TransferError, WriteError};

use crate::config::resolve::ServoMap;
use crate::robot_io::dynamixel::table;
use crate::robot_io::{Info, Readings, RobotControl, RobotError, RobotMeta, Target};

/// A Dynamixel chain on a serial port.
pub struct DynamixelChain {
    port: PathBuf,
    baud: u32,
    map: ServoMap,
    meta: RobotMeta,
    bus: Option<Bus<Vec<u8>, Vec<u8>>>,
}

impl std::fmt::Debug for DynamixelChain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DynamixelChain")
            .field("port", &self.port)
            .field("baud", &self.baud)
            .field("ids", &self.meta.ids)
            .field("connected", &self.bus.is_some())
            .finish()
    }
}

fn write_error(e: WriteError) -> RobotError {
    RobotError::Bus(format!("{e:?}"))
}

/// The robot error of a failed answer from servo `id`; `chain` is every id on the bus (an
/// answer from a later servo of a sync read means `id` said nothing).
fn read_error(e: ReadError, id: u8, chain: &[u8]) -> RobotError {
    match e {
        ReadError::Io(io)
            if matches!(
                io.kind(),
                std::io::ErrorKind::TimedOut | std::io::ErrorKind::WouldBlock
            ) =>
        {
            RobotError::Timeout { id }
        }
        ReadError::Io(io) => RobotError::Bus(io.to_string()),
        ReadError::MotorError(m) => RobotError::Servo {
            id,
            code: m.error_number(),
        },
        ReadError::InvalidMessage(dynamixel2::InvalidMessage::InvalidPacketId(p))
            if chain.contains(&p.actual) =>
        {
            RobotError::Timeout { id }
        }
        ReadError::InvalidMessage(dynamixel2::InvalidMessage::InvalidPacketId(p)) => {
            RobotError::WrongId {
                expected: id,
                got: p.actual,
            }
        }
        other => RobotError::Bus(format!("servo {id}: {other:?}")),
    }
}

fn transfer_error(e: TransferError, id: u8) -> RobotError {
    match e {
        TransferError::WriteError(w) => write_error(w),
        TransferError::ReadError(r) => read_error(r, id, &[]),
    }
}

impl DynamixelChain {
    /// A chain on `port` at `baud` (the robot file's baud when `None`).
    pub fn new(port: &Path, baud: Option<u32>, map: ServoMap, topology: &str) -> Self {
        let meta = RobotMeta {
            joints: map.joints.len(),
            sensor_modules: 0,
            topology: topology.to_string(),
            ids: map.joints.iter().map(|j| j.id).collect(),
        };
        DynamixelChain {
            port: port.to_path_buf(),
            baud: baud.unwrap_or(map.baud),
            map,
            meta,
            bus: None,
        }
    }

    fn bus(&mut self) -> Result<&mut Bus<Vec<u8>, Vec<u8>>, RobotError> {
        self.bus.as_mut().ok_or(RobotError::NotConnected)
    }

    fn targets(&self, target: Target) -> Result<Vec<u8>, RobotError> {
        match target {
            Target::All => Ok(self.meta.ids.clone()),
            Target::Id(id) if self.meta.ids.contains(&id) => Ok(vec![id]),
            Target::Id(id) => Err(RobotError::Command(format!(
                "servo {id} is not one of the robot's servos {:?}",
                self.meta.ids
            ))),
        }
    }

    fn write_u8_all(&mut self, ids: &[u8], address: u16, value: u8) -> Result<(), RobotError> {
        let bus = self.bus()?;
        bus.sync_write_u8(
            address,
            ids.iter().map(|id| SyncWriteData {
                motor_id: *id,
                data: value,
            }),
        )
        .map_err(write_error)
    }

    /// Reads one byte register of every servo into `out` (joint order).
    fn read_u8_all(&mut self, address: u16, out: &mut [f64]) -> Result<(), RobotError> {
        let ids = self.meta.ids.clone();
        let bus = self.bus()?;
        let mut failure = None;
        let mut k = 0;
        bus.sync_read_cb(&ids, address, 1, |r| {
            match r {
                Ok(resp) => {
                    if let (Some(o), Some(v)) = (out.get_mut(k), resp.data.first()) {
                        *o = f64::from(*v);
                    }
                }
                Err(e) if failure.is_none() => {
                    let id = ids.get(k).copied().unwrap_or(0);
                    failure = Some(read_error(e, id, &ids));
                }
                Err(_) => {}
            }
            k += 1;
        })
        .map_err(write_error)?;
        failure.map_or(Ok(()), Err)
    }
}

/// A failed read-back, telling the stuffing quirk apart.
enum Garbled {
    /// An answer one or more bytes too long (see [`DynamixelChain::read`]).
    Stuffing,
    Other(RobotError),
}

impl Garbled {
    fn into_error(self) -> RobotError {
        match self {
            Garbled::Stuffing => {
                RobotError::Bus("an answer with unremoved byte stuffing".to_string())
            }
            Garbled::Other(e) => e,
        }
    }
}

impl DynamixelChain {
    /// Reads registers `address .. address + len` of every servo, a part of the present
    /// current (126, 2 bytes) / velocity (128, 4) / position (132, 4) block, into
    /// `readings`.
    fn read_span(
        &mut self,
        readings: &mut Readings,
        address: u16,
        len: u16,
    ) -> Result<(), Garbled> {
        let map = &self.map.joints;
        let ids = &self.meta.ids;
        let bus = self
            .bus
            .as_mut()
            .ok_or(Garbled::Other(RobotError::NotConnected))?;
        let mut failure = None;
        let mut k = 0;
        bus.sync_read_cb(ids, address, len, |r| {
            match r {
                Ok(resp) if k < map.len() => {
                    let s = map[k];
                    let d = resp.data;
                    let at = |reg: u16, n: usize| {
                        let i = usize::from(reg.checked_sub(address)?);
                        d.get(i..i + n)
                    };
                    if let (Some(b), Some(c)) =
                        (at(table::PRESENT_CURRENT, 2), readings.currents.get_mut(k))
                    {
                        *c = f64::from(i16::from_le_bytes([b[0], b[1]])) * table::CURRENT_UNIT_A;
                    }
                    if let (Some(b), Some(v)) =
                        (at(table::PRESENT_VELOCITY, 4), readings.speeds.get_mut(k))
                    {
                        let raw = i32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                        *v = s.direction * f64::from(raw) * table::VELOCITY_UNIT_DEG_S;
                    }
                    if let (Some(b), Some(p)) = (
                        at(table::PRESENT_POSITION, 4),
                        readings.positions.get_mut(k),
                    ) {
                        let raw = i32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                        *p = s.joint_angle(table::position_deg(raw));
                    }
                }
                Ok(_) => {}
                Err(ReadError::InvalidMessage(
                    dynamixel2::InvalidMessage::InvalidParameterCount(c),
                )) if failure.is_none() && c.actual > usize::from(len) => {
                    failure = Some(Garbled::Stuffing);
                }
                Err(e) if failure.is_none() => {
                    let id = ids.get(k).copied().unwrap_or(0);
                    failure = Some(Garbled::Other(read_error(e, id, ids)));
                }
                Err(_) => {}
            }
            k += 1;
        })
        .map_err(|e| Garbled::Other(write_error(e)))?;
        failure.map_or(Ok(()), Err)
    }
}

impl RobotControl for DynamixelChain {
    fn connect(&mut self) -> Result<(), RobotError> {
        let bus = Bus::open(&self.port, self.baud).map_err(|e| RobotError::Port {
            port: self.port.display().to_string(),
            cause: e.to_string(),
        })?;
        self.bus = Some(bus);
        for id in self.meta.ids.clone() {
            let r = self.bus()?.ping(id).map_err(|e| transfer_error(e, id));
            if let Err(e) = r {
                self.bus = None;
                return Err(e);
            }
        }
        Ok(())
    }

    fn disconnect(&mut self) {
        self.bus = None;
    }

    fn is_connected(&self) -> bool {
        self.bus.is_some()
    }

    fn enable_servos(&mut self, on: bool) -> Result<(), RobotError> {
        let ids = self.meta.ids.clone();
        self.write_u8_all(&ids, table::TORQUE_ENABLE, u8::from(on))
    }

    fn set_joint_angles(&mut self, angles: &[f64]) -> Result<(), RobotError> {
        if angles.len() != self.map.joints.len() {
            return Err(RobotError::Command(format!(
                "{} angles for {} joints",
                angles.len(),
                self.map.joints.len()
            )));
        }
        let map = &self.map.joints;
        let bus = self.bus.as_mut().ok_or(RobotError::NotConnected)?;
        bus.sync_write_u32(
            table::GOAL_POSITION,
            map.iter().zip(angles).map(|(s, a)| SyncWriteData {
                motor_id: s.id,
                data: table::position_raw(s.servo_angle(*a)),
            }),
        )
        .map_err(write_error)
    }

    fn send_command(
        &mut self,
        command: &str,
        values: &[f64],
        target: Target,
    ) -> Result<(), RobotError> {
        let ids = self.targets(target)?;
        let value = |what: &str| {
            values
                .first()
                .copied()
                .filter(|v| v.is_finite())
                .ok_or_else(|| RobotError::Command(format!("{command}: give {what}")))
        };
        match command.trim().to_ascii_lowercase().as_str() {
            "torque" => {
                let v = value("0 or 1")?;
                self.write_u8_all(&ids, table::TORQUE_ENABLE, u8::from(v != 0.0))
            }
            "led" => {
                let v = value("0 or 1")?;
                self.write_u8_all(&ids, table::LED, u8::from(v != 0.0))
            }
            "goal" => {
                let deg = value("an angle in degrees")?;
                let servos: Vec<_> = self
                    .map
                    .joints
                    .iter()
                    .filter(|s| ids.contains(&s.id))
                    .copied()
                    .collect();
                let bus = self.bus()?;
                bus.sync_write_u32(
                    table::GOAL_POSITION,
                    servos.iter().map(|s| SyncWriteData {
                        motor_id: s.id,
                        data: table::position_raw(s.servo_angle(deg)),
                    }),
                )
                .map_err(write_error)
            }
            "reboot" => {
                for id in ids {
                    self.bus()?.reboot(id).map_err(|e| transfer_error(e, id))?;
                }
                Ok(())
            }
            other => Err(RobotError::Command(format!(
                "unknown command \"{other}\"; commands: torque, led, goal, reboot"
            ))),
        }
    }

    fn request(&mut self, info: Info, out: &mut [f64]) -> Result<(), RobotError> {
        match info {
            Info::Positions | Info::Currents | Info::Speeds => {
                let mut r = Readings::new(self.meta.joints);
                self.read(&mut r)?;
                let src = match info {
                    Info::Positions => &r.positions,
                    Info::Currents => &r.currents,
                    _ => &r.speeds,
                };
                for (o, v) in out.iter_mut().zip(src) {
                    *o = *v;
                }
                Ok(())
            }
            Info::Temperatures => self.read_u8_all(table::PRESENT_TEMPERATURE, out),
            Info::Errors => self.read_u8_all(table::HARDWARE_ERROR, out),
            Info::Torque => self.read_u8_all(table::TORQUE_ENABLE, out),
        }
    }

    fn read(&mut self, readings: &mut Readings) -> Result<(), RobotError> {
        match self.read_span(readings, table::PRESENT_CURRENT, table::PRESENT_BLOCK_LEN) {
            // dynamixel2 0.9.1 does not remove the stuffing byte of `FF FF FF FD` (a small
            // negative velocity followed by a position whose low byte is FD): the answer
            // arrives one byte long. Read the two halves apart then — the pattern cannot
            // form inside either.
            Err(Garbled::Stuffing) => {
                self.read_span(readings, table::PRESENT_CURRENT, 6)
                    .map_err(Garbled::into_error)?;
                self.read_span(readings, table::PRESENT_POSITION, 4)
                    .map_err(Garbled::into_error)
            }
            other => other.map_err(Garbled::into_error),
        }
    }

    fn meta(&self) -> &RobotMeta {
        &self.meta
    }
}
