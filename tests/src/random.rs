//! A small seeded random-number generator for the tests that shake inputs (xorshift64*):
//! deterministic, so a failure reproduces from its seed.

/// xorshift64*: small, deterministic, good enough to shake a decoder or a description.
pub struct Random(pub u64);

impl Random {
    /// The next number.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A number below `limit` (which must not be 0).
    pub fn below(&mut self, limit: usize) -> usize {
        (self.next_u64() % limit as u64) as usize
    }
}
