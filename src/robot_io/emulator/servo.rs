//! One emulated X-series servo: its control table, and a motion model that moves the
//! present position toward the goal at a set speed while torque is on.

use crate::robot_io::dynamixel::table;

/// An emulated servo.
#[derive(Debug, Clone, PartialEq)]
pub struct EmulatedServo {
    /// Bus id.
    pub id: u8,
    /// The control table (little-endian registers).
    pub memory: [u8; table::TABLE_LEN],
    /// Present position in units, kept as a float between steps.
    position: f64,
    /// Speed toward the goal (position units per second).
    speed: f64,
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
        let mut s = EmulatedServo {
            id,
            memory: [0; table::TABLE_LEN],
            position: table::POSITION_CENTRE,
            speed: speed_deg_s * table::POSITION_UNITS / 360.0,
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
        if a <= usize::from(table::GOAL_POSITION) && end > usize::from(table::GOAL_POSITION) {
            self.goals_written += 1;
        }
        self.memory[a..end].copy_from_slice(data);
        true
    }

    /// Moves toward the goal for `dt` seconds and updates the present registers.
    pub fn advance(&mut self, dt: f64) {
        let mut velocity = 0.0;
        if self.torque() && dt > 0.0 {
            let goal = f64::from(self.goal());
            let step = self.speed * dt;
            let delta = (goal - self.position).clamp(-step, step);
            self.position += delta;
            velocity = delta / dt;
        }
        self.sync_present(velocity);
    }

    fn sync_present(&mut self, velocity_units_s: f64) {
        // Units of 0.229 rpm = 1.374 deg/s = 15.63 position units/s.
        let (position, velocity) = self.held.unwrap_or((
            self.position.round() as i32,
            (velocity_units_s * 360.0 / table::POSITION_UNITS / table::VELOCITY_UNIT_DEG_S).round()
                as i32,
        ));
        // A load current that grows with the speed (emulated, in 2.69 mA units).
        let current = if self.torque() {
            (40 + velocity.unsigned_abs() / 4).min(1000) as i16
        } else {
            0
        };
        self.put(table::PRESENT_CURRENT, &current.to_le_bytes());
        self.put(table::PRESENT_VELOCITY, &velocity.to_le_bytes());
        self.put(table::PRESENT_POSITION, &position.to_le_bytes());
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
}
