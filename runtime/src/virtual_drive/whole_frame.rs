//! Answering one whole request frame handed over as it is, with no bytes before or after
//! it (as `vfd check` and tests hand a manual's example): read in the protocol's variant in
//! force, a bad checksum answered as on the line.

use super::bad_checksum;
use super::outcome::{Outcome, Refusal};
use super::unreadable;
use super::VirtualDrive;
use crate::error::DecodeErrorKind;
use crate::protocol::Protocol;

impl VirtualDrive {
    /// Answers one whole request frame (no bytes before or after it). Over a protocol with
    /// variants, the frame is read in the variant the drive's selector register selects;
    /// a frame in another variant's form gets the description's mismatch error.
    pub fn respond(&mut self, protocol: &Protocol, frame: &[u8]) -> Outcome {
        let own = self.in_force(protocol).own;
        if let Some((len, again)) = self.take_follow_up(own.as_ref(), frame) {
            if len == frame.len() {
                return match again {
                    Some(reply) => Outcome::Reply(reply),
                    None => Outcome::Silent("the master's follow-up to a reply"),
                };
            }
        }
        let outcome = self.respond_to_request(protocol, frame);
        let code = own.decode_request_exact(frame).ok().map(|r| r.command.code);
        if let Some(code) = code {
            let reply = match &outcome {
                Outcome::Reply(bytes) => Some(bytes.as_slice()),
                Outcome::Silent(_) => None,
            };
            self.note_reply(protocol, code, reply);
        }
        outcome
    }

    fn respond_to_request(&mut self, protocol: &Protocol, frame: &[u8]) -> Outcome {
        let variants = self.in_force(protocol);
        let protocol = variants.own.as_ref();
        match protocol.decode_request_exact(frame) {
            Ok(request) if self.unplugged => {
                self.requests += 1;
                self.count_addressed(&request);
                Outcome::Silent("unplugged from the line")
            }
            Ok(_) if self.starting_up() => {
                self.requests += 1;
                Outcome::Silent("starting up after power-on")
            }
            Ok(request) => {
                self.requests += 1;
                self.count_addressed(&request);
                let outcome = self.answer(protocol, &request);
                self.follow_station_register();
                if matches!(outcome, Outcome::Reply(_)) {
                    self.tally.answered += 1;
                }
                outcome
            }
            Err(error) => {
                let other = variants
                    .others
                    .iter()
                    .find_map(|other| other.decode_request_exact(frame).ok());
                if let Some(request) = other {
                    self.requests += 1;
                    return self.answer_mismatch(protocol, &request, variants.mismatch);
                }
                // As on the line (`take_frames`): a drive whose manual gives codes for
                // unreadable frames reads a bad checksum's station from the frame and counts
                // them in a row; otherwise the frame is read with its checksum put right;
                // a frame unreadable either way gets the malformed frame's code.
                let checksum = error.kind() == DecodeErrorKind::ChecksumMismatch;
                let whole = |found: Option<unreadable::Unreadable>| match found {
                    Some(unreadable::Unreadable::Frame { len, outcome }) if len == frame.len() => {
                        Some(outcome)
                    }
                    _ => None,
                };
                if checksum {
                    if let Some(outcome) = whole(self.unreadable(protocol, frame, true)) {
                        return outcome;
                    }
                }
                match bad_checksum::repaired(protocol, frame, true) {
                    bad_checksum::Repaired::Frame(request) => {
                        self.requests += 1;
                        self.count_addressed(&request);
                        self.answer_bad_checksum(protocol, &request)
                    }
                    _ if checksum => self.refuse(protocol, None, Refusal::BadChecksum),
                    _ => whole(self.unreadable(protocol, frame, false))
                        .unwrap_or(Outcome::Silent("not a request frame")),
                }
            }
        }
    }
}
