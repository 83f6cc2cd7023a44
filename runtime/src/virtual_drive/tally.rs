//! What a virtual drive saw on its line: the requests addressed to it, the replies it sent
//! and the writes it carried out, so a test can assert that a station received no write.

/// Counts kept by a virtual drive since it was made ([`super::VirtualDrive::tally`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Tally {
    /// Request frames for this station (its own number, a broadcast, or a frame that
    /// carries no station number), answered or not, unplugged or not.
    pub addressed: u64,
    /// Replies it put on the line (faults that drop a reply excepted).
    pub answered: u64,
    /// Writes it carried out (a register, a block or a command that changes its state),
    /// answered or not; refused writes are not counted.
    pub writes: u64,
}
