//! Faults the virtual drive can be told to commit, for testing a master's error handling.

use super::VirtualDrive;
use crate::error::DecodeErrorKind;
use crate::protocol::Protocol;

/// A misbehaviour of the virtual drive (or of its line). All but [`Fault::Noise`] and
/// [`Fault::EchoRequest`] apply to the next reply only; those two are states of the line and
/// go on until the faults are cleared.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Fault {
    /// Do not answer the next request.
    DropReply,
    /// Answer with a wrong checksum.
    CorruptChecksum,
    /// Answer only after the master's reply timeout (in process: the reply arrives after
    /// the master has given up).
    Delay,
    /// Send these bytes before the reply.
    GarbageBefore(Vec<u8>),
    /// Answer as station `address + 1` (where the reply carries a station number).
    WrongStation,
    /// Return every request to the master, ahead of any reply, as a two-wire line without
    /// echo cancelling does (also when the drive stays silent).
    EchoRequest,
    /// Send the reply one byte at a time, with gaps of this many character times.
    SplitBytes(u32),
    /// Send endless noise instead of replies.
    Noise,
    /// Answer the next request whatever station it addresses (a broadcast, or another
    /// station's request).
    AnswerBroadcast,
}

/// Flips one bit of `reply` so that it fails its checksum: the last byte whose change the
/// protocol's decoder reports as a checksum mismatch. Returns false when none does (the
/// frame has no checksum).
pub(crate) fn corrupt_checksum(protocol: &Protocol, reply: &mut [u8]) -> bool {
    for index in (0..reply.len()).rev() {
        let original = reply[index];
        for flip in [0x01u8, 0x02, 0x10] {
            reply[index] = original ^ flip;
            if let Err(error) = protocol.decode_reply(None, reply) {
                if error.kind() == DecodeErrorKind::ChecksumMismatch {
                    return true;
                }
            }
        }
        reply[index] = original;
    }
    false
}

impl VirtualDrive {
    /// Commits `fault` (see [`Fault`] for how long it lasts).
    pub fn inject(&mut self, fault: Fault) {
        match fault {
            Fault::Noise => self.noise = true,
            Fault::EchoRequest => self.echo = true,
            fault => self.faults.push_back(fault),
        }
    }

    /// Stops every fault.
    pub fn clear_faults(&mut self) {
        self.faults.clear();
        self.noise = false;
        self.echo = false;
    }

    /// Whether `fault` is pending (noise and echo: in force).
    pub fn has_fault(&self, fault: &Fault) -> bool {
        match fault {
            Fault::Noise => self.noise,
            Fault::EchoRequest => self.echo,
            other => self.faults.contains(other),
        }
    }
}
