//! One emulated X-series servo: its control table, and a motion model that moves the
//! present position toward the goal while torque is on: the simulator's servo law
//! ([`servo_velocity`]: a proportional gain clamped to a speed, a dead band) on goals that
//! arrive after a latency, with optional backlash between motor and output and noise on
//! the reported position ([`ServoDynamics`]; by default a constant speed toward the goal).
//! Calibration tests hide dynamics here and recover them from a recording.

use std::collections::VecDeque;

use crate::rng::SimRng;
use crate::robot_io::dynamixel::table;
use crate::sim::servo::servo_velocity;

/// How an emulated servo moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoDynamics {
    /// Top speed (degrees/s).
    pub speed_deg_s: f64,
    /// Proportional gain (1/s); infinite: the top speed until the goal.
    pub gain: f64,
    /// Angle error (degrees) left uncorrected.
    pub dead_band_deg: f64,
    /// How long (s) a written goal takes to act.
    pub latency_s: f64,
    /// Standard deviation (degrees) of the noise on the reported position.
    pub noise_deg: f64,
    /// Play (degrees) between the motor and the output shaft.
    pub backlash_deg: f64,
}

impl ServoDynamics {
    /// A servo that moves at `speed_deg_s` straight to its goal, at once and exactly.
    pub fn constant_speed(speed_deg_s: f64) -> ServoDynamics {
        ServoDynamics {
            speed_deg_s,
            gain: f64::INFINITY,
            dead_band_deg: 0.0,
            latency_s: 0.0,
            noise_deg: 0.0,
            backlash_deg: 0.0,
        }
    }
}

/// Longest integration step of the motion model (s).
const SUBSTEP: f64 = 0.0005;

/// Degrees per position unit.
const DEG_PER_UNIT: f64 = 360.0 / table::POSITION_UNITS;

/// An emulated servo.
#[derive(Debug, Clone, PartialEq)]
pub struct EmulatedServo {
    /// Bus id.
    pub id: u8,
    /// The control table (little-endian registers).
    pub memory: [u8; table::TABLE_LEN],
    /// Output position in units, kept as a float between steps.
    position: f64,
    /// Motor position in units (the output follows it within the backlash).
    motor: f64,
    /// How it moves.
    dynamics: ServoDynamics,
    /// Emulator time (s) this servo has advanced.
    clock: f64,
    /// Goals written (time, units) not yet acting.
    in_flight: VecDeque<(f64, f64)>,
    /// The goal acting now (units).
    acting: f64,
    /// The noise of the reported position.
    rng: SimRng,
    /// Does not answer (to test timeouts).
    pub silent: bool,
    /// Stops answering once the bus has seen this many packets.
    pub silent_after: Option<u64>,
    /// Goal positions written so far (units), for tests.
    pub goals_written: u64,
    /// Present position and velocity (register units) held whatever the goal (tests).
    pub held: Option<(i32, i32)>,
}

impl EmulatedServo {
    /// A servo at the centre (0°), torque off, moving at `speed_deg_s` when on.
    pub fn new(id: u8, speed_deg_s: f64) -> Self {
        EmulatedServo::with_dynamics(id, ServoDynamics::constant_speed(speed_deg_s))
    }

    /// A servo at the centre (0°), torque off, moving as `dynamics` say when on (its
    /// noise seeded by its id).
    pub fn with_dynamics(id: u8, dynamics: ServoDynamics) -> Self {
        let mut s = EmulatedServo {
            id,
            memory: [0; table::TABLE_LEN],
            position: table::POSITION_CENTRE,
            motor: table::POSITION_CENTRE,
            dynamics,
            clock: 0.0,
            in_flight: VecDeque::new(),
            acting: table::POSITION_CENTRE,
            rng: SimRng::new(0x5e7_0000 + u64::from(id)),
            silent: false,
            silent_after: None,
            goals_written: 0,
            held: None,
        };
        s.put(table::MODEL_NUMBER, &table::XM430_W350.to_le_bytes());
        s.memory[7] = id;
        s.put(table::GOAL_POSITION, &2048u32.to_le_bytes());
        s.memory[usize::from(table::PRESENT_TEMPERATURE)] = 31;
        s.sync_present(0.0);
        s
    }

    fn put(&mut self, address: u16, bytes: &[u8]) {
        let a = usize::from(address);
        self.memory[a..a + bytes.len()].copy_from_slice(bytes);
    }

    fn u32_at(&self, address: u16) -> u32 {
        let a = usize::from(address);
        u32::from_le_bytes([
            self.memory[a],
            self.memory[a + 1],
            self.memory[a + 2],
            self.memory[a + 3],
        ])
    }

    /// Whether it answers after the bus has seen `packets` packets.
    pub fn answers(&self, packets: u64) -> bool {
        !self.silent && self.silent_after.is_none_or(|n| packets <= n)
    }

    /// Whether the torque is on.
    pub fn torque(&self) -> bool {
        self.memory[usize::from(table::TORQUE_ENABLE)] != 0
    }

    /// The goal position (units).
    pub fn goal(&self) -> u32 {
        self.u32_at(table::GOAL_POSITION)
    }

    /// The present position (units).
    pub fn present(&self) -> f64 {
        self.position
    }

    /// The bytes `address .. address + len`, or `None` outside the table.
    pub fn read(&self, address: u16, len: u16) -> Option<&[u8]> {
        let (a, n) = (usize::from(address), usize::from(len));
        self.memory.get(a..a + n)
    }

    /// Writes `data` at `address`; false outside the table or into read-only registers.
    pub fn write(&mut self, address: u16, data: &[u8]) -> bool {
        let a = usize::from(address);
        let end = a + data.len();
        // 0..7 (model, firmware) and 120..147 (present values) are read-only.
        let overlaps = |lo: usize, hi: usize| a < hi && end > lo;
        if end > table::TABLE_LEN || overlaps(0, 7) || overlaps(120, 147) {
            return false;
        }
        let goal =
            a <= usize::from(table::GOAL_POSITION) && end > usize::from(table::GOAL_POSITION);
        self.memory[a..end].copy_from_slice(data);
        let torque = usize::from(table::TORQUE_ENABLE);
        if (a..end).contains(&torque) {
            // The load current follows the torque at once, not at the next movement.
            let v = self.u32_at(table::PRESENT_VELOCITY) as i32;
            self.put_current(v);
        }
        if goal {
            self.goals_written += 1;
            self.in_flight
                .push_back((self.clock, f64::from(self.goal())));
        }
        true
    }

    /// Moves toward the goal for `dt` seconds and updates the present registers.
    pub fn advance(&mut self, dt: f64) {
        let before = self.position;
        if dt > 0.0 {
            let steps = (dt / SUBSTEP).ceil().max(1.0);
            let h = dt / steps;
            for _ in 0..steps as u64 {
                self.clock += h;
                self.take_arrived_goals();
                if self.torque() {
                    self.move_motor(h);
                }
            }
        }
        let velocity = if dt > 0.0 {
            (self.position - before) / dt
        } else {
            0.0
        };
        self.sync_present(velocity);
    }

    /// The goals whose latency has passed act, the last of them now.
    fn take_arrived_goals(&mut self) {
        while let Some(&(written, goal)) = self.in_flight.front() {
            if written + self.dynamics.latency_s > self.clock {
                break;
            }
            self.acting = goal;
            self.in_flight.pop_front();
        }
    }

    /// One integration step of `h` seconds: the servo law moves the motor (never past its
    /// goal), the output follows within the backlash.
    fn move_motor(&mut self, h: f64) {
        let d = &self.dynamics;
        let error = (self.acting - self.motor) * DEG_PER_UNIT;
        let v = servo_velocity(d.gain, d.speed_deg_s, d.dead_band_deg, error);
        let step = v * h;
        let step = if step.abs() > error.abs() {
            error
        } else {
            step
        };
        self.motor += step / DEG_PER_UNIT;
        let play = d.backlash_deg / 2.0 / DEG_PER_UNIT;
        self.position = self.position.clamp(self.motor - play, self.motor + play);
    }

    fn sync_present(&mut self, velocity_units_s: f64) {
        // Units of 0.229 rpm = 1.374 deg/s = 15.63 position units/s.
        let noise = if self.dynamics.noise_deg > 0.0 {
            self.rng.gaussian() * self.dynamics.noise_deg / DEG_PER_UNIT
        } else {
            0.0
        };
        let (position, velocity) = self.held.unwrap_or((
            (self.position + noise).round() as i32,
            (velocity_units_s * 360.0 / table::POSITION_UNITS / table::VELOCITY_UNIT_DEG_S).round()
                as i32,
        ));
        self.put_current(velocity);
        self.put(table::PRESENT_VELOCITY, &velocity.to_le_bytes());
        self.put(table::PRESENT_POSITION, &position.to_le_bytes());
    }

    /// A load current that grows with the speed while the torque is on (emulated, in
    /// 2.69 mA units).
    fn put_current(&mut self, velocity: i32) {
        let current = if self.torque() {
            (40 + velocity.unsigned_abs() / 4).min(1000) as i16
        } else {
            0
        };
        self.put(table::PRESENT_CURRENT, &current.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_toward_the_goal_at_its_speed_only_with_torque() {
        let mut s = EmulatedServo::new(1, 90.0);
        assert!(s.write(table::GOAL_POSITION, &3072u32.to_le_bytes()));
        s.advance(0.5);
        assert_eq!(s.present(), 2048.0, "torque off: no motion");
        assert!(s.write(table::TORQUE_ENABLE, &[1]));
        s.advance(0.5);
        assert!(
            (s.present() - (2048.0 + 512.0)).abs() < 1e-9,
            "{}",
            s.present()
        );
        s.advance(1.0);
        assert_eq!(s.present(), 3072.0);
        assert!(!s.write(table::PRESENT_POSITION, &[0, 0, 0, 0]));
        assert!(!s.write(0, &[1]));
        assert_eq!(s.goals_written, 1);
    }

    #[test]
    fn the_load_current_follows_the_torque_switch_before_any_movement() {
        let current = |s: &EmulatedServo| {
            let b = s.read(table::PRESENT_CURRENT, 2).unwrap_or(&[0, 0]);
            i16::from_le_bytes([b[0], b[1]])
        };
        let mut s = EmulatedServo::new(1, 90.0);
        assert_eq!(current(&s), 0);
        assert!(s.write(table::TORQUE_ENABLE, &[1]));
        assert_eq!(current(&s), 40, "holding current at once");
        assert!(s.write(table::TORQUE_ENABLE, &[0]));
        assert_eq!(current(&s), 0);
    }
}
