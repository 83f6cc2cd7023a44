//! One command of a protocol ([`CommandSpec`]): its code, layouts, and what it can carry.

use super::address_map::AddressMap;
use super::follow_up::FollowUp;
use super::percent_of::PercentOf;
use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::{Counts, Format, FrameLayout, List, Part, Role, SizedBy, Text};
use std::borrow::Cow;

/// One command of a protocol: its code and the layouts of its request and reply.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CommandSpec {
    /// Code on the wire: a letter (`b'R'`), an AK nibble or a function code. Unused by
    /// layouts without a command field (process telegrams).
    pub code: u32,
    /// What it does.
    pub kind: CommandKind,
    /// Data types it carries; empty means any.
    pub data_types: List<DataType>,
    /// Address space it serves.
    pub space: Space,
    /// Register number to wire number.
    pub address_map: AddressMap,
    /// Request layout.
    pub request: FrameLayout,
    /// Normal reply layout.
    pub reply: FrameLayout,
    /// Codes a normal reply may carry; empty means the request's own code.
    pub reply_codes: List<u32>,
    /// The code an error reply to this command carries, where the error layout allows
    /// several (a Modbus exception to function 03 carries 83h); `None`: the one code the
    /// error layout allows.
    pub error_code: Option<u32>,
    /// Never answered (`reply: none`): a master returns once the frame is on the line (its
    /// wire time and the frame gap) without waiting, and the virtual drive stays silent.
    /// `reply` is then the request's layout, never awaited.
    pub no_reply: bool,
    /// An extra command (`extra: true`): never chosen for a request by its kind alone; a
    /// request uses it only by naming its code
    /// ([`Request::using`](crate::register::Request::using)).
    pub extra: bool,
    /// A lower-case code in the *request* says its sender (a master inverter) has tripped
    /// (`lowercase_means: sender_tripped`), rather than a lower-case reply saying the
    /// replying drive has.
    pub lowercase_means_sender_tripped: bool,
    /// The registers (numbers before the address map) the command may address; empty: any.
    pub registers: List<u16>,
    /// The data is a percentage of another register's value rather than a value in the
    /// addressed register's own unit.
    pub percent_of: Option<PercentOf>,
    /// What the master sends after this command's reply (`None`: nothing): an
    /// acknowledgement when the reply was sound, a request to send it again when it was not
    /// (the Eaton protocol's C and F after a read's E).
    pub follow_up: Option<FollowUp>,
    /// A plain write whose storage is the instruction's (`storage: by_instruction`): a
    /// RAM-only register's write goes to RAM, any other's to RAM and EEPROM (where no
    /// persistence selector governs it). A master sends a persistent write of such a
    /// register with it, and refuses a RAM write of one that it would store in EEPROM.
    pub stored_by_instruction: bool,
}
/// Const constructors for generated code.
impl CommandSpec {
    /// A command on parameters, carrying any data type, with the identity address map and
    /// replies that carry the request's code.
    pub const fn new(
        code: u32,
        kind: CommandKind,
        request: FrameLayout,
        reply: FrameLayout,
    ) -> CommandSpec {
        CommandSpec {
            code,
            kind,
            data_types: Cow::Borrowed(&[]),
            space: Space::Parameter,
            address_map: AddressMap::IDENTITY,
            request,
            reply,
            reply_codes: Cow::Borrowed(&[]),
            error_code: None,
            no_reply: false,
            extra: false,
            lowercase_means_sender_tripped: false,
            registers: Cow::Borrowed(&[]),
            percent_of: None,
            follow_up: None,
            stored_by_instruction: false,
        }
    }

    /// A plain write whose storage is the instruction's (see
    /// [`CommandSpec::stored_by_instruction`]).
    pub const fn with_storage_by_instruction(mut self) -> CommandSpec {
        self.stored_by_instruction = true;
        self
    }

    /// The master answers its replies with `ok` (sound) or `again` (garbled): see
    /// [`CommandSpec::follow_up`].
    pub const fn with_follow_up(mut self, ok: FrameLayout, again: FrameLayout) -> CommandSpec {
        // As in `with_data_types`: nothing to drop in generated code.
        core::mem::forget(self.follow_up.replace(FollowUp { ok, again }));
        self
    }

    /// Never answered (see [`CommandSpec::no_reply`]).
    pub const fn without_reply(mut self) -> CommandSpec {
        self.no_reply = true;
        self
    }

    /// Used only when a request names its code (see [`CommandSpec::extra`]).
    pub const fn as_extra(mut self) -> CommandSpec {
        self.extra = true;
        self
    }

    /// A lower-case code in the request says the sender has tripped.
    pub const fn with_lowercase_sender_tripped(mut self) -> CommandSpec {
        self.lowercase_means_sender_tripped = true;
        self
    }

    /// Addresses only these registers (numbers before the address map).
    pub const fn with_registers(mut self, registers: &'static [u16]) -> CommandSpec {
        // As in `with_data_types`: the old value is borrowed in generated code.
        core::mem::forget(core::mem::replace(
            &mut self.registers,
            Cow::Borrowed(registers),
        ));
        self
    }

    /// Its data is a percentage of the register with code `register`, `step` % per raw step;
    /// a receiving drive applies the first of the conversions `received_by` that holds.
    pub const fn with_percent_of(
        mut self,
        register: &'static str,
        step: f64,
        received_by: &'static [Text],
    ) -> CommandSpec {
        // As in `with_data_types`: nothing to drop in generated code.
        core::mem::forget(self.percent_of.replace(PercentOf {
            register: Cow::Borrowed(register),
            step,
            received_by: Cow::Borrowed(received_by),
        }));
        self
    }

    /// An error reply to it carries this code.
    pub const fn with_error_code(mut self, code: u32) -> CommandSpec {
        self.error_code = Some(code);
        self
    }

    /// Carries only these data types.
    pub const fn with_data_types(mut self, data_types: &'static [DataType]) -> CommandSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(
            &mut self.data_types,
            Cow::Borrowed(data_types),
        ));
        self
    }

    /// Addresses this space.
    pub const fn with_space(mut self, space: Space) -> CommandSpec {
        self.space = space;
        self
    }

    /// Numbers registers on the wire through `address_map`.
    pub const fn with_address_map(mut self, address_map: AddressMap) -> CommandSpec {
        self.address_map = address_map;
        self
    }

    /// A normal reply carries one of these codes.
    pub const fn with_reply_codes(mut self, codes: &'static [u32]) -> CommandSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(
            &mut self.reply_codes,
            Cow::Borrowed(codes),
        ));
        self
    }
}

impl CommandSpec {
    /// Whether it carries `data_type`.
    pub fn carries(&self, data_type: DataType) -> bool {
        self.data_types.is_empty() || self.data_types.contains(&data_type)
    }

    /// The code shown for people: the letter for printable codes, hex otherwise.
    pub fn code_label(&self) -> String {
        code_label(self.code)
    }

    /// Whether `code` names this command: its own code, or, for a command whose lower case
    /// says the sender tripped, its lower-case letter.
    pub fn answers_to(&self, code: u32) -> bool {
        code == self.code
            || (self.lowercase_means_sender_tripped
                && u8::try_from(code).is_ok_and(|b| u32::from(b.to_ascii_uppercase()) == self.code))
    }

    /// Whether it may address register `number` (before the address map).
    pub fn serves_register(&self, number: u16) -> bool {
        self.registers.is_empty() || self.registers.contains(&number)
    }
}

/// Shows a command code: `R` for letters, `03h` for numbers.
pub fn code_label(code: u32) -> String {
    match u8::try_from(code) {
        Ok(byte) if byte.is_ascii_alphabetic() => (byte as char).to_string(),
        _ => format!("{code:02X}h"),
    }
}
/// Whether `command`'s request counts its data (a length part counting `data_size`) and its
/// reply's data field takes its size from a length part: it can read a block of registers.
pub fn command_reads_blocks(command: &CommandSpec) -> bool {
    let counts_data = command
        .request
        .parts
        .iter()
        .any(|part| matches!(part, Part::Length(length) if length.counts == Counts::DataSize));
    let sized_data = command.reply.parts.iter().any(|part| {
        matches!(part, Part::Field(field) if field.role == Role::Data
            && field.sized_by == SizedBy::Length
            && matches!(field.format, Format::UintBe | Format::UintLe))
    });
    counts_data && sized_data
}

/// Whether `command`'s request carries its data in a field sized by a length part (the
/// Modbus 10h quantity and byte count): it can write several consecutive registers.
pub fn command_writes_blocks(command: &CommandSpec) -> bool {
    command.request.parts.iter().any(|part| {
        matches!(part, Part::Field(field) if field.role == Role::Data
            && field.sized_by == SizedBy::Length
            && matches!(field.format, Format::UintBe | Format::UintLe))
    })
}
