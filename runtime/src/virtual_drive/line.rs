//! The drive on its line: the bytes received are cut into request frames (noise before a
//! start sequence skipped, an unfinished frame kept for the bytes to come), each frame is
//! answered and the reply sent with the pending fault applied; the line's silence ends the
//! garbage before a frame; a drive unplugged from the line answers nothing.

use super::bad_checksum;
use super::faults::Fault;
use super::outcome::{Outcome, Refusal};
use super::transmission::Transmission;
use super::unreadable;
use super::unsupported;
use super::variants::Read;
use super::VirtualDrive;
use crate::error::DecodeErrorKind;
use crate::protocol::{Found, Protocol};
use std::time::Duration;

impl VirtualDrive {
    /// Unplugs the drive from its line (`true`) or plugs it back (`false`). Unplugged, it
    /// neither answers nor acts on any frame (a dead station on a multi-drop bus), but
    /// still counts the requests addressed to it
    /// ([`Tally::addressed`](super::Tally::addressed)), so a test can tell that a master
    /// tried it. Its motor and clock go on.
    pub fn set_unplugged(&mut self, unplugged: bool) {
        self.unplugged = unplugged;
    }

    /// Whether the drive is unplugged ([`VirtualDrive::set_unplugged`]).
    pub fn unplugged(&self) -> bool {
        self.unplugged
    }

    /// The line has been silent for a frame gap: bytes received before no longer belong
    /// to the next frame (see [`crate::serial::BeforeStart`]).
    pub fn line_silent(&mut self) {
        self.garbage = false;
    }

    /// Takes the request frames out of `input` (bytes received so far; noise before a
    /// start sequence is skipped, an unfinished frame is left in it) and returns what the
    /// drive sends in answer, faults applied. Over a protocol with variants, frames are
    /// read in the variant in force (see [`VirtualDrive::respond`]); a frame that another
    /// variant's form would continue (a CR that an LF may follow) waits for the next byte
    /// or for the line's silence ([`VirtualDrive::receive_before_silence`]).
    pub fn receive(&mut self, protocol: &Protocol, input: &mut Vec<u8>) -> Vec<Transmission> {
        self.take_frames(protocol, input, false)
    }

    /// [`VirtualDrive::receive`] for bytes the line's silence follows (a master's whole
    /// burst): a frame that another variant's form could still have continued is taken
    /// as it stands, and a frame that never completed in the variant in force but is whole
    /// in another's gets the mismatch error.
    pub fn receive_before_silence(
        &mut self,
        protocol: &Protocol,
        input: &mut Vec<u8>,
    ) -> Vec<Transmission> {
        self.take_frames(protocol, input, true)
    }

    fn take_frames(
        &mut self,
        protocol: &Protocol,
        input: &mut Vec<u8>,
        settled: bool,
    ) -> Vec<Transmission> {
        let mut sent = Vec::new();
        if input.is_empty() {
            return sent;
        }
        let variants = self.in_force(protocol);
        let protocol = variants.own.as_ref();
        let start = protocol
            .commands
            .first()
            .and_then(|c| c.request.start_bytes())
            .unwrap_or(&[]);
        loop {
            if let Some((len, again)) = self.take_follow_up(protocol, input) {
                drop(input.drain(..len));
                if let Some(reply) = again {
                    // Asking for the reply again is a request of its own.
                    self.requests += 1;
                    if !self.noise && !self.unplugged {
                        if let Some(transmission) = self.commit_faults(protocol, &[], reply) {
                            sent.push(transmission);
                        }
                    }
                }
                continue;
            }
            if !start.is_empty() {
                match find(input, start) {
                    Some(offset) => {
                        self.garbage |= offset > 0;
                        drop(input.drain(..offset));
                    }
                    None => {
                        let keep = input.len().min(start.len() - 1);
                        self.garbage |= input.len() > keep;
                        input.drain(..input.len() - keep);
                        break;
                    }
                }
            }
            if input.is_empty() {
                break;
            }
            let decoded = match variants.read(input, settled) {
                Read::Own(decoded) => Ok(decoded),
                Read::Wait => break,
                Read::Other(frame) => Err(frame),
            };
            let (outcome, used) = match decoded {
                Err(frame) => {
                    // Another variant's frame: the mismatch error, in the variant in force.
                    self.requests += 1;
                    (
                        self.answer_mismatch(protocol, &frame, variants.mismatch),
                        frame.len,
                    )
                }
                Ok(Ok(Found::Frame { frame, .. })) => {
                    self.requests += 1;
                    self.count_addressed(&frame);
                    let mut pending = self.faults.front().cloned();
                    let rejected = std::mem::take(&mut self.garbage)
                        && protocol.timing.before_start == crate::serial::BeforeStart::Reject;
                    let outcome = if self.unplugged {
                        Outcome::Silent("unplugged from the line")
                    } else if self.starting_up() {
                        Outcome::Silent("starting up after power-on")
                    } else if rejected {
                        Outcome::Silent("bytes before the start sequence reject the frame")
                    } else if pending == Some(Fault::AnswerBroadcast) {
                        self.faults.pop_front();
                        pending = None;
                        let own = self.address;
                        self.address = frame.address.unwrap_or(own);
                        // A broadcast is answered as if it addressed this station alone.
                        let frame = crate::protocol::DecodedRequest {
                            address: frame.address.or(frame.broadcast.map(|_| own)),
                            broadcast: None,
                            ..frame
                        };
                        let outcome = self.answer(protocol, &frame);
                        self.address = own;
                        outcome
                    } else {
                        self.answer(protocol, &frame)
                    };
                    let outcome = match (pending, outcome) {
                        (Some(Fault::WrongStation), Outcome::Reply(_)) => {
                            self.faults.pop_front();
                            let own = self.address;
                            let other = own.wrapping_add(1);
                            self.address = frame.address.map_or(own, |_| other);
                            let mut wrong = frame;
                            wrong.address = frame.address.map(|_| other);
                            let outcome = self.answer(protocol, &wrong);
                            self.address = own;
                            outcome
                        }
                        (_, outcome) => outcome,
                    };
                    // A write of the station register moves the station (its reply is
                    // already made, from the station addressed).
                    self.follow_station_register();
                    let reply = match &outcome {
                        Outcome::Reply(bytes) => Some(bytes.as_slice()),
                        Outcome::Silent(_) => None,
                    };
                    self.note_reply(protocol, frame.command.code, reply);
                    (outcome, frame.len)
                }
                Ok(Ok(Found::Incomplete)) => break,
                Ok(Err(error)) => {
                    let checksum = error.kind() == DecodeErrorKind::ChecksumMismatch;
                    // A drive whose manual gives codes for unreadable frames reads their
                    // station from the frame and counts them in a row.
                    let unreadable = if checksum {
                        self.unreadable(protocol, input, true)
                    } else {
                        None
                    };
                    match unreadable {
                        Some(unreadable::Unreadable::Frame { len, outcome }) => (outcome, len),
                        Some(unreadable::Unreadable::Wait) if !settled => break,
                        _ => match bad_checksum::repaired(protocol, input, false) {
                            bad_checksum::Repaired::Frame(request) => {
                                self.requests += 1;
                                self.count_addressed(&request);
                                (self.answer_bad_checksum(protocol, &request), request.len)
                            }
                            bad_checksum::Repaired::Incomplete if !settled => break,
                            _ if checksum => {
                                let outcome = self.refuse(protocol, None, Refusal::BadChecksum);
                                (outcome, input.len().min(start.len().max(1)))
                            }
                            _ => match unsupported::lacking(protocol, input, settled) {
                                unsupported::Lacking::Wait => break,
                                unsupported::Lacking::Frame {
                                    len,
                                    address,
                                    function,
                                } => {
                                    self.requests += 1;
                                    (self.answer_lacking(protocol, address, function), len)
                                }
                                unsupported::Lacking::No => {
                                    match self.unreadable(protocol, input, false) {
                                        Some(unreadable::Unreadable::Frame { len, outcome }) => {
                                            (outcome, len)
                                        }
                                        Some(unreadable::Unreadable::Wait) if !settled => break,
                                        _ => (
                                            Outcome::Silent("framing error"),
                                            if start.is_empty() { input.len() } else { 1 },
                                        ),
                                    }
                                }
                            },
                        },
                    }
                }
            };
            let request: Vec<u8> = input.drain(..used).collect();
            if self.noise || self.unplugged {
                // The line is jammed, or the drive is off it: no reply gets through.
                continue;
            }
            if self.echo {
                // The line returns what the master sent, whether the drive answers or not.
                sent.push(Transmission {
                    bytes: request.clone(),
                    delayed: false,
                    split: None,
                    wait: Duration::ZERO,
                    request_len: request.len(),
                });
            }
            if let Outcome::Reply(bytes) = outcome {
                if let Some(transmission) = self.commit_faults(protocol, &request, bytes) {
                    self.tally.answered += 1;
                    sent.push(transmission);
                }
            }
        }
        sent
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}
