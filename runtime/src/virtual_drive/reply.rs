//! Encoding the virtual drive's replies with the protocol's layouts: the normal reply to a
//! request (its code, station, register, data, process words and the optional parts the
//! request carried), and the manual's error reply for a refusal.

use super::outcome::{Outcome, Refusal};
use super::VirtualDrive;
use crate::behaviour::Refusals;
use crate::codec::{self, FrameValues, Roles};
use crate::kinds::DataType;
use crate::layout::{FrameLayout, Part, Role};
use crate::protocol::{CommandSpec, DecodedRequest, Protocol};

/// The code a normal reply to `command` carries for a register of `data_type`: the
/// request's own code, or the reply code listed at the data type's position.
pub(super) fn reply_code(command: &CommandSpec, data_type: DataType) -> u32 {
    match command.reply_codes.len() {
        0 => command.code,
        1 => command.reply_codes[0],
        _ => command
            .data_types
            .iter()
            .position(|t| *t == data_type)
            .and_then(|i| command.reply_codes.get(i).copied())
            .unwrap_or(command.reply_codes[0]),
    }
}

/// The code of an error reply to `command`: the code the protocol file gives it, else the
/// one code the error layout allows, else the request's own code.
fn error_code_for(layout: &FrameLayout, command: Option<&CommandSpec>) -> u32 {
    match (
        command.and_then(|c| c.error_code),
        layout.allowed_commands(),
    ) {
        (Some(code), _) => code,
        (None, [only]) => *only,
        _ => command.map_or(0, |c| c.code),
    }
}

impl VirtualDrive {
    /// Lower-case letters while tripped, when the protocol says so.
    pub(super) fn shown(&self, protocol: &Protocol, code: u32) -> u32 {
        if protocol.lowercase_means_tripped && self.motor.trip.is_some() {
            if let Ok(byte) = u8::try_from(code) {
                return u32::from(byte.to_ascii_lowercase());
            }
        }
        code
    }

    /// The error reply for `refusal`, or silence when the protocol has no code for it.
    pub(crate) fn refuse(
        &self,
        protocol: &Protocol,
        request: Option<&DecodedRequest<'_>>,
        refusal: Refusal,
    ) -> Outcome {
        let refusals = self
            .behaviour()
            .map_or(&Refusals::SILENT, |b| b.refusals(&protocol.id));
        match refusal.code(refusals) {
            Some(code) => self.error_reply(protocol, request, code),
            None => Outcome::Silent("the manual gives no error reply for this"),
        }
    }

    /// The protocol's error reply carrying the error code `code`, answering `request` (its
    /// station, register and optional parts) or, for a frame that could not be read, with
    /// the protocol's default optional parts.
    pub(crate) fn error_reply(
        &self,
        protocol: &Protocol,
        request: Option<&DecodedRequest<'_>>,
        code: u16,
    ) -> Outcome {
        let Some(layout) = &protocol.error_reply else {
            return Outcome::Silent("the manual gives no error reply for this");
        };
        let command = error_code_for(layout, request.map(|r| r.command));
        let mut values = FrameValues::default();
        match request {
            Some(request) => mirror_optional_parts(
                &request.command.request,
                &request.values,
                layout,
                &mut values,
            ),
            None => {
                for name in protocol.default_optional_parts.iter() {
                    values.include(layout, &[name]);
                }
            }
        }
        let roles = Roles {
            address: request.and_then(|r| r.address).map(u32::from),
            command: Some(self.shown(protocol, command)),
            register: request.and_then(|r| r.wire_register).map(u32::from),
            index: request.and_then(|r| r.index).map(u32::from),
            error_code: Some(u32::from(code)),
            ..self.process_roles(layout)
        };
        values.fill(layout, &roles);
        encode(layout, &values, protocol)
    }

    /// The normal reply to `request` carrying `data` (`data_size` bytes; 0: as many as
    /// the request's data field).
    pub(super) fn reply(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        data: u32,
        data_size: u8,
    ) -> Outcome {
        self.reply_with(protocol, request, data, data_size, &[])
    }

    /// A normal reply carrying `data`, or the `block` of registers when there is one.
    pub(super) fn reply_with(
        &self,
        protocol: &Protocol,
        request: &DecodedRequest<'_>,
        data: u32,
        data_size: u8,
        block: &[u8],
    ) -> Outcome {
        let command = request.command;
        let layout = &command.reply;
        let mut values = FrameValues {
            data_size: if data_size == 0 {
                request.values.data_size
            } else {
                data_size
            },
            ..FrameValues::default()
        };
        mirror_optional_parts(&command.request, &request.values, layout, &mut values);
        let data_type = match data_size {
            4 => DataType::DoubleWord,
            _ => DataType::Word,
        };
        let roles = Roles {
            address: request.address.map(u32::from),
            command: Some(self.shown(protocol, reply_code(command, data_type))),
            register: request.wire_register.map(u32::from),
            index: request.index.map(u32::from),
            data: Some(data),
            // The decimals of the scale in force (a scale selector's choice, if any).
            decimals: self
                .target_of(request)
                .ok()
                .map(|info| u32::from(self.scaled(info).decimals())),
            ..self.process_roles(layout)
        };
        values.fill(layout, &roles);
        encode_with(layout, &values, block, protocol)
    }

    /// Status word and output as the reply's process words, when the drive has them.
    fn process_roles(&self, layout: &FrameLayout) -> Roles {
        let Some(process) = self.behaviour().and_then(|b| b.process.as_ref()) else {
            return Roles::default();
        };
        if !layout.has(Role::Process1) {
            return Roles::default();
        }
        let word = |id: &str| {
            self.drive
                .register(id)
                .map(|info| self.storage.get(info, 0))
        };
        Roles {
            process_1: word(process.status),
            process_2: word(process.output),
            ..Roles::default()
        }
    }
}

/// Marks present in `reply` the optional parts that were present in the request (a
/// Toshiba-style reply carries the station number, `&SUM` and `)` only if the request did).
pub(super) fn mirror_optional_parts(
    request: &FrameLayout,
    request_values: &FrameValues,
    reply: &FrameLayout,
    values: &mut FrameValues,
) {
    for (index, part) in request.parts.iter().enumerate() {
        let optional = match part {
            Part::Field(field) => field.optional.is_some(),
            Part::Checksum(checksum) => checksum.optional,
            Part::Literal { optional, .. } => *optional,
            _ => false,
        };
        if optional && request_values.parts[index].present {
            values.include(reply, &[part.name()]);
        }
    }
}

/// Whether `layout`'s data field is least significant byte first.
pub(super) fn data_little_endian(layout: &FrameLayout) -> bool {
    layout.parts.iter().any(|part| {
        matches!(part, Part::Field(field) if field.role == Role::Data
            && field.format == crate::layout::Format::UintLe)
    })
}

fn encode(layout: &FrameLayout, values: &FrameValues, protocol: &Protocol) -> Outcome {
    encode_with(layout, values, &[], protocol)
}

/// Encodes a reply, with `payload` for a data field carrying a block of registers.
pub(super) fn encode_with(
    layout: &FrameLayout,
    values: &FrameValues,
    payload: &[u8],
    protocol: &Protocol,
) -> Outcome {
    let mut out = vec![0u8; usize::from(protocol.max_frame_len).max(8) + 8];
    match codec::encode_with_payload(layout, values, payload, &mut out) {
        Ok(len) => {
            out.truncate(len);
            Outcome::Reply(out)
        }
        Err(_) => Outcome::Silent("the reply cannot be encoded"),
    }
}
