//! What a reply must carry to answer one request ([`Expectation`]), and why a frame does
//! not ([`NotAnAnswer`], [`Difference`]).

use super::command::CommandSpec;
use super::decoded::DecodedRequest;
use super::Protocol;
use crate::codec::Roles;
use crate::error::DecodeError;
use crate::layout::Role;
use std::fmt;

/// What a reply must carry to answer one request: [`Protocol::search_reply`] passes over
/// frames that carry something else (another station's reply, a late reply to an earlier
/// request).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Expectation {
    /// The station the request went to (`None`: not checked).
    pub address: Option<u8>,
    /// The register number on the wire (`None`: not checked).
    pub wire_register: Option<u16>,
    /// The array index (`None`: not checked).
    pub index: Option<u16>,
    /// The value a write's reply must report written, where the reply carries one, and
    /// the bits compared (the request's data width); `None`: not checked. A reply reporting
    /// another value answers an earlier write (a late reply), not this one.
    pub data: Option<(u32, u32)>,
    /// The number of data bytes a read's reply must carry, where its layout sizes the data
    /// (a byte count); `None`: not checked. A reply of another size answers another read.
    pub data_size: Option<u8>,
}

impl Expectation {
    /// What a reply must carry to answer `request`, as the master expects it of a request
    /// it built: the same station, register and index, and for a write the value written
    /// (in the bytes the request carried). The reply's data size is not checked.
    pub fn answering(request: &DecodedRequest<'_>) -> Expectation {
        let mask = match request.values.data_size {
            0 | 2 => 0xFFFF,
            bytes @ 1..=3 => (1u32 << (8 * u32::from(bytes))) - 1,
            _ => u32::MAX,
        };
        Expectation {
            address: request.address,
            wire_register: request.wire_register,
            index: request.index,
            data: request
                .command
                .kind
                .reports_data()
                .then_some((request.data, mask)),
            data_size: None,
        }
    }
}

/// Why one frame is not the reply to another ([`Protocol::check_answer`]).
#[derive(Debug, Clone, PartialEq)]
pub enum NotAnAnswer {
    /// The request does not decode.
    Request(DecodeError),
    /// The reply is a whole frame, but carries another value than the request expects.
    Differs(Difference),
    /// The bytes hold no whole reply of the request's command, or more than one frame.
    NotAReply(Option<DecodeError>),
}

impl fmt::Display for NotAnAnswer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotAnAnswer::Request(error) => write!(f, "the request does not decode: {error}"),
            NotAnAnswer::Differs(d) => write!(
                f,
                "the reply carries {} {:X}h where the request expects {:X}h",
                d.role.as_str(),
                d.found,
                d.expected
            ),
            NotAnAnswer::NotAReply(Some(error)) => {
                write!(f, "the bytes are not a reply to the request: {error}")
            }
            NotAnAnswer::NotAReply(None) => {
                f.write_str("the bytes are not exactly one reply to the request")
            }
        }
    }
}

impl Protocol {
    /// Whether `reply` (one whole frame) is the answer to `request` (one whole frame), as
    /// the master judges a reply it receives: the request's reply layout or the error
    /// reply, carrying the station, register, index and written value the request
    /// expects ([`Expectation::answering`]).
    pub fn check_answer(&self, request: &[u8], reply: &[u8]) -> Result<(), NotAnAnswer> {
        let request = self
            .decode_request_exact(request)
            .map_err(NotAnAnswer::Request)?;
        // The decoded command, or one whose request is alike (a read of a byte where the
        // decoder found the read of a word): the reply tells them apart.
        let mut first = None;
        for command in self.alike_commands(request.command) {
            let request = DecodedRequest { command, ..request };
            let expectation = Expectation::answering(&request);
            let search = self.search_reply(command, &expectation, reply);
            let outcome = match (search.found, search.foreign) {
                (Some((frame, 0)), _) if frame.len() == reply.len() => return Ok(()),
                (_, Some(difference)) => NotAnAnswer::Differs(difference),
                _ => NotAnAnswer::NotAReply(search.last_error),
            };
            first.get_or_insert(outcome);
        }
        Err(first.expect("a command is alike to itself"))
    }

    /// `command`, then the other commands of its kind and space whose requests have the
    /// same layout (they differ in the data types they carry, and so in their replies'
    /// data width): a request alone does not say which of them it is.
    pub fn alike_commands<'p>(
        &'p self,
        command: &'p CommandSpec,
    ) -> impl Iterator<Item = &'p CommandSpec> + 'p {
        std::iter::once(command).chain(self.commands.iter().filter(move |other| {
            !std::ptr::eq(*other, command)
                && other.kind == command.kind
                && other.space == command.space
                && other.request.parts == command.request.parts
        }))
    }
}

/// A value a reply carries that is not the one its request expects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Difference {
    /// Which value: [`Role::Address`], [`Role::Register`], [`Role::Index`] or
    /// [`Role::Data`]: for a write, the value its reply reports written (masked as
    /// compared); for a read, the number of data bytes its reply carries.
    pub role: Role,
    /// The value the request expects.
    pub expected: u32,
    /// The value the reply carries.
    pub found: u32,
}

impl Expectation {
    /// The first of `roles` (of a whole frame, or of the parts of one decoded so far) that
    /// differs from what is expected; values a frame does not carry are not compared.
    pub fn difference(&self, roles: &Roles) -> Option<Difference> {
        [
            (Role::Address, self.address.map(u32::from), roles.address),
            (
                Role::Register,
                self.wire_register.map(u32::from),
                roles.register,
            ),
            (Role::Index, self.index.map(u32::from), roles.index),
            (
                Role::Data,
                self.data.map(|(value, mask)| value & mask),
                self.data
                    .and_then(|(_, mask)| roles.data.map(|found| found & mask)),
            ),
        ]
        .into_iter()
        .find_map(|(role, expected, found)| match (expected, found) {
            (Some(expected), Some(found)) if expected != found => Some(Difference {
                role,
                expected,
                found,
            }),
            _ => None,
        })
    }
}
