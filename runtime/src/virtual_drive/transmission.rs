//! What the drive puts on the line in answer to one request: the reply's bytes, the wait
//! before them (its reply-delay registers' and the one the request asks for) and the next
//! pending fault applied.

use super::faults::{self, Fault};
use super::VirtualDrive;
use crate::protocol::Protocol;
use std::time::Duration;

/// Bytes the drive sends in answer to one request, and how.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transmission {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Sent only after the master's reply timeout.
    pub delayed: bool,
    /// Sent one byte at a time with gaps of this many character times.
    pub split: Option<u32>,
    /// Held back this long after the request before it is sent: the wait the drive's
    /// reply-delay registers set (VF-AS1 F805 / F825).
    pub wait: Duration,
    /// Length of the request answered, in bytes (for the reply timing).
    pub request_len: usize,
}

impl VirtualDrive {
    /// The wait before its replies over `protocol` that its reply-delay registers set (the
    /// longest, where there are several); zero when the protocol has none.
    pub fn reply_delay(&self, protocol: &Protocol) -> Duration {
        let Some(delay) = &protocol.timing.reply_delay else {
            return Duration::ZERO;
        };
        delay
            .registers
            .iter()
            .filter_map(|number| {
                self.drive
                    .register_at(crate::kinds::Space::Parameter, *number)
            })
            .map(|info| delay.of_raw(self.storage.get(info, 0)))
            .max()
            .unwrap_or(Duration::ZERO)
    }

    /// Applies the next pending fault to a reply.
    pub(super) fn commit_faults(
        &mut self,
        protocol: &Protocol,
        request: &[u8],
        mut bytes: Vec<u8>,
    ) -> Option<Transmission> {
        let mut transmission = Transmission {
            bytes: Vec::new(),
            delayed: false,
            split: None,
            wait: self.reply_delay(protocol) + requested_wait(protocol, request),
            request_len: request.len(),
        };
        match self.faults.pop_front() {
            Some(Fault::DropReply) => return None,
            Some(Fault::CorruptChecksum) => {
                faults::corrupt_checksum(protocol, &mut bytes);
            }
            Some(Fault::Delay) => transmission.delayed = true,
            Some(Fault::GarbageBefore(garbage)) => transmission.bytes.extend(garbage),
            Some(Fault::SplitBytes(gap)) => transmission.split = Some(gap),
            Some(other) => self.faults.push_front(other),
            None => {}
        }
        transmission.bytes.extend(bytes);
        Some(transmission)
    }
}

/// The wait before the reply a request asks for ([`crate::Role::ReplyWait`], in tens of
/// milliseconds), where its layout carries one.
fn requested_wait(protocol: &Protocol, request: &[u8]) -> Duration {
    protocol
        .decode_request_exact(request)
        .ok()
        .and_then(|decoded| {
            decoded
                .values
                .get(&decoded.command.request, crate::Role::ReplyWait)
        })
        .map_or(Duration::ZERO, |tens| {
            Duration::from_millis(10 * u64::from(tens))
        })
}
