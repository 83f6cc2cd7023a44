//! Checksum primitives named by protocol descriptions.

use crate::layout::ChecksumAlgorithm;

/// Low byte of the sum of `bytes` (Toshiba-style "SUM").
#[inline]
pub fn sum8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |sum, byte| sum.wrapping_add(*byte))
}

/// Exclusive-or of `bytes` (FC-protocol "BCC").
#[inline]
pub fn xor8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |acc, byte| acc ^ byte)
}

/// CRC-16/MODBUS lookup table, built at compile time from the reflected polynomial A001h.
const CRC16_MODBUS_TABLE: [u16; 256] = {
    let mut table = [0u16; 256];
    let mut index = 0;
    while index < 256 {
        let mut crc = index as u16;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
            bit += 1;
        }
        table[index] = crc;
        index += 1;
    }
    table
};

/// CRC-16/MODBUS: reflected polynomial A001h, initial value FFFFh (sent low byte first).
#[inline]
pub fn crc16_modbus(bytes: &[u8]) -> u16 {
    bytes.iter().fold(0xFFFFu16, |crc, byte| {
        (crc >> 8) ^ CRC16_MODBUS_TABLE[usize::from((crc ^ u16::from(*byte)) as u8)]
    })
}

/// Modbus ASCII LRC: the two's complement of the byte sum.
#[inline]
pub fn lrc8(bytes: &[u8]) -> u8 {
    sum8(bytes).wrapping_neg()
}

/// Computes `algorithm` over `bytes`.
#[inline]
pub fn compute(algorithm: ChecksumAlgorithm, bytes: &[u8]) -> u32 {
    match algorithm {
        ChecksumAlgorithm::Sum8 => u32::from(sum8(bytes)),
        ChecksumAlgorithm::Xor8 => u32::from(xor8(bytes)),
        ChecksumAlgorithm::Crc16Modbus => u32::from(crc16_modbus(bytes)),
        ChecksumAlgorithm::Lrc8 => u32::from(lrc8(bytes)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sum8_matches_the_manual_worked_example() {
        // YD1000 manual 4.2: 2Fh + 52h + 01h + 02h = 84h.
        assert_eq!(sum8(&[0x2F, 0x52, 0x01, 0x02]), 0x84);
        // YD1000 manual 4.1: "(R0000&" sums to 160h, so the checksum is "60".
        assert_eq!(sum8(b"(R0000&"), 0x60);
    }

    #[test]
    fn sum8_wraps() {
        assert_eq!(sum8(&[0xFF, 0x02]), 0x01);
    }

    #[test]
    fn crc16_matches_the_fc_manual_modbus_example() {
        // FC manual, function 03: 01 03 0B D5 00 02 carries CRC D7 D7.
        assert_eq!(
            crc16_modbus(&[0x01, 0x03, 0x0B, 0xD5, 0x00, 0x02]).to_le_bytes(),
            [0xD7, 0xD7]
        );
        // The CRC-16/MODBUS check value.
        assert_eq!(crc16_modbus(b"123456789"), 0x4B37);
    }

    #[test]
    fn crc16_table_matches_the_bitwise_definition() {
        let bitwise = |bytes: &[u8]| {
            let mut crc = 0xFFFFu16;
            for byte in bytes {
                crc ^= u16::from(*byte);
                for _ in 0..8 {
                    crc = if crc & 1 != 0 {
                        (crc >> 1) ^ 0xA001
                    } else {
                        crc >> 1
                    };
                }
            }
            crc
        };
        let data: Vec<u8> = (0..=255u8).chain((0..=255u8).rev()).collect();
        for len in [0, 1, 2, 7, 64, 512] {
            assert_eq!(
                crc16_modbus(&data[..len]),
                bitwise(&data[..len]),
                "{len} bytes"
            );
        }
    }

    #[test]
    fn lrc8_makes_the_sum_zero() {
        let bytes = [0x01, 0x03, 0x00, 0x6B, 0x00, 0x03];
        assert_eq!(sum8(&bytes).wrapping_add(lrc8(&bytes)), 0);
        assert_eq!(lrc8(&bytes), 0x8E);
    }

    #[test]
    fn xor8_of_equal_bytes_is_zero() {
        assert_eq!(xor8(&[0x5A, 0x5A]), 0);
        assert_eq!(xor8(&[0x02, 0x04, 0x01]), 0x07);
    }
}
