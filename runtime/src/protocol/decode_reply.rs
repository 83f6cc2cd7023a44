//! Decoding reply frames: error replies, normal replies by plan or interpreter, and finding
//! one after noise.

use super::command::CommandSpec;
use super::decoded::{Found, Reply};
use super::frame_checks::{no_open_station, settle};
use super::Protocol;
use crate::codec::{DecodeStatus, FrameValues, Roles};
use crate::error::DecodeError;
use crate::layout::{FrameLayout, Role};

impl Protocol {
    /// Decodes a reply frame starting at `bytes[0]`. With `expected` (one of this
    /// protocol's commands, compared by identity), that command's reply layout is tried
    /// first, then the error reply; without it, the error reply and then every command's.
    /// Layouts restrict their command codes, so the order only saves work.
    pub fn decode_reply(
        &self,
        expected: Option<&CommandSpec>,
        bytes: &[u8],
    ) -> Result<Found<Reply<'_>>, DecodeError> {
        if let Some(reply) = expected.and_then(|wanted| self.planned_reply(wanted, bytes)) {
            return Ok(Found::Frame {
                frame: reply,
                skipped: 0,
            });
        }
        let mut best: Option<DecodeError> = None;
        let mut incomplete = false;
        if let Some(wanted) = expected {
            if let Some(command) = self.commands.iter().find(|c| std::ptr::eq(*c, wanted)) {
                if let Some(reply) = settle(
                    self.try_data_reply(command, bytes),
                    &mut best,
                    &mut incomplete,
                ) {
                    return Ok(Found::Frame {
                        frame: reply,
                        skipped: 0,
                    });
                }
            }
        }
        if let Some(reply) = settle(self.try_error_reply(bytes), &mut best, &mut incomplete) {
            return Ok(Found::Frame {
                frame: reply,
                skipped: 0,
            });
        }
        if expected.is_none() {
            // A command that is never answered has no reply to decode.
            for command in self.commands.iter().filter(|c| !c.no_reply) {
                if let Some(reply) = settle(
                    self.try_data_reply(command, bytes),
                    &mut best,
                    &mut incomplete,
                ) {
                    return Ok(Found::Frame {
                        frame: reply,
                        skipped: 0,
                    });
                }
            }
        }
        if incomplete {
            return Ok(Found::Incomplete);
        }
        Err(self.no_match("reply", best))
    }

    /// The error reply, if `bytes` hold one; `Ok(None)` while more bytes are needed;
    /// `Err` also when the bytes are a complete frame of another kind.
    fn try_error_reply(&self, bytes: &[u8]) -> Result<Option<Reply<'_>>, DecodeError> {
        let Some(layout) = &self.error_reply else {
            return Err(DecodeError::NoLayoutMatches {
                protocol: self.id.clone(),
                what: "error reply",
                closest: Box::new(DecodeError::Truncated {
                    layout: self.id.clone(),
                    len: bytes.len(),
                }),
            });
        };
        let error = match self.try_error_layout(layout, bytes, false) {
            Err(error) => error,
            found => return found,
        };
        // A drive answering functions it lacks marks any function, not only those the
        // protocol file's layout lists (the DV1's 81h to a request with function 01).
        match self.lacking_function_reply() {
            Some(any) => self.try_error_layout(&any, bytes, true).map_err(|_| error),
            None => Err(error),
        }
    }

    /// The error reply in `layout`, if `bytes` hold one; `lacking`: only the drive's answer
    /// to a function it lacks ([`Protocol::is_lacking_function_reply`]).
    fn try_error_layout(
        &self,
        layout: &FrameLayout,
        bytes: &[u8],
        lacking: bool,
    ) -> Result<Option<Reply<'_>>, DecodeError> {
        match crate::plan::decode(layout, bytes)? {
            DecodeStatus::Incomplete => Ok(None),
            DecodeStatus::Complete { values, len } => {
                no_open_station(layout, &values)?;
                self.station_in_range(layout, &values)?;
                let lacking_reply = {
                    let code = values.get(layout, Role::Command).unwrap_or(0);
                    let error = values.get(layout, Role::ErrorCode).unwrap_or(0);
                    self.is_lacking_function_reply(code, error)
                };
                if lacking && !lacking_reply {
                    // Any other function stays refused as the file's layout refuses it.
                    return Err(DecodeError::NoLayoutMatches {
                        protocol: self.id.clone(),
                        what: "error reply",
                        closest: Box::new(DecodeError::Truncated {
                            layout: layout.name.clone(),
                            len: bytes.len(),
                        }),
                    });
                }
                if !lacking_reply {
                    self.error_function_known(layout, &values)?;
                }
                Ok(Some(self.error_reply_from(layout, values, len)))
            }
        }
    }

    /// The error reply with these decoded `values`.
    pub(super) fn error_reply_from(
        &self,
        layout: &FrameLayout,
        values: FrameValues,
        len: usize,
    ) -> Reply<'_> {
        let roles = values.roles(layout);
        let code = roles.command.unwrap_or(0);
        let error = roles.error_code.unwrap_or(0) as u16;
        Reply::Error {
            address: roles.address.map(|a| a as u8),
            tripped: self.is_tripped(code),
            code,
            error,
            info: self.error_code(error),
            values,
            len,
        }
    }

    /// `command`'s normal reply, if `bytes` hold one (see [`Protocol::try_error_reply`]).
    fn try_data_reply<'p>(
        &'p self,
        command: &'p CommandSpec,
        bytes: &[u8],
    ) -> Result<Option<Reply<'p>>, DecodeError> {
        match crate::plan::decode(&command.reply, bytes)? {
            DecodeStatus::Incomplete => Ok(None),
            DecodeStatus::Complete { values, len } => {
                self.data_reply_from(command, values, len).map(Some)
            }
        }
    }

    /// The reply of `wanted` (one of this protocol's commands, by identity) at the start of
    /// `bytes`, decoded by its reply layout's plan: `Some` only when the plan decodes a
    /// sound, complete reply, which is then the reply [`Protocol::decode_reply`] returns
    /// (see [`crate::plan`]); `None` leaves the bytes to the interpreter.
    #[inline(always)]
    fn planned_reply(&self, wanted: &CommandSpec, bytes: &[u8]) -> Option<Reply<'_>> {
        // `wanted` must be one of this protocol's commands, as the interpreter requires.
        let command = self.commands.iter().find(|c| std::ptr::eq(*c, wanted))?;
        let plan = command.reply.plan.as_ref()?;
        let frame = plan.decode(&command.reply, bytes)?;
        // What `data_reply_with` makes of it: a plan decodes no open station and no text
        // field, and the roles are gathered.
        let roles = &frame.roles;
        let code = roles.command;
        if code.is_some_and(|code| !self.reply_code_matches(command, code)) {
            return None;
        }
        // A station outside the range: the interpreter says so.
        if roles.address.is_some()
            && self
                .station_in_range(&command.reply, &frame.values)
                .is_err()
        {
            return None;
        }
        Some(self.data_reply(command, roles, frame.values, frame.len, None))
    }

    /// `command`'s normal reply with these decoded `values`; an error when the reply
    /// carries a code the command does not answer with.
    pub(super) fn data_reply_from<'p>(
        &'p self,
        command: &'p CommandSpec,
        values: FrameValues,
        len: usize,
    ) -> Result<Reply<'p>, DecodeError> {
        let layout = &command.reply;
        no_open_station(layout, &values)?;
        self.station_in_range(layout, &values)?;
        let roles = values.roles(layout);
        let code = roles.command;
        if let Some(code) = code.filter(|code| !self.reply_code_matches(command, *code)) {
            return Err(DecodeError::NotAllowed {
                layout: layout.name.clone(),
                part: "command".into(),
                offset: 0,
                value: code,
                format: crate::layout::Format::U8,
            });
        }
        let text = layout.index_of(Role::Text).map(|index| {
            let slot = values.parts[index];
            (slot.value as usize, usize::from(slot.width))
        });
        Ok(self.data_reply(command, &roles, values, len, text))
    }

    /// The [`Reply::Data`] of `command` from a sound frame's `roles` and `values`, its
    /// length and its text field; what the plan and the interpreter both return.
    #[inline(always)]
    fn data_reply<'p>(
        &self,
        command: &'p CommandSpec,
        roles: &Roles,
        values: FrameValues,
        len: usize,
        text: Option<(usize, usize)>,
    ) -> Reply<'p> {
        let code = roles.command;
        Reply::Data {
            command,
            code: code.unwrap_or(command.code),
            address: roles.address.map(|a| a as u8),
            tripped: code.is_some_and(|code| self.is_tripped(code)),
            wire_register: roles.register.map(|r| r as u16),
            index: roles.index.map(|i| i as u16),
            // A block of registers is no number: its bytes are read from the frame.
            data: if values.data_size > 4 {
                0
            } else {
                roles.data.unwrap_or(0)
            },
            process: match (roles.process_1, roles.process_2) {
                (Some(first), Some(second)) => Some([first as u16, second as u16]),
                _ => None,
            },
            text,
            values,
            len,
        }
    }

    fn is_tripped(&self, code: u32) -> bool {
        self.lowercase_means_tripped && u8::try_from(code).is_ok_and(|b| b.is_ascii_lowercase())
    }

    fn reply_code_matches(&self, command: &CommandSpec, code: u32) -> bool {
        let folded = if self.lowercase_means_tripped {
            u8::try_from(code).map_or(code, |b| u32::from(b.to_ascii_uppercase()))
        } else {
            code
        };
        if command.reply_codes.is_empty() {
            folded == command.code
        } else {
            command.reply_codes.contains(&folded)
        }
    }

    /// Decodes exactly one reply frame: `bytes` must hold the whole frame and nothing else.
    pub fn decode_reply_exact(
        &self,
        expected: Option<&CommandSpec>,
        bytes: &[u8],
    ) -> Result<Reply<'_>, DecodeError> {
        match self.decode_reply(expected, bytes)? {
            Found::Frame { frame, .. } => self.exact(frame.len(), bytes.len()).map(|()| frame),
            Found::Incomplete => Err(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }),
        }
    }

    /// Looks for a reply in `bytes`, skipping noise before a start sequence: each
    /// occurrence of a layout's start bytes is tried in turn. Protocols without a start
    /// sequence (Modbus RTU) are decoded from the first byte.
    pub fn find_reply(
        &self,
        expected: Option<&CommandSpec>,
        bytes: &[u8],
    ) -> Result<Found<Reply<'_>>, DecodeError> {
        // The expected reply at offset 0 is what the search below finds first (a frame
        // may start there: the reply's own start bytes are there, or it has none).
        if let Some(reply) = expected.and_then(|wanted| self.planned_reply(wanted, bytes)) {
            return Ok(Found::Frame {
                frame: reply,
                skipped: 0,
            });
        }
        let mut last_error = None;
        let mut incomplete = false;
        for offset in 0..bytes.len() {
            let may_start = self.reply_may_start(&bytes[offset..]);
            if may_start == Some(false) {
                continue;
            }
            match self.decode_reply(expected, &bytes[offset..]) {
                Ok(Found::Frame { frame, .. }) => {
                    return Ok(Found::Frame {
                        frame,
                        skipped: offset,
                    })
                }
                Ok(Found::Incomplete) => incomplete = true,
                Err(error) => last_error = Some(error),
            }
            if may_start.is_none() {
                break;
            }
        }
        match (incomplete, last_error) {
            (false, Some(error)) => Err(error),
            _ => Ok(Found::Incomplete),
        }
    }

    /// Whether a reply may start at `bytes[0]`: some reply layout (a command's, or the
    /// error reply) begins with a start literal the bytes begin with. Protocols whose
    /// replies start differently (ACK, NAK, STX) are covered by every one of them. `None`
    /// when some reply layout has no start literal (Modbus RTU): a frame may start anywhere.
    pub fn reply_may_start(&self, bytes: &[u8]) -> Option<bool> {
        let mut any = false;
        let replies = self.commands.iter().map(|c| &c.reply);
        for layout in replies.chain(self.error_reply.as_ref()) {
            any |= bytes.starts_with(layout.start_bytes()?);
        }
        Some(any)
    }
}
