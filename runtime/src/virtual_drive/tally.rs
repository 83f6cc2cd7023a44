//! What a virtual drive saw on its line: the requests addressed to it, the replies it sent
//! and the writes it carried out, so a test can assert that a station received no write.

use super::VirtualDrive;
use crate::protocol::DecodedRequest;

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

impl VirtualDrive {
    /// The number of request frames received so far, whatever station they address and
    /// whether or not a fault kept the reply from the master (a test counts with it how
    /// often a master sent a request).
    pub fn requests(&self) -> u64 {
        self.requests
    }

    /// What this station saw on its line so far: requests addressed to it (answered or
    /// not), replies sent, writes carried out.
    pub fn tally(&self) -> Tally {
        self.tally
    }

    /// Counts `request` in [`Tally::addressed`] when it is for this station: its own
    /// number, a broadcast, or a frame without a station number (a point-to-point line).
    pub(super) fn count_addressed(&mut self, request: &DecodedRequest<'_>) {
        if request.broadcast.is_some() || request.address.is_none_or(|a| a == self.address) {
            self.tally.addressed += 1;
            self.unreadable_in_a_row = 0;
        }
    }
}
