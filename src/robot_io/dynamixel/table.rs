//! The X-series control table (XM430 / XL430 / XH430 and kin) as proleg uses it, and the
//! conversions between register values and joint units.

/// Model number (2 bytes, read-only).
pub const MODEL_NUMBER: u16 = 0;
/// Torque enable (1 byte).
pub const TORQUE_ENABLE: u16 = 64;
/// LED (1 byte).
pub const LED: u16 = 65;
/// Hardware error status (1 byte).
pub const HARDWARE_ERROR: u16 = 70;
/// Goal position (4 bytes).
pub const GOAL_POSITION: u16 = 116;
/// Present current (2 bytes, signed), then present velocity (4, signed) and present
/// position (4): read in one block of [`PRESENT_BLOCK_LEN`] bytes.
pub const PRESENT_CURRENT: u16 = 126;
/// Present velocity (4 bytes, signed).
pub const PRESENT_VELOCITY: u16 = 128;
/// Present position (4 bytes).
pub const PRESENT_POSITION: u16 = 132;
/// Bytes of the present current/velocity/position block.
pub const PRESENT_BLOCK_LEN: u16 = 10;
/// Present temperature (1 byte, °C).
pub const PRESENT_TEMPERATURE: u16 = 146;
/// The length of the control table the emulator keeps.
pub const TABLE_LEN: usize = 160;
/// XM430-W350's model number.
pub const XM430_W350: u16 = 1020;

/// Position units per revolution; 2048 is the centre (0°).
pub const POSITION_UNITS: f64 = 4096.0;
/// The position of 0°.
pub const POSITION_CENTRE: f64 = 2048.0;
/// One current unit in A (XM430: 2.69 mA).
pub const CURRENT_UNIT_A: f64 = 0.00269;
/// One velocity unit in degrees/s (0.229 rpm).
pub const VELOCITY_UNIT_DEG_S: f64 = 0.229 * 6.0;

/// The goal-position register value of a servo angle (degrees), within 0..4095.
pub fn position_raw(servo_deg: f64) -> u32 {
    let raw = POSITION_CENTRE + servo_deg * POSITION_UNITS / 360.0;
    raw.round().clamp(0.0, POSITION_UNITS - 1.0) as u32
}

/// The servo angle (degrees) of a position register value.
pub fn position_deg(raw: i32) -> f64 {
    (f64::from(raw) - POSITION_CENTRE) * 360.0 / POSITION_UNITS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_convert_both_ways_within_a_unit() {
        for deg in [-90.0, -12.3, 0.0, 45.0, 179.0] {
            let back = position_deg(position_raw(deg) as i32);
            assert!(
                (back - deg).abs() <= 360.0 / POSITION_UNITS,
                "{deg} -> {back}"
            );
        }
        assert_eq!(position_raw(0.0), 2048);
        assert_eq!(position_raw(1000.0), 4095);
        assert_eq!(position_raw(-1000.0), 0);
    }
}
