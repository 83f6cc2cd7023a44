//! A well-formed request with a function the drive does not carry out: answered with the
//! error code the description gives ([`Protocol::unsupported_function`]: DV1 and VF-AS1
//! Modbus, exception 01), else not at all. No command layout reads such a frame, so it is
//! read with the protocol's error-reply layout, whose function may be any and whose error
//! code gives way to the request's data, of whatever size makes a sound frame (a valid
//! checksum and, in text framings, the terminator where it belongs; without a terminator,
//! the bytes up to the line's silence).

use super::outcome::Outcome;
use super::reply::encode_with;
use super::VirtualDrive;
use crate::codec::DecodeStatus;
use crate::layout::{FieldSpec, Format, FrameLayout, FrameValues, Part, Role, Roles, SizedBy};
use crate::protocol::Protocol;
use std::borrow::Cow;

/// What the bytes at the start of the input are to a drive answering functions it lacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Lacking {
    /// Not such a request (or the drive stays silent to them): the bytes are a framing error.
    No,
    /// Such a request may still arrive whole: wait for more bytes or the line's silence.
    Wait,
    /// A whole request of `len` bytes to `address` with the function `function`.
    Frame {
        /// Its length in bytes.
        len: usize,
        /// The station it addresses.
        address: Option<u32>,
        /// Its function (command code).
        function: u32,
    },
}

/// Reads `input` as a request with a function `protocol` does not carry out; `settled`:
/// the line has been silent since its last byte.
pub(super) fn lacking(protocol: &Protocol, input: &[u8], settled: bool) -> Lacking {
    let Some(error) = protocol.error_reply.as_ref() else {
        return Lacking::No;
    };
    if protocol.unsupported_function.is_none() {
        return Lacking::No;
    }
    let (Some(function_at), Some(code_at)) = (
        error.index_of(Role::Command),
        error.index_of(Role::ErrorCode),
    ) else {
        return Lacking::No;
    };
    let terminated = matches!(
        error.parts.last(),
        Some(Part::Literal {
            optional: false,
            ..
        })
    );
    let mut wait = false;
    for size in 0..=input.len() {
        let layout = request_layout(error, function_at, code_at, size);
        match crate::plan::decode(&layout, input) {
            Ok(DecodeStatus::Complete { values, len }) => {
                if !terminated && (!settled || len != input.len()) {
                    // Without a terminator only the line's silence ends a frame.
                    wait |= !settled;
                    continue;
                }
                let Some(function) = values.get(&layout, Role::Command) else {
                    return Lacking::No;
                };
                if protocol.commands.iter().any(|c| c.answers_to(function)) {
                    // A function the drive has, in a frame its layouts refuse.
                    return Lacking::No;
                }
                return Lacking::Frame {
                    len,
                    address: values.get(&layout, Role::Address),
                    function,
                };
            }
            Ok(DecodeStatus::Incomplete) => wait |= !settled || terminated,
            Err(_) => {}
        }
    }
    let room = input.len() < usize::from(protocol.max_frame_len);
    if wait && room && !known_function(protocol, error, function_at, input) {
        Lacking::Wait
    } else {
        Lacking::No
    }
}

/// Whether the bytes so far name a function the drive has (then they are no request of a
/// lacking one, and the usual framing error applies).
fn known_function(
    protocol: &Protocol,
    error: &FrameLayout,
    function_at: usize,
    input: &[u8],
) -> bool {
    // The function's position: the fixed parts before it (start, station).
    let offset: Option<usize> = error.parts[..function_at]
        .iter()
        .map(Part::fixed_size)
        .sum();
    let Some(offset) = offset else {
        return false;
    };
    let head = error.verbatim_ends().0.len();
    let function = match error.encoding {
        crate::layout::Encoding::Binary => input.get(offset).copied(),
        crate::layout::Encoding::HexPairs => {
            let at = head + 2 * offset.saturating_sub(head);
            input
                .get(at..at + 2)
                .and_then(|digits| std::str::from_utf8(digits).ok())
                .and_then(|digits| u8::from_str_radix(digits, 16).ok())
        }
    };
    function.is_some_and(|f| protocol.commands.iter().any(|c| c.answers_to(u32::from(f))))
}

/// The error-reply layout read as a request: any function, and `size` bytes of data in
/// place of the error code.
fn request_layout(
    error: &FrameLayout,
    function_at: usize,
    code_at: usize,
    size: usize,
) -> FrameLayout {
    let mut parts: Vec<Part> = error.parts.to_vec();
    if let Part::Field(field) = &mut parts[function_at] {
        field.allowed = Cow::Borrowed(&[]);
    }
    if size == 0 {
        parts.remove(code_at);
    } else {
        let width = u8::try_from(size).unwrap_or(u8::MAX);
        parts[code_at] = Part::Field(
            FieldSpec::new("data", Role::Data, Format::Bytes, width).with_sized_by(SizedBy::Format),
        );
    }
    FrameLayout {
        name: Cow::Borrowed("unsupported_function_request"),
        parts: Cow::Owned(parts),
        encoding: error.encoding,
        plan: None,
    }
}

impl VirtualDrive {
    /// Answers a request with the function `function`, which the drive lacks, addressed to
    /// `address`: the error reply with [`Protocol::unsupported_function`]'s code and the
    /// function marked as the protocol marks its commands' (Modbus: + 80h); silence for
    /// another station, a broadcast, or a protocol that gives no such reply.
    pub(super) fn answer_lacking(
        &self,
        protocol: &Protocol,
        address: Option<u32>,
        function: u32,
    ) -> Outcome {
        let (Some(code), Some(layout)) = (
            protocol.unsupported_function,
            protocol.lacking_function_reply(),
        ) else {
            return Outcome::Silent("the manual gives no reply to a function the drive lacks");
        };
        if self.starting_up() {
            return Outcome::Silent("starting up after power-on");
        }
        if address.is_some_and(|a| a != u32::from(self.address)) {
            return Outcome::Silent("another station's request");
        }
        let Some(marked) = protocol.error_code_of_function(function) else {
            return Outcome::Silent("the protocol cannot mark the function as an error");
        };
        let mut values = FrameValues::default();
        for name in protocol.default_optional_parts.iter() {
            values.include(&layout, &[name]);
        }
        values.fill(
            &layout,
            &Roles {
                address: address.map(|_| u32::from(self.address)),
                command: Some(marked),
                error_code: Some(u32::from(code)),
                ..Roles::default()
            },
        );
        encode_with(&layout, &values, &[], protocol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_layout_without_the_error_code_reads_only_its_other_parts() {
        let error = FrameLayout {
            name: Cow::Borrowed("exception"),
            parts: Cow::Owned(vec![
                Part::Field(FieldSpec::new("address", Role::Address, Format::U8, 1)),
                Part::Field(FieldSpec::new("function", Role::Command, Format::U8, 1)),
                Part::Field(FieldSpec::new("code", Role::ErrorCode, Format::U8, 1)),
            ]),
            encoding: crate::layout::Encoding::Binary,
            plan: None,
        };
        assert_eq!(request_layout(&error, 1, 2, 0).parts.len(), 2);
        let four = request_layout(&error, 1, 2, 4);
        assert_eq!(four.parts[2].fixed_size(), Some(4));
    }
}
