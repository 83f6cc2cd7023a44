//! Request frames the drive cannot read, answered as its manual says where the behaviour
//! model gives the codes (`refusals.<protocol>`): a character no frame of the protocol
//! carries (`bad_character`, the computer link's character error; where the model gives
//! none, `malformed`'s code), a frame that cannot be read otherwise (`malformed`, its
//! protocol error) and a wrong checksum (`bad_checksum`);
//! and once more such frames came in a row than the drive allows, the retries error
//! (`retries_exceeded`, its NAK error). Such a frame ends at the requests' terminator and
//! is answered at the station its station field holds: a frame whose station cannot be
//! read, or that is another station's, gets no reply. A model that gives none of
//! `bad_character`, `malformed` and `retries_exceeded` keeps the drive as before (a bad
//! checksum refused without a station, anything else a framing error).

use super::outcome::{Outcome, Refusal};
use super::VirtualDrive;
use crate::behaviour::Refusals;
use crate::codec::{FrameValues, Roles};
use crate::layout::{Format, FrameLayout, Part, Role};
use crate::protocol::Protocol;

/// What the bytes at the start of the input are, to a drive answering unreadable frames.
#[derive(Debug)]
pub(super) enum Unreadable {
    /// The frame has not ended yet: wait for its terminator.
    Wait,
    /// An unreadable frame of `len` bytes, and the drive's answer to it.
    Frame {
        /// Its length in bytes, terminator included.
        len: usize,
        /// The error reply, or silence.
        outcome: Outcome,
    },
}

impl VirtualDrive {
    /// Reads the unreadable frame at the start of `input` (`checksum`: the decoder found
    /// its checksum wrong) and answers it; `None` when the behaviour model gives no code
    /// for unreadable frames over `protocol`, or the protocol's requests end in no
    /// terminator that ends such a frame.
    pub(super) fn unreadable(
        &mut self,
        protocol: &Protocol,
        input: &[u8],
        checksum: bool,
    ) -> Option<Unreadable> {
        let refusals = self.behaviour()?.refusals(&protocol.id);
        if refusals.bad_character.is_none()
            && refusals.malformed.is_none()
            && refusals.retries_exceeded.is_none()
        {
            return None;
        }
        let request = &protocol.commands.first()?.request;
        // A frame of the master's that is no request (a follow-up) is not one to answer.
        if !request
            .start_bytes()
            .is_some_and(|start| input.starts_with(start))
        {
            return None;
        }
        let end = terminator(request)?;
        let Some(at) = input.windows(end.len()).position(|w| w == end) else {
            let room = input.len() < usize::from(protocol.max_frame_len);
            return room.then_some(Unreadable::Wait);
        };
        let len = at + end.len();
        let frame = &input[..len];
        let refusal = if checksum {
            Refusal::BadChecksum
        } else if carries_only_its_characters(protocol, frame) {
            Refusal::Malformed
        } else {
            Refusal::BadCharacter
        };
        let outcome = self.answer_unreadable(protocol, request, frame, refusal, refusals);
        Some(Unreadable::Frame { len, outcome })
    }

    fn answer_unreadable(
        &mut self,
        protocol: &Protocol,
        request: &FrameLayout,
        frame: &[u8],
        refusal: Refusal,
        refusals: &Refusals,
    ) -> Outcome {
        self.requests += 1;
        if self.unplugged {
            return Outcome::Silent("unplugged from the line");
        }
        if self.starting_up() {
            return Outcome::Silent("starting up after power-on");
        }
        let Some(station) = station_of(request, frame) else {
            return Outcome::Silent("an unreadable frame whose station cannot be read");
        };
        if station != u32::from(self.address) {
            return Outcome::Silent("another station's request");
        }
        self.tally.addressed += 1;
        self.unreadable_in_a_row += 1;
        let code = match refusals.retries_exceeded {
            Some(rule) if f64::from(self.unreadable_in_a_row) > self.amount(rule.after) => {
                Some(rule.code)
            }
            // A manual without a character error counts a wrong character as a syntax
            // error: the malformed frame's code.
            _ if refusal == Refusal::BadCharacter => refusals.bad_character.or(refusals.malformed),
            _ => refusal.code(refusals),
        };
        let Some(code) = code else {
            return Outcome::Silent("the manual gives no error reply for this");
        };
        let Some(layout) = &protocol.error_reply else {
            return Outcome::Silent("the manual gives no error reply for this");
        };
        let mut values = FrameValues::default();
        for name in protocol.default_optional_parts.iter() {
            values.include(layout, &[name]);
        }
        let command = match layout.allowed_commands() {
            [only] => Some(self.shown(protocol, *only)),
            _ => None,
        };
        values.fill(
            layout,
            &Roles {
                address: Some(station),
                command,
                error_code: Some(u32::from(code)),
                ..Roles::default()
            },
        );
        let mut out = vec![0u8; usize::from(protocol.max_frame_len).max(8) + 8];
        match crate::codec::encode(layout, &values, &mut out) {
            Ok(len) => {
                out.truncate(len);
                Outcome::Reply(out)
            }
            Err(_) => Outcome::Silent("the reply cannot be encoded"),
        }
    }
}

/// The bytes of the terminator that ends every request of the layout: its last part, a
/// required literal that is not empty.
fn terminator(request: &FrameLayout) -> Option<&[u8]> {
    match request.parts.last() {
        Some(Part::Literal {
            bytes,
            optional: false,
            ..
        }) if !bytes.is_empty() => Some(bytes),
        _ => None,
    }
}

/// The station a request frame names, read from its station field where only fixed parts
/// (a start character) come before it.
fn station_of(request: &FrameLayout, frame: &[u8]) -> Option<u32> {
    let at = request.index_of(Role::Address)?;
    let offset: usize = request.parts[..at]
        .iter()
        .map(Part::fixed_size)
        .sum::<Option<usize>>()?;
    let Part::Field(field) = &request.parts[at] else {
        return None;
    };
    let radix = match field.format {
        Format::Hex => 16,
        Format::Decimal => 10,
        Format::U8 => return frame.get(offset).map(|b| u32::from(*b)),
        _ => return None,
    };
    let digits = frame.get(offset..offset + usize::from(field.width))?;
    let digits = std::str::from_utf8(digits).ok()?;
    u32::from_str_radix(digits, radix).ok()
}

/// Whether every byte of `frame` is one some request of `protocol` may carry: a byte of a
/// literal, a digit of a digit field, a letter a field allows. A text framing's other
/// characters are its character errors.
fn carries_only_its_characters(protocol: &Protocol, frame: &[u8]) -> bool {
    let mut allowed = [false; 256];
    for command in protocol.commands.iter() {
        for part in command.request.parts.iter() {
            match part {
                Part::Literal { bytes, .. } => {
                    for b in bytes.iter() {
                        allowed[usize::from(*b)] = true;
                    }
                }
                Part::Field(field) => {
                    let digits: &[u8] = match field.format {
                        Format::Hex => b"0123456789ABCDEF",
                        Format::Decimal => b"0123456789",
                        _ => b"",
                    };
                    for b in digits {
                        allowed[usize::from(*b)] = true;
                        if field.fold_case {
                            allowed[usize::from(b.to_ascii_lowercase())] = true;
                        }
                    }
                    for code in field.allowed.iter() {
                        if let Ok(b) = u8::try_from(*code) {
                            allowed[usize::from(b)] = true;
                        }
                    }
                }
                Part::Checksum(spec) if spec.format == Format::Hex => {
                    for b in b"0123456789ABCDEF" {
                        allowed[usize::from(*b)] = true;
                    }
                }
                _ => {}
            }
        }
    }
    frame.iter().all(|b| allowed[usize::from(*b)])
}
