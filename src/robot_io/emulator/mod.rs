//! An emulated Dynamixel bus on a pseudo-terminal, for using and testing the real-robot
//! mode without hardware (`proleg robot-emulator`, the integration tests). A thread
//! answers Protocol 2.0 on the pty's master side for N servos ([`servo`]): ping, read,
//! write, sync read, sync write, reboot; servos move toward their goal at a set speed
//! while torque is on. A servo can be made silent to test timeouts.
//!
//! The driver opens the pty's slave side ([`EmulatedBus::path`]) like a USB adapter;
//! [`packet`] finds and builds Protocol 2.0 packets from the servo's side; [`line`] is what
//! a faulty line does to the answers on their way (dropped, cut, corrupted, repeated,
//! split, after noise), set with [`EmulatedBus::set_faults`].
//!
//! A host's writes that get no answer (sync writes, the torque-off at the end) reach the
//! emulator's thread some time after the host's `write` returned: [`EmulatedBus::servos`]
//! and [`EmulatedBus::stats`] therefore first *settle* the bus, sending a marker packet
//! (a ping to an id no servo has) behind everything written so far and waiting until the
//! thread has handled it, so a snapshot taken after a run shows all of the run.

pub mod line;
pub mod packet;
pub mod servo;

use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use nix::fcntl::OFlag;
use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
use nix::pty::{PtyMaster, grantpt, posix_openpt, ptsname_r, unlockpt};
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};

use crate::robot_io::emulator::line::LineFault;
use crate::robot_io::emulator::packet::{Instruction, Parsed, parse, status};
use crate::robot_io::emulator::servo::EmulatedServo;

const PING: u8 = 0x01;
const READ: u8 = 0x02;
const WRITE: u8 = 0x03;
const REBOOT: u8 = 0x08;
const SYNC_READ: u8 = 0x82;
const SYNC_WRITE: u8 = 0x83;
const BROADCAST: u8 = 0xFE;
/// Status error numbers.
const INSTRUCTION_ERROR: u8 = 2;
const DATA_LENGTH_ERROR: u8 = 5;
const ACCESS_ERROR: u8 = 7;

/// Counts of what the bus was asked.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BusStats {
    /// Packets received.
    pub packets: u64,
    /// Sync writes received.
    pub sync_writes: u64,
    /// Sync reads received.
    pub sync_reads: u64,
    /// Packets with a bad header or checksum.
    pub bad_packets: u64,
}

#[derive(Debug, Default)]
struct Shared {
    servos: Vec<EmulatedServo>,
    stats: BusStats,
    /// Corrupt (bad checksum) the first answer once the bus has seen this many packets.
    garble_after: Option<u64>,
    /// What the line does to the next answers, in turn (then they pass).
    faults: std::collections::VecDeque<LineFault>,
    /// Settle markers handled (not counted as packets).
    markers: u64,
}

/// The longest a settle waits for the emulator's thread before giving up (a guard against
/// a hang; the thread handles a marker within milliseconds).
const SETTLE_LIMIT: Duration = Duration::from_secs(10);

/// A running emulated bus; stops when dropped.
pub struct EmulatedBus {
    path: PathBuf,
    shared: Arc<Mutex<Shared>>,
    /// Signalled when the thread has handled a settle marker.
    handled: Arc<Condvar>,
    /// The emulator's own handle on the slave side, through which settle markers go, and
    /// the id they ping (none when every id is a servo's).
    marker: Option<(std::fs::File, u8)>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for EmulatedBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EmulatedBus")
            .field("path", &self.path)
            .finish()
    }
}

/// Why the emulated bus could not start.
#[derive(Debug, thiserror::Error)]
pub enum EmulatorError {
    /// A pseudo-terminal call failed.
    #[error("pseudo-terminal: {what}: {source}")]
    Pty {
        /// The call.
        what: &'static str,
        /// The system's error.
        source: nix::Error,
    },
    /// The pseudo-terminal's device could not be opened.
    #[error("{}: {source}", path.display())]
    Open {
        /// Its path.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The emulator's thread could not start.
    #[error("emulator thread: {0}")]
    Thread(std::io::Error),
}

impl EmulatedBus {
    /// Servos with these ids, moving at `speed_deg_s`, on a new pseudo-terminal.
    pub fn start(ids: &[u8], speed_deg_s: f64) -> Result<EmulatedBus, EmulatorError> {
        EmulatedBus::start_with(ids, servo::ServoDynamics::constant_speed(speed_deg_s))
    }

    /// Starts a bus of servos with these ids that move as `dynamics` say.
    pub fn start_with(
        ids: &[u8],
        dynamics: servo::ServoDynamics,
    ) -> Result<EmulatedBus, EmulatorError> {
        let err = |what: &'static str, e: nix::Error| EmulatorError::Pty { what, source: e };
        let master = posix_openpt(OFlag::O_RDWR | OFlag::O_NOCTTY).map_err(|e| err("open", e))?;
        grantpt(&master).map_err(|e| err("grantpt", e))?;
        unlockpt(&master).map_err(|e| err("unlockpt", e))?;
        let path = PathBuf::from(ptsname_r(&master).map_err(|e| err("ptsname", e))?);
        // Our own raw-mode handle on the slave side: no echo or line editing before the
        // driver opens it, and the master never sees a hang-up between connections.
        let slave = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(&path)
            .map_err(|source| EmulatorError::Open {
                path: path.clone(),
                source,
            })?;
        let mut t = tcgetattr(&slave).map_err(|e| err("tcgetattr", e))?;
        cfmakeraw(&mut t);
        tcsetattr(&slave, SetArg::TCSANOW, &t).map_err(|e| err("tcsetattr", e))?;
        let shared = Arc::new(Mutex::new(Shared {
            servos: ids
                .iter()
                .map(|id| EmulatedServo::with_dynamics(*id, dynamics))
                .collect(),
            stats: BusStats::default(),
            garble_after: None,
            faults: std::collections::VecDeque::new(),
            markers: 0,
        }));
        let marker_id = (0..=252u8).rev().find(|id| !ids.contains(id));
        let marker = marker_id
            .map(|id| slave.try_clone().map(|file| (file, id)))
            .transpose()
            .map_err(|source| EmulatorError::Open {
                path: path.clone(),
                source,
            })?;
        let handled = Arc::new(Condvar::new());
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let bus = Bus {
                shared: shared.clone(),
                handled: handled.clone(),
                marker_id,
            };
            let stop = stop.clone();
            std::thread::Builder::new()
                .name("dynamixel emulator".into())
                .spawn(move || serve(master, slave, &bus, &stop))
                .map_err(EmulatorError::Thread)?
        };
        Ok(EmulatedBus {
            path,
            shared,
            handled,
            marker,
            stop,
            thread: Some(thread),
        })
    }

    /// The serial port to open (the pty's slave side).
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Shared> {
        self.shared.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Waits until the emulator's thread has handled every byte written to the bus before
    /// this call. Gives up (the snapshot is then as far as the thread got) when the thread
    /// has stopped, the marker cannot be written, or [`SETTLE_LIMIT`] passes.
    fn settle(&self) -> std::sync::MutexGuard<'_, Shared> {
        let Some((file, id)) = &self.marker else {
            return self.lock();
        };
        let target = self.lock().markers + 1;
        let mut writer: &std::fs::File = file;
        if writer
            .write_all(&packet::instruction(*id, PING, &[]))
            .is_err()
        {
            return self.lock();
        }
        let deadline = Instant::now() + SETTLE_LIMIT;
        let mut shared = self.lock();
        while shared.markers < target {
            let now = Instant::now();
            let finished = self.thread.as_ref().is_none_or(|t| t.is_finished());
            if finished || now >= deadline {
                break;
            }
            shared = self
                .handled
                .wait_timeout(shared, (deadline - now).min(Duration::from_millis(100)))
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
        shared
    }

    /// A snapshot of every servo, once the bus has settled (everything written to it so
    /// far handled).
    pub fn servos(&self) -> Vec<EmulatedServo> {
        self.settle().servos.clone()
    }

    /// What the bus has received so far, once it has settled.
    pub fn stats(&self) -> BusStats {
        self.settle().stats
    }

    /// Sends the first answer after `packets` packets with a wrong checksum (line noise).
    pub fn garble_after(&self, packets: u64) {
        self.lock().garble_after = Some(packets);
    }

    /// Sends the next answers through these line faults, one each, in turn (then as they
    /// are).
    pub fn set_faults(&self, faults: std::collections::VecDeque<LineFault>) {
        self.lock().faults = faults;
    }

    /// Makes servo `id` stop answering once the bus has seen `packets` packets.
    pub fn set_silent_after(&self, id: u8, packets: u64) {
        for s in self.lock().servos.iter_mut().filter(|s| s.id == id) {
            s.silent_after = Some(packets);
        }
    }

    /// Holds servo `id`'s present position and velocity (register units) at these values.
    pub fn hold_present(&self, id: u8, position: i32, velocity: i32) {
        for s in self.lock().servos.iter_mut().filter(|s| s.id == id) {
            s.held = Some((position, velocity));
        }
    }

    /// Makes servo `id` stop (or resume) answering.
    pub fn set_silent(&self, id: u8, silent: bool) {
        for s in self.lock().servos.iter_mut().filter(|s| s.id == id) {
            s.silent = silent;
        }
    }
}

impl Drop for EmulatedBus {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// What the emulator's thread shares with the [`EmulatedBus`].
struct Bus {
    shared: Arc<Mutex<Shared>>,
    handled: Arc<Condvar>,
    marker_id: Option<u8>,
}

/// The emulator thread: reads instructions, answers, moves the servos.
fn serve(mut master: PtyMaster, _slave: std::fs::File, bus: &Bus, stop: &AtomicBool) {
    let mut buf: Vec<u8> = Vec::with_capacity(1024);
    let mut chunk = [0u8; 512];
    let mut last = Instant::now();
    while !stop.load(Ordering::SeqCst) {
        let readable = {
            let mut fds = [PollFd::new(master.as_fd(), PollFlags::POLLIN)];
            matches!(poll(&mut fds, PollTimeout::from(1u8)), Ok(n) if n > 0)
                && fds[0]
                    .revents()
                    .is_some_and(|r| r.contains(PollFlags::POLLIN))
        };
        if readable {
            match master.read(&mut chunk) {
                Ok(n) => buf.extend_from_slice(&chunk[..n]),
                Err(_) => std::thread::sleep(std::time::Duration::from_millis(1)),
            }
        }
        let now = Instant::now();
        let dt = now.duration_since(last).as_secs_f64();
        last = now;
        let mut shared = bus.shared.lock().unwrap_or_else(PoisonError::into_inner);
        for s in shared.servos.iter_mut() {
            s.advance(dt);
        }
        loop {
            match parse(&buf) {
                Parsed::Incomplete => break,
                Parsed::Skip(n) => {
                    shared.stats.bad_packets += u64::from(n >= 4);
                    buf.drain(..n.min(buf.len()));
                }
                Parsed::Packet(instruction, used) => {
                    buf.drain(..used);
                    if instruction.instruction == PING && Some(instruction.id) == bus.marker_id {
                        shared.markers += 1;
                        bus.handled.notify_all();
                        continue;
                    }
                    shared.stats.packets += 1;
                    let mut answer = answer(&mut shared, &instruction);
                    if !answer.is_empty()
                        && shared
                            .garble_after
                            .is_some_and(|n| shared.stats.packets > n)
                    {
                        shared.garble_after = None;
                        if let Some(last) = answer.last_mut() {
                            *last ^= 0x5A;
                        }
                    }
                    if answer.is_empty() {
                        continue;
                    }
                    let fault = shared.faults.pop_front().unwrap_or(LineFault::Pass);
                    if fault.send(&answer, &mut master).is_err() {
                        break;
                    }
                }
            }
        }
    }
}

fn u16_at(p: &[u8], i: usize) -> Option<u16> {
    Some(u16::from_le_bytes([*p.get(i)?, *p.get(i + 1)?]))
}

/// The status packets an instruction gets (empty for broadcasts and silent servos).
fn answer(shared: &mut Shared, i: &Instruction) -> Vec<u8> {
    let mut out = Vec::new();
    let p = &i.params;
    let packets = shared.stats.packets;
    match i.instruction {
        SYNC_WRITE => {
            shared.stats.sync_writes += 1;
            let (Some(address), Some(len)) = (u16_at(p, 0), u16_at(p, 2)) else {
                return out;
            };
            let stride = usize::from(len) + 1;
            for rec in p[4..].chunks_exact(stride) {
                if let Some(s) = shared.servos.iter_mut().find(|s| s.id == rec[0]) {
                    s.write(address, &rec[1..]);
                }
            }
        }
        SYNC_READ => {
            shared.stats.sync_reads += 1;
            let (Some(address), Some(len)) = (u16_at(p, 0), u16_at(p, 2)) else {
                return out;
            };
            for id in &p[4..] {
                if let Some(s) = shared
                    .servos
                    .iter()
                    .find(|s| s.id == *id && s.answers(packets))
                {
                    match s.read(address, len) {
                        Some(data) => out.extend(status(s.id, 0, data)),
                        None => out.extend(status(s.id, ACCESS_ERROR, &[])),
                    }
                }
            }
        }
        _ => {
            let broadcast = i.id == BROADCAST;
            for s in shared
                .servos
                .iter_mut()
                .filter(|s| (broadcast || s.id == i.id) && s.answers(packets))
            {
                let reply = match i.instruction {
                    PING => {
                        let model = crate::robot_io::dynamixel::table::XM430_W350.to_le_bytes();
                        status(s.id, 0, &[model[0], model[1], 45])
                    }
                    READ => match (u16_at(p, 0), u16_at(p, 2)) {
                        (Some(a), Some(n)) => match s.read(a, n) {
                            Some(data) => status(s.id, 0, data),
                            None => status(s.id, ACCESS_ERROR, &[]),
                        },
                        _ => status(s.id, DATA_LENGTH_ERROR, &[]),
                    },
                    WRITE => match u16_at(p, 0) {
                        Some(a) if p.len() > 2 => {
                            let e = if s.write(a, &p[2..]) { 0 } else { ACCESS_ERROR };
                            status(s.id, e, &[])
                        }
                        _ => status(s.id, DATA_LENGTH_ERROR, &[]),
                    },
                    REBOOT => {
                        s.write(crate::robot_io::dynamixel::table::TORQUE_ENABLE, &[0]);
                        status(s.id, 0, &[])
                    }
                    _ => status(s.id, INSTRUCTION_ERROR, &[]),
                };
                // Broadcast pings are answered; other broadcasts are not.
                if !broadcast || i.instruction == PING {
                    out.extend(reply);
                }
            }
        }
    }
    out
}
