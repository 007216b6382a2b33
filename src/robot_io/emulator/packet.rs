//! Protocol 2.0 packets from the servo's side: finding instruction packets in a byte
//! stream (header, length, byte stuffing, CRC) and building status packets.

use dynamixel2::checksum::calculate_checksum;

/// The header every packet starts with.
pub const HEADER: [u8; 4] = [0xFF, 0xFF, 0xFD, 0x00];
/// The status instruction.
pub const STATUS: u8 = 0x55;

/// One instruction packet, parameters unstuffed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instruction {
    /// Servo id (254: broadcast).
    pub id: u8,
    /// Instruction code.
    pub instruction: u8,
    /// Parameters, unstuffed.
    pub params: Vec<u8>,
}

/// What the front of a buffer holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Parsed {
    /// Not a whole packet yet.
    Incomplete,
    /// Bytes to drop (noise before a header, a packet with a bad CRC).
    Skip(usize),
    /// A packet and the bytes it took.
    Packet(Instruction, usize),
}

/// Removes byte stuffing: `FF FF FD FD` becomes `FF FF FD`.
fn unstuff(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len());
    let mut i = 0;
    while i < data.len() {
        out.push(data[i]);
        if i >= 2 && data[i - 2..=i] == [0xFF, 0xFF, 0xFD] && data.get(i + 1) == Some(&0xFD) {
            i += 1;
        }
        i += 1;
    }
    out
}

/// Adds byte stuffing after every `FF FF FD`.
fn stuff(data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() + 4);
    for (i, b) in data.iter().enumerate() {
        out.push(*b);
        if i >= 2 && data[i - 2..=i] == [0xFF, 0xFF, 0xFD] {
            out.push(0xFD);
        }
    }
    out
}

/// Looks for an instruction packet at the front of `buf`.
pub fn parse(buf: &[u8]) -> Parsed {
    let Some(start) = buf.windows(4).position(|w| w == HEADER) else {
        // Keep a possible partial header at the end.
        return match buf.len() {
            0..=3 => Parsed::Incomplete,
            n => Parsed::Skip(n - 3),
        };
    };
    if start > 0 {
        return Parsed::Skip(start);
    }
    if buf.len() < 7 {
        return Parsed::Incomplete;
    }
    let len = usize::from(u16::from_le_bytes([buf[5], buf[6]]));
    if len < 3 {
        return Parsed::Skip(4);
    }
    let total = 7 + len;
    if buf.len() < total {
        return Parsed::Incomplete;
    }
    let crc = u16::from_le_bytes([buf[total - 2], buf[total - 1]]);
    if calculate_checksum(0, &buf[..total - 2]) != crc {
        return Parsed::Skip(4);
    }
    let body = unstuff(&buf[7..total - 2]);
    Parsed::Packet(
        Instruction {
            id: buf[4],
            instruction: body[0],
            params: body[1..].to_vec(),
        },
        total,
    )
}

/// A packet to or from `id`: header, id, length, then `body` stuffed, then the CRC.
fn packet(id: u8, body: &[u8]) -> Vec<u8> {
    let body = stuff(body);
    let len = (body.len() + 2) as u16;
    let mut out = HEADER.to_vec();
    out.push(id);
    out.extend_from_slice(&len.to_le_bytes());
    out.extend_from_slice(&body);
    let crc = calculate_checksum(0, &out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// A status packet from servo `id` with error byte `error` and `params`.
pub fn status(id: u8, error: u8, params: &[u8]) -> Vec<u8> {
    let mut body = vec![STATUS, error];
    body.extend_from_slice(params);
    packet(id, &body)
}

/// An instruction packet (what a host sends), for tests.
pub fn instruction(id: u8, instruction: u8, params: &[u8]) -> Vec<u8> {
    let mut body = vec![instruction];
    body.extend_from_slice(params);
    packet(id, &body)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packets_round_trip_with_stuffing_and_noise() {
        let params = [0x74, 0x00, 0xFF, 0xFF, 0xFD, 0x01];
        let mut stream = vec![0x00, 0x42];
        stream.extend(instruction(3, 0x03, &params));
        assert_eq!(parse(&stream), Parsed::Skip(2));
        let p = &stream[2..];
        match parse(p) {
            Parsed::Packet(i, used) => {
                assert_eq!(used, p.len());
                assert_eq!((i.id, i.instruction), (3, 0x03));
                assert_eq!(i.params, params);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(parse(&p[..p.len() - 1]), Parsed::Incomplete);
        let mut bad = p.to_vec();
        let n = bad.len();
        bad[n - 1] ^= 1;
        assert_eq!(parse(&bad), Parsed::Skip(4));
    }

    #[test]
    fn status_packets_are_what_the_protocol_says() {
        // The ping answer of the e-manual's example: ID 1, XM430 model 1030 (0x0406), fw 38.
        let s = status(1, 0, &[0x06, 0x04, 0x26]);
        assert_eq!(
            s,
            [
                0xFF, 0xFF, 0xFD, 0x00, 0x01, 0x07, 0x00, 0x55, 0x00, 0x06, 0x04, 0x26, 0x65, 0x5D
            ]
        );
    }
}
