//! Checksum primitives named by protocol descriptions.

use crate::layout::ChecksumAlgorithm;

/// Low byte of the sum of `bytes` (Toshiba-style "SUM").
pub fn sum8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |sum, byte| sum.wrapping_add(*byte))
}

/// Exclusive-or of `bytes` (FC-protocol "BCC").
pub fn xor8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |acc, byte| acc ^ byte)
}

/// Computes `algorithm` over `bytes`.
pub fn compute(algorithm: ChecksumAlgorithm, bytes: &[u8]) -> u32 {
    match algorithm {
        ChecksumAlgorithm::Sum8 => u32::from(sum8(bytes)),
        ChecksumAlgorithm::Xor8 => u32::from(xor8(bytes)),
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
    fn xor8_of_equal_bytes_is_zero() {
        assert_eq!(xor8(&[0x5A, 0x5A]), 0);
        assert_eq!(xor8(&[0x02, 0x04, 0x01]), 0x07);
    }
}
