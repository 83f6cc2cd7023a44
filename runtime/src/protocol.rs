//! A protocol is a set of frame layouts tied to commands, plus the error-reply layout, the
//! drive's error-code table and any steps a request needs first; this module encodes
//! requests and decodes replies with it.

use crate::broadcast::{self as broadcasts, Broadcast, BroadcastRule};
use crate::codec::{self, DecodeStatus, FrameValues, Progress, Roles, Words};
use crate::error::{DecodeError, EncodeError};
pub use crate::info::ErrorCodeInfo;
pub use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::{Counts, Format, FrameLayout, List, Part, Role, SizedBy, Text};
use crate::register::DriveRequest;
pub use crate::register::Request;
use crate::serial::LinkTiming;
pub use crate::variant::{Variant, VariantLiteral, VariantSelector, VariantValue, Variants};
use std::borrow::Cow;
use std::fmt;
use std::marker::PhantomData;

/// How a command turns a register number into the number on the wire:
/// `wire = number * multiply + offset` (Modbus holding register = parameter x 10 - 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AddressMap {
    /// Factor.
    pub multiply: u16,
    /// Offset added after multiplying.
    pub offset: i32,
}

impl AddressMap {
    /// The identity map.
    pub const IDENTITY: AddressMap = AddressMap {
        multiply: 1,
        offset: 0,
    };

    /// The wire number of `number`, if it fits 16 bits.
    pub fn to_wire(self, number: u16) -> Option<u16> {
        u16::try_from(i64::from(number) * i64::from(self.multiply) + i64::from(self.offset)).ok()
    }

    /// The register number of a wire number, if it maps back exactly.
    pub fn from_wire(self, wire: u16) -> Option<u16> {
        let shifted = i64::from(wire) - i64::from(self.offset);
        let multiply = i64::from(self.multiply.max(1));
        (shifted % multiply == 0)
            .then(|| u16::try_from(shifted / multiply).ok())
            .flatten()
    }
}

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
    /// request uses it only by naming its code ([`Request::using`]).
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
}

/// The master's answer to a reply (`follow_up:` of a protocol file's command): `ok` after a
/// sound reply (the drive does nothing more), `again` after a garbled one (the drive sends
/// the same reply again). Neither is answered by a new frame of its own.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FollowUp {
    /// Sent after a sound reply.
    pub ok: FrameLayout,
    /// Sent after a garbled reply, to have it sent again.
    pub again: FrameLayout,
}

impl FollowUp {
    /// The layout for a sound (`true`) or a garbled (`false`) reply.
    pub fn layout(&self, sound: bool) -> &FrameLayout {
        if sound {
            &self.ok
        } else {
            &self.again
        }
    }

    /// Encodes the follow-up for station `address` into `out`; returns its length. A field
    /// of role `command` carries the one code its layout allows (the NAK character).
    pub fn encode(
        &self,
        sound: bool,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let layout = self.layout(sound);
        let mut values = FrameValues::default();
        let roles = Roles {
            address: address.map(u32::from),
            command: layout.allowed_commands().first().copied(),
            ..Roles::default()
        };
        values.fill(layout, &roles);
        codec::encode(layout, &values, out)
    }

    /// Whether `bytes` begin with this follow-up: `true` for the acknowledgement, `false`
    /// for the request to send again, with the station it names and its length.
    pub fn recognise(&self, bytes: &[u8]) -> Option<(bool, Option<u8>, usize)> {
        [true, false].into_iter().find_map(|sound| {
            let layout = self.layout(sound);
            match crate::plan::decode(layout, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => Some((
                    sound,
                    values
                        .get(layout, Role::Address)
                        .and_then(|a| u8::try_from(a).ok()),
                    len,
                )),
                _ => None,
            }
        })
    }
}

/// Parameters reached through pages (`pages:` of a drive's protocol entry): a request
/// carries a parameter's offset within its page, and the page is chosen beforehand by
/// writing its number to a page register, which the drive keeps until it is changed or the
/// drive is reset. The DV1's Eaton protocol: P mode pages 0-4 of 100 parameters each, group
/// mode pages 100 + group.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Paging {
    /// The page register's number in read requests (`None`: it cannot be read back).
    pub select_read: Option<u16>,
    /// The page register's number in write requests.
    pub select_write: u16,
    /// The page register's data type: the page switch goes out with the write command that
    /// carries it (a byte command's narrower layout where the drive takes two data digits),
    /// and the virtual drive answers a read of the page with the read that carries it.
    pub select_data_type: DataType,
    /// The ranges of register numbers laid out on pages.
    pub ranges: List<PageRange>,
    /// Registers whose write makes the drive forget its page (a reset): the master selects
    /// the page again before the next paged access.
    pub forgotten_after: List<u16>,
    /// The page a drive is on after power-on or a reset (the virtual drive's start).
    pub initial: u16,
}

/// Register numbers `first..=last`, laid out `size` to a page from page `first_page` on:
/// register `first + k` is at offset `k % size` of page `first_page + k / size`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PageRange {
    /// Lowest register number of the range.
    pub first: u16,
    /// Highest register number of the range.
    pub last: u16,
    /// Registers per page.
    pub size: u16,
    /// The page of `first`.
    pub first_page: u16,
    /// Pages the range skips: no register of the range lies on them (the DV1 has no pages
    /// for parameter groups 09, 12 and 14).
    pub missing: List<u16>,
}

impl PageRange {
    fn locate(&self, number: u16) -> Option<(u16, u16)> {
        if number < self.first || number > self.last || self.size == 0 {
            return None;
        }
        let k = number - self.first;
        let page = self.first_page.checked_add(k / self.size)?;
        (!self.missing.contains(&page)).then_some((page, k % self.size))
    }

    fn register(&self, page: u16, offset: u16) -> Option<u16> {
        if offset >= self.size || page < self.first_page || self.missing.contains(&page) {
            return None;
        }
        let k = u32::from(page - self.first_page) * u32::from(self.size) + u32::from(offset);
        let number = u32::from(self.first) + k;
        (number <= u32::from(self.last)).then_some(number as u16)
    }
}

impl Paging {
    /// The page and the offset within it of register `number`; `None`: it is not paged.
    pub fn locate(&self, number: u16) -> Option<(u16, u16)> {
        self.ranges.iter().find_map(|range| range.locate(number))
    }

    /// The register at `offset` of `page`, if one lies there.
    pub fn register(&self, page: u16, offset: u16) -> Option<u16> {
        self.ranges
            .iter()
            .find_map(|range| range.register(page, offset))
    }

    /// Whether `page` exists (some range lays registers on it).
    pub fn has_page(&self, page: u16) -> bool {
        self.ranges
            .iter()
            .any(|range| range.size > 0 && range.register(page, 0).is_some())
    }

    /// The most registers one page holds: the offsets a request can carry are below it.
    pub fn page_size(&self) -> u16 {
        self.ranges.iter().map(|r| r.size).max().unwrap_or(0)
    }
}

/// A command's data as a percentage of another register's value (the Toshiba S command
/// carries a frequency in 0.01 % of the maximum frequency): `raw = value / reference x 100
/// / step`, truncated, and back `value = raw x step / 100 x reference`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PercentOf {
    /// Code of the register whose value is 100 %.
    pub register: Text,
    /// The percentage one raw step stands for (0.01).
    pub step: f64,
    /// Conversions (ids of the drive's `conversions`) a receiving drive turns the raw
    /// percentage into its register's value with, the first that applies; empty: the plain
    /// proportion ([`PercentOf::from_raw`]).
    pub received_by: List<Text>,
}

impl PercentOf {
    /// The raw word for `value` when `reference` (the register's value in the same unit) is
    /// 100 %, truncated toward zero as the manuals do; `None` when the reference is not
    /// positive or the result does not fit 16 bits (no other range is checked).
    pub fn to_raw(&self, value: f64, reference: f64) -> Option<u32> {
        if !(reference > 0.0 && self.step > 0.0 && value.is_finite()) {
            return None;
        }
        // A hair above, so that 50 / 100 % at 0.01 % steps is 5000, not 4999.
        let raw = (value / reference * 100.0 / self.step + 1e-9).floor();
        (0.0..=f64::from(u16::MAX))
            .contains(&raw)
            .then_some(raw as u32)
    }

    /// The value `raw` stands for when `reference` is 100 % (not truncated).
    pub fn from_raw(&self, raw: u32, reference: f64) -> f64 {
        f64::from(raw) * self.step / 100.0 * reference
    }
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
        }
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

/// Something a request needs done first, in another exchange.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PreStep {
    /// Before an indexed access, write the index to this wire register (FC Modbus: 0008h).
    Index {
        /// Wire register that selects the index.
        register: u16,
    },
    /// Before a parameter write, select RAM or RAM + EEPROM by writing `ram` or
    /// `persistent` to `register` of `space` (FC Modbus: coil 65, 0000h or FF00h). Coil
    /// writes (process data) skip it.
    Persistence {
        /// Address space of the selector.
        space: Space,
        /// Selector register (number before mapping).
        register: u16,
        /// Data type of the selector.
        data_type: DataType,
        /// Value selecting RAM only.
        ram: u32,
        /// Value selecting RAM and EEPROM.
        persistent: u32,
    },
}

/// A protocol of drive `D` (a generated drive module's `Drive` marker): it encodes only
/// requests for that drive's registers, and a [`crate::transaction::Master`] built on it
/// sends only those. It dereferences to the untyped [`Protocol`] for everything else
/// (decoding, and tools that work with any drive).
pub struct DriveProtocol<D: 'static> {
    protocol: &'static Protocol,
    drive: PhantomData<fn() -> D>,
}

impl<D: 'static> DriveProtocol<D> {
    /// `protocol`, as drive `D` speaks it.
    pub const fn new(protocol: &'static Protocol) -> Self {
        DriveProtocol {
            protocol,
            drive: PhantomData,
        }
    }

    /// The untyped protocol.
    pub const fn protocol(&self) -> &'static Protocol {
        self.protocol
    }

    /// The same protocol in its variant `id` (see [`Protocol::variant`]); `None`: no such
    /// variant.
    pub fn variant(&self, id: &str) -> Option<DriveProtocol<D>> {
        self.protocol.variant(id).map(DriveProtocol::new)
    }

    /// Encodes a request for one of the drive's registers; see [`Protocol::encode_request`].
    pub fn encode_request(
        &self,
        request: &DriveRequest<D>,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        self.protocol.encode_request(request, address, out)
    }
}

impl<D: 'static> std::ops::Deref for DriveProtocol<D> {
    type Target = Protocol;
    fn deref(&self) -> &Protocol {
        self.protocol
    }
}

impl<D: 'static> fmt::Debug for DriveProtocol<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.protocol.fmt(f)
    }
}

/// A protocol as one drive speaks it.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Protocol {
    /// Identifier within the drive (`ascii`).
    pub id: Text,
    /// Human name.
    pub name: Text,
    /// Commands.
    pub commands: List<CommandSpec>,
    /// Layout of error replies, if the protocol has them.
    pub error_reply: Option<FrameLayout>,
    /// A lower-case command letter in a reply means the drive is tripped.
    pub lowercase_means_tripped: bool,
    /// Longest frame, in bytes, used to size buffers and derive reply timeouts.
    pub max_frame_len: u16,
    /// Lowest and highest station address.
    pub address_range: (u8, u8),
    /// Optional parts (by name) included in requests unless the caller says otherwise.
    pub default_optional_parts: List<Text>,
    /// The drive's error codes.
    pub error_codes: List<ErrorCodeInfo>,
    /// Steps some requests need first.
    pub pre_steps: List<PreStep>,
    /// Process words sent with requests that carry them when the caller gives none
    /// (FC: a control word with "data valid" clear, so the drive ignores it).
    pub default_process: [u16; 2],
    /// Silence between frames, in character times (Modbus RTU: 3.5); 0 for none.
    pub frame_gap_chars: f32,
    /// The most 16-bit registers one read may carry (Modbus 03: 125); 1 when every read
    /// carries one register. Above 1, a read command whose request counts its data
    /// (a length part counting `data_size`) reads consecutive registers in one exchange:
    /// see [`Protocol::block_read_command`] and
    /// [`crate::transaction::Master::read_words`].
    pub max_words_per_read: u16,
    /// The most 16-bit registers one write may carry (Modbus 10h: 123; the DV1: 12); 1 when
    /// every write carries one register (of its own width). Above 1, a write command whose
    /// request's data field is sized by a length part writes consecutive registers in one
    /// exchange: see [`Protocol::block_write_command`] and
    /// [`crate::transaction::Master::write_words`].
    pub max_words_per_write: u16,
    /// A read or write of several registers is carried out for the registers that can be,
    /// and refused only when none can (the DV1: "若有 1 个及以上可以操作就不视为错误"): a
    /// register that does not exist reads as 0, one that does not exist or refuses its value
    /// is left as it is. `false`: one such register refuses the whole request.
    pub partial_blocks: bool,
    /// What a block-transfer command ([`CommandKind::Block`]) writes and reads on this
    /// drive; `None`: the drive has no block transfer (and no such command).
    pub block: Option<BlockSpec>,
    /// The drive's timing rules for this protocol beyond `frame_gap_chars` (gap floor in
    /// milliseconds, inner-gap limit, bytes before the start, reply delay register).
    pub timing: LinkTiming,
    /// Which commands the drive carries out when broadcast and which station answers;
    /// `None`: the drive takes no broadcasts over this protocol (its address field's
    /// broadcast encodings, if any, are not used).
    pub broadcast: Option<BroadcastRule>,
    /// Registers with their own numbers on the wire in this protocol, by direction (the
    /// Eaton command codes of the DV1's 10xxh registers); the others go through their
    /// command's address map ([`Protocol::to_wire`]).
    pub wire_numbers: List<WireNumber>,
    /// Parameters reached through pages on this protocol (`None`: no pages): a request
    /// carries a paged register's offset in its page, after the page is selected
    /// ([`Protocol::to_wire`], [`crate::transaction::Master::transact`]).
    pub paging: Option<Paging>,
    /// The drive's register choosing where parameter writes go (the description's
    /// `persistence:`, the same in every protocol of the drive); `None`: the command's kind
    /// says it (or a [`PreStep::Persistence`] does).
    pub persistence: Option<PersistenceSelector>,
    /// The protocol's variants (other bytes for some literal parts, such as the
    /// terminator) and which one this protocol is in; `None`: it has none. See
    /// [`Protocol::variant`].
    pub variants: Option<Variants>,
    /// The error code the drive answers a well-formed request with when its function
    /// (command code) is not one of [`Protocol::commands`] (DV1 and VF-AS1 Modbus:
    /// exception 01); the reply carries the request's function marked as every command's
    /// error code marks it ([`Protocol::error_code_of_function`]). `None`: the manual does
    /// not say, and the virtual drive stays silent.
    pub unsupported_function: Option<u16>,
}

/// A register of the drive whose value chooses where parameter writes over the link go
/// (DV1 07-11 / P.34: 0 RAM and EEPROM, 1 RAM only). Writing the selector is itself a
/// parameter write, governed by the value it has before the write.
///
/// [`crate::transaction::Master`] remembers the selector's value and sets it before a write
/// it governs: to `ram` before a RAM write (which stores `ram` in the EEPROM too when the
/// selector held `persistent`), and around a persistent write to `persistent` and back
/// (the value written back is stored in the EEPROM, which held it already). See
/// drives/README.md, "Persistence chosen by a register".
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PersistenceSelector {
    /// The selector's register number (before the address map).
    pub register: u16,
    /// The selector's address space.
    pub space: Space,
    /// The selector's data type.
    pub data_type: DataType,
    /// The value with which parameter writes go to RAM only.
    pub ram: u32,
    /// The value with which parameter writes go to RAM and EEPROM.
    pub persistent: u32,
    /// The register numbers (first, last) whose writes it governs; empty: every parameter.
    pub registers: List<(u16, u16)>,
}

impl PersistenceSelector {
    /// Whether a write of register `register` in `space` goes where the selector says:
    /// a parameter (not RAM only) among the governed numbers.
    pub fn governs(&self, space: Space, register: u16, ram_only: bool) -> bool {
        space == Space::Parameter
            && !ram_only
            && (self.registers.is_empty()
                || self
                    .registers
                    .iter()
                    .any(|&(from, to)| (from..=to).contains(&register)))
    }

    /// Whether `request` is a write the selector governs: a write of a described register
    /// (a request built from its [`crate::info::RegisterInfo`]) that it governs. Requests
    /// by number alone ([`Request::raw`]) go as they are: their number may not be a
    /// parameter at all (the Eaton page switch 7Fh is P.127's number).
    pub fn governs_request(&self, request: &Request) -> bool {
        request.kind.is_write()
            && request
                .info
                .is_some_and(|info| self.governs(request.space, request.register, info.ram_only))
    }

    /// Whether `request` is addressed to the selector itself.
    pub fn is_selector(&self, request: &Request) -> bool {
        request.space == self.space && request.register == self.register
    }

    /// A request writing `value` to the selector.
    pub fn write(&self, value: u32) -> Request {
        Request::raw(CommandKind::WriteRam, self.register, value)
            .in_space(self.space)
            .with_data_type(self.data_type)
    }

    /// A request reading the selector.
    pub fn read(&self) -> Request {
        Request::raw(CommandKind::Read, self.register, 0)
            .in_space(self.space)
            .with_data_type(self.data_type)
    }
}

/// A register's own numbers on the wire in one protocol, for reading and for writing.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct WireNumber {
    /// The register's number in the drive description.
    pub register: u16,
    /// Its number in read requests; `None`: it cannot be read over this protocol.
    pub read: Option<u16>,
    /// Its number in write requests; `None`: it cannot be written over this protocol.
    pub write: Option<u16>,
    /// When several registers share its write number (the DV1's parameter clears 1102h-1106h
    /// are all Eaton HFC), the data values that pick this one; empty otherwise.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "<[u32]>::is_empty"))]
    pub data: List<u32>,
}

/// Room for the probe frame [`Protocol::default_address`] encodes.
const MAX_FRAME_PROBE: usize = 256;

impl Protocol {
    /// The number `command` carries on the wire for register `number`: the register's own
    /// number in this protocol ([`Protocol::wire_numbers`]) for the command's direction,
    /// else the command's address map.
    /// A paged register ([`Protocol::paging`]) carries its offset in its page through the
    /// address map: the frame is right only once its page is selected.
    pub fn to_wire(&self, command: &CommandSpec, number: u16) -> Option<u16> {
        match self.wire_numbers.iter().find(|w| w.register == number) {
            Some(own) if command.kind.is_write() => own.write,
            Some(own) => own.read,
            None => command
                .address_map
                .to_wire(self.page_of(number).map_or(number, |(_, offset)| offset)),
        }
    }

    /// The page and offset of register `number` on this protocol, if it is paged (a
    /// register with its own wire numbers never is).
    pub fn page_of(&self, number: u16) -> Option<(u16, u16)> {
        let paging = self.paging.as_ref()?;
        if self.wire_numbers.iter().any(|w| w.register == number) {
            return None;
        }
        paging.locate(number)
    }

    /// The register a number on the wire stands for in a request of `command` carrying
    /// `data`: the register whose own number it is for that direction (of several sharing
    /// a write number, the one whose values include the data), else the command's address
    /// map undone.
    pub fn from_wire(&self, command: &CommandSpec, wire: u16, data: Option<u32>) -> Option<u16> {
        let mut own = self.wire_numbers.iter().filter(|w| {
            if command.kind.is_write() {
                w.write == Some(wire)
            } else {
                w.read == Some(wire)
            }
        });
        let first = own.next();
        let picked = data.and_then(|data| {
            first
                .into_iter()
                .chain(own)
                .find(|w| w.data.contains(&data))
        });
        match picked.or(first) {
            Some(own) => Some(own.register),
            // On a protocol with pages, any other number is an offset in a page (or the
            // page register): the frame alone does not say which register it is.
            None if self.paging.is_some() => None,
            None => command.address_map.from_wire(wire),
        }
    }
}

/// Variants built from generated protocols, kept for the life of the process like the
/// statics they come from: (the protocol built from, variant index, the variant).
type Derived = Vec<(&'static Protocol, usize, &'static Protocol)>;
static DERIVED: std::sync::Mutex<Derived> = std::sync::Mutex::new(Vec::new());

impl Protocol {
    /// This protocol with no plan in any layout: every frame goes through the interpreter,
    /// as for a layout no plan covers. For comparing the two paths (the differential tests,
    /// the `plan_agreement` fuzz target, the codec benchmark); a master or tool has no
    /// reason to use it.
    pub fn without_plans(&self) -> Protocol {
        let commands = self
            .commands
            .iter()
            .map(|command| CommandSpec {
                request: command.request.clone().unplanned(),
                reply: command.reply.clone().unplanned(),
                follow_up: command.follow_up.as_ref().map(|f| FollowUp {
                    ok: f.ok.clone().unplanned(),
                    again: f.again.clone().unplanned(),
                }),
                ..command.clone()
            })
            .collect();
        Protocol {
            commands: Cow::Owned(commands),
            error_reply: self.error_reply.clone().map(FrameLayout::unplanned),
            ..self.clone()
        }
    }

    /// The code an error reply carries for a request with the function `code`, when every
    /// command's error code is its own code moved by one offset (Modbus: function + 80h),
    /// which then holds for any function; `None` when the commands have no error codes or
    /// no common offset.
    pub fn error_code_of_function(&self, code: u32) -> Option<u32> {
        let mut offsets = self.commands.iter().map(|command| {
            command
                .error_code
                .map(|error| error.wrapping_sub(command.code))
        });
        let first = offsets.next()??;
        offsets
            .all(|offset| offset == Some(first))
            .then(|| code.wrapping_add(first))
    }

    /// The id of the variant this protocol is in (`None`: the protocol has no variants).
    pub fn variant_id(&self) -> Option<&str> {
        self.variants.as_ref()?.current().map(|v| v.id.as_ref())
    }

    /// This protocol in the variant at `index` of [`Protocol::variants`] (its own when it
    /// is already in it): every literal part the variant lists gets the variant's bytes,
    /// in every command's layouts (its follow-ups included) and in the error reply.
    /// `None`: no such variant.
    pub fn in_variant(&self, index: usize) -> Option<Protocol> {
        let variants = self.variants.as_ref()?;
        let variant = variants.choices.get(index)?;
        let commands = self
            .commands
            .iter()
            .map(|command| CommandSpec {
                request: variant.apply(&command.request),
                reply: variant.apply(&command.reply),
                follow_up: command.follow_up.as_ref().map(|f| FollowUp {
                    ok: variant.apply(&f.ok),
                    again: variant.apply(&f.again),
                }),
                ..command.clone()
            })
            .collect();
        Some(Protocol {
            commands: Cow::Owned(commands),
            error_reply: self.error_reply.as_ref().map(|l| variant.apply(l)),
            variants: Some(Variants {
                current: u8::try_from(index).ok()?,
                ..variants.clone()
            }),
            ..self.clone()
        })
    }

    /// This protocol in its variant `id` (`cr_lf`), for a master or tool told which one
    /// the drive is set to; `None`: no such variant. The variant of a generated protocol
    /// is built once, on first use, and kept for the life of the process, like the static
    /// it comes from.
    pub fn variant(&'static self, id: &str) -> Option<&'static Protocol> {
        let index = self.variants.as_ref()?.index_of(id)?;
        Some(self.variant_at(index))
    }

    /// [`Protocol::variant`], or the typed reason there is none (naming the variants
    /// there are).
    pub fn variant_or_error(&'static self, id: &str) -> Result<&'static Protocol, EncodeError> {
        self.variant(id).ok_or_else(|| EncodeError::NoSuchVariant {
            protocol: self.id.clone(),
            variant: id.to_owned(),
            known: self
                .variants
                .iter()
                .flat_map(|v| v.choices.iter().map(|c| c.id.as_ref()))
                .collect::<Vec<_>>()
                .join(", "),
        })
    }

    /// Every variant of this protocol, in the protocol file's order, this one among them;
    /// only this one when it has no variants.
    pub fn all_variants(&'static self) -> Vec<&'static Protocol> {
        match &self.variants {
            Some(variants) => (0..variants.choices.len())
                .map(|index| self.variant_at(index))
                .collect(),
            None => vec![self],
        }
    }

    /// The variant the value `value_of(register)` of the drive's selector register selects
    /// (`None` from `value_of`: its default); this protocol when there is no selector or
    /// the value selects none.
    pub fn variant_selected(
        &'static self,
        value_of: impl Fn(u16) -> Option<u32>,
    ) -> &'static Protocol {
        let Some(variants) = &self.variants else {
            return self;
        };
        let Some(selector) = &variants.selected_by else {
            return self;
        };
        match value_of(selector.register).and_then(|value| variants.selected_by_value(value)) {
            Some(index) => self.variant_at(index),
            None => self,
        }
    }

    /// The variant at `index` (an index of [`Variants::choices`] that exists; this
    /// protocol otherwise).
    fn variant_at(&'static self, index: usize) -> &'static Protocol {
        let same = |a: &Protocol, b: &Protocol| std::ptr::eq(a, b);
        let mut derived = DERIVED
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        // A variant built here is taken back to the protocol it was built from, so that
        // every variant of a generated protocol is built from it, once.
        let origin = derived
            .iter()
            .find(|(_, _, built)| same(built, self))
            .map_or(self, |(origin, _, _)| *origin);
        let current = origin.variants.as_ref().map(|v| usize::from(v.current));
        if current == Some(index) {
            return origin;
        }
        if let Some((_, _, built)) = derived
            .iter()
            .find(|(from, at, _)| same(from, origin) && *at == index)
        {
            return built;
        }
        let Some(protocol) = origin.in_variant(index) else {
            return origin;
        };
        let built: &'static Protocol = Box::leak(Box::new(protocol));
        derived.push((origin, index, built));
        built
    }
}

/// One selector of a block transfer: a register whose value chooses the register one word
/// of the transfer goes to (or comes from), through a code table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockSelector {
    /// The selector register's number.
    pub register: u16,
    /// Its default (factory) value.
    pub default: u16,
}

/// One code of a selector's code table: the register the value selects, `None` for "no
/// selection".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockChoice {
    /// The selector value.
    pub value: u16,
    /// The register it selects.
    pub register: Option<u16>,
}

/// Another selection of a block transfer, in force while a mode register holds a value:
/// fixed registers instead of the selectors' (see `protocols[].block.modes` in
/// `drives/README.md`).
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockMode {
    /// The register that turns the mode on.
    pub register: u16,
    /// The value that turns it on.
    pub value: u16,
    /// The register's default value.
    pub default: u16,
    /// The registers written, in word order.
    pub write: List<u16>,
    /// The registers read, in word order.
    pub read: List<u16>,
}

/// What a drive's block transfer writes and reads: selector registers whose values pick
/// the registers through code tables, and modes that replace the selection. The drive
/// reads the selectors at a reset (parameters that `take effect after reset`), so the
/// selection in force is the one at the last reset.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BlockSpec {
    /// Selectors of the words written, in word order.
    pub write: List<BlockSelector>,
    /// Selectors of the words read, in word order.
    pub read: List<BlockSelector>,
    /// The write selectors' code table.
    pub write_choices: List<BlockChoice>,
    /// The read selectors' code table.
    pub read_choices: List<BlockChoice>,
    /// Modes that replace the selection; the first in force wins.
    pub modes: List<BlockMode>,
}

/// The registers a block transfer writes and reads, position by position (`None`: the
/// position selects nothing: a word written there is not written, a word read there is 0).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BlockSelection {
    /// Registers written, in word order.
    pub write: Vec<Option<u16>>,
    /// Registers read, in word order.
    pub read: Vec<Option<u16>>,
}

impl BlockSpec {
    /// The selection given the drive's current values: `value_of(register)` returns a
    /// selector's or mode register's value, `None` for its default.
    pub fn selection(&self, value_of: impl Fn(u16) -> Option<u32>) -> BlockSelection {
        let value = |register: u16, default: u16| value_of(register).unwrap_or(u32::from(default));
        if let Some(mode) = self
            .modes
            .iter()
            .find(|mode| value(mode.register, mode.default) == u32::from(mode.value))
        {
            return BlockSelection {
                write: mode.write.iter().map(|r| Some(*r)).collect(),
                read: mode.read.iter().map(|r| Some(*r)).collect(),
            };
        }
        let pick = |selectors: &[BlockSelector], choices: &[BlockChoice]| {
            selectors
                .iter()
                .map(|selector| {
                    let chosen = value(selector.register, selector.default);
                    choices
                        .iter()
                        .find(|choice| u32::from(choice.value) == chosen)
                        .and_then(|choice| choice.register)
                })
                .collect()
        };
        BlockSelection {
            write: pick(&self.write, &self.write_choices),
            read: pick(&self.read, &self.read_choices),
        }
    }

    /// The selection with every selector and mode register at its default (a drive in its
    /// factory state).
    pub fn default_selection(&self) -> BlockSelection {
        self.selection(|_| None)
    }

    /// Every register whose value the selection depends on: selectors, then mode registers.
    pub fn selector_registers(&self) -> Vec<u16> {
        self.write
            .iter()
            .chain(self.read.iter())
            .map(|s| s.register)
            .chain(self.modes.iter().map(|m| m.register))
            .collect()
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

/// A decoded request (what a drive, or the simulator, receives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecodedRequest<'p> {
    /// The command it carries.
    pub command: &'p CommandSpec,
    /// Station address, if the frame carries one (`None` for a broadcast).
    pub address: Option<u8>,
    /// The stations a broadcast addresses, when the station field holds a broadcast
    /// encoding (`**`, `*9`, FFh, Modbus 0) rather than one station.
    pub broadcast: Option<Broadcast>,
    /// Register number on the wire.
    pub wire_register: Option<u16>,
    /// Register number after undoing the command's address map, when it maps back.
    pub register: Option<u16>,
    /// Array index, if the frame carries one.
    pub index: Option<u16>,
    /// Data (0 for reads).
    pub data: u32,
    /// Process words, if the frame carries them.
    pub process: Option<[u16; 2]>,
    /// The words of its words field (a block transfer's words to write); empty if none.
    pub words: Words,
    /// The registers its data field carries when it carries more than 4 bytes (a Modbus
    /// 10h write of three registers or more), each in the field's byte order; empty
    /// otherwise (the data is then the number in `data`).
    pub data_words: Words,
    /// Every part's value, including presentation (digits used, optional parts present).
    pub values: FrameValues,
    /// Frame length in bytes.
    pub len: usize,
}

impl DecodedRequest<'_> {
    /// The command code as on the wire (the letter in its case); the command's own code
    /// when the layout carries none.
    pub fn code(&self) -> u32 {
        self.values
            .get(&self.command.request, Role::Command)
            .unwrap_or(self.command.code)
    }

    /// The request says its sender has tripped (a lower-case code of a command whose lower
    /// case means so: the Toshiba drive-to-drive `s`).
    pub fn sender_tripped(&self) -> bool {
        self.command.lowercase_means_sender_tripped
            && u8::try_from(self.code()).is_ok_and(|b| b.is_ascii_lowercase())
    }
}

/// A decoded reply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reply<'p> {
    /// A normal reply.
    Data {
        /// The command it answers.
        command: &'p CommandSpec,
        /// The code it carries (the AK response, the letter in its case).
        code: u32,
        /// Station address, if the frame carries one.
        address: Option<u8>,
        /// The command letter was lower case: the drive is tripped.
        tripped: bool,
        /// Register number on the wire, if the reply carries one.
        wire_register: Option<u16>,
        /// Array index, if the reply carries one.
        index: Option<u16>,
        /// Data read, or actually written (0 when the reply carries none).
        data: u32,
        /// Process words (status word, output value), if the reply carries them.
        process: Option<[u16; 2]>,
        /// Offset and length of the text in the frame, for text replies.
        text: Option<(usize, usize)>,
        /// Every part's value.
        values: FrameValues,
        /// Frame length in bytes.
        len: usize,
    },
    /// An error reply.
    Error {
        /// Station address, if the frame carries one.
        address: Option<u8>,
        /// The command letter was lower case: the drive is tripped.
        tripped: bool,
        /// The code the reply carries (`N`, AK 7, function | 80h).
        code: u32,
        /// Error code.
        error: u16,
        /// The manual's entry for the error code, when the table has it.
        info: Option<&'p ErrorCodeInfo>,
        /// Every part's value.
        values: FrameValues,
        /// Frame length in bytes.
        len: usize,
    },
}

impl Reply<'_> {
    /// Frame length in bytes.
    pub fn len(&self) -> usize {
        match self {
            Reply::Data { len, .. } | Reply::Error { len, .. } => *len,
        }
    }

    /// Whether the frame is empty (never true for a decoded reply).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Outcome of looking for one frame in received bytes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Found<T> {
    /// A frame, found after skipping `skipped` bytes of noise.
    Frame {
        /// The decoded frame.
        frame: T,
        /// Bytes skipped before its start.
        skipped: usize,
    },
    /// The bytes so far may still become a frame.
    Incomplete,
}

fn process_of(layout: &FrameLayout, values: &FrameValues) -> Option<[u16; 2]> {
    match (
        values.get(layout, Role::Process1),
        values.get(layout, Role::Process2),
    ) {
        (Some(first), Some(second)) => Some([first as u16, second as u16]),
        _ => None,
    }
}

impl Protocol {
    /// The first command of `kind` serving `space` and carrying `data_type`.
    pub fn command_for(
        &self,
        kind: CommandKind,
        space: Space,
        data_type: DataType,
    ) -> Option<&CommandSpec> {
        self.commands
            .iter()
            .find(|c| !c.extra && c.kind == kind && c.space == space && c.carries(data_type))
    }

    /// The read command that reads several consecutive 16-bit registers of `space` in one
    /// exchange, when the protocol allows more than one ([`Protocol::max_words_per_read`]):
    /// a read of words whose request counts its data (a length part counting `data_size`)
    /// and whose reply's data field is sized by a length part.
    pub fn block_read_command(&self, space: Space) -> Option<&CommandSpec> {
        if self.max_words_per_read < 2 {
            return None;
        }
        self.command_for(CommandKind::Read, space, DataType::Word)
            .filter(|command| command_reads_blocks(command))
    }

    /// The command that writes several consecutive registers in one exchange, when the
    /// protocol allows more than one ([`Protocol::max_words_per_write`]): a RAM write of
    /// `space` whose request's data field is sized by a length part (Modbus 10h).
    pub fn block_write_command(&self, space: Space) -> Option<&CommandSpec> {
        if self.max_words_per_write < 2 {
            return None;
        }
        self.commands.iter().find(|c| {
            c.kind == CommandKind::WriteRam && c.space == space && command_writes_blocks(c)
        })
    }

    /// The block-transfer command, when the drive has one (a [`CommandKind::Block`] command
    /// and a [`BlockSpec`]).
    pub fn block_command(&self) -> Option<&CommandSpec> {
        self.block.as_ref()?;
        self.commands.iter().find(|c| c.kind == CommandKind::Block)
    }

    /// The command that carries `request`, or the typed reason there is none.
    pub fn command_for_request(&self, request: &Request) -> Result<&CommandSpec, EncodeError> {
        crate::tally::lookup();
        if let Some(code) = request.command {
            return self
                .commands
                .iter()
                .find(|c| {
                    c.answers_to(code)
                        && c.kind == request.kind
                        && c.space == request.space
                        && c.carries(request.data_type)
                })
                .ok_or_else(|| EncodeError::NoSuchCommand {
                    protocol: self.id.clone(),
                    code,
                    kind: request.kind,
                });
        }
        self.command_for(request.kind, request.space, request.data_type)
            .ok_or_else(|| EncodeError::UnsupportedCommand {
                protocol: self.id.clone(),
                kind: request.kind,
                space: request.space,
                data_type: request.data_type,
            })
    }

    /// The error-code table entry for `code`.
    pub fn error_code(&self, code: u16) -> Option<&ErrorCodeInfo> {
        self.error_codes.iter().find(|entry| entry.code == code)
    }

    /// Builds the request's frame values: its layout and the values to encode, with the
    /// protocol's default optional parts included. Callers may adjust presentation (digits,
    /// optional parts) before calling [`codec::encode`].
    pub fn request_values(
        &self,
        request: &Request,
        address: Option<u8>,
    ) -> Result<(&FrameLayout, FrameValues), EncodeError> {
        let command = self.command_for_request(request)?;
        self.request_values_for(command, request, address)
    }

    /// Like [`Protocol::request_values`] with the command chosen by the caller (for
    /// example the one a captured frame used).
    pub fn request_values_for<'c>(
        &self,
        command: &'c CommandSpec,
        request: &Request,
        address: Option<u8>,
    ) -> Result<(&'c FrameLayout, FrameValues), EncodeError> {
        let layout = &command.request;
        let roles = self.request_roles(command, request, address)?;
        let mut values = FrameValues {
            data_size: request.data_type.size(),
            ..FrameValues::default()
        };
        for name in self.default_optional_parts.iter() {
            values.include(layout, &[name]);
        }
        values.fill(layout, &roles);
        Ok((layout, values))
    }

    /// The values of every role a request of `command` carries, once the request is
    /// checked against the protocol (register, station); what
    /// [`Protocol::request_values_for`] fills the frame values with.
    #[inline]
    fn request_roles(
        &self,
        command: &CommandSpec,
        request: &Request,
        address: Option<u8>,
    ) -> Result<Roles, EncodeError> {
        let layout = &command.request;
        let wire = if request.wire_register {
            Some(request.register)
        } else {
            self.to_wire(command, request.register)
        };
        let own = self
            .wire_numbers
            .iter()
            .any(|w| w.register == request.register);
        let wire = wire.ok_or_else(|| match own {
            // The drive file gives the register its own numbers here, but none for this
            // direction (a Modbus-only monitor over the Eaton protocol).
            true if !request.wire_register => EncodeError::NotInProtocol {
                protocol: self.id.clone(),
                register: request.register,
                writing: command.kind.is_write(),
            },
            _ => EncodeError::RegisterOutOfRange {
                protocol: self.id.clone(),
                register: request.register,
            },
        })?;
        if !request.wire_register && !command.serves_register(request.register) {
            return Err(EncodeError::RegisterNotServed {
                protocol: self.id.clone(),
                code: command.code,
                register: request.register,
            });
        }
        let [first, second] = request.process.unwrap_or(self.default_process);
        let roles = Roles {
            address: address.map(u32::from),
            command: Some(
                request
                    .command
                    .filter(|code| command.answers_to(*code))
                    .unwrap_or(command.code),
            ),
            register: Some(u32::from(wire)),
            index: Some(u32::from(request.index.unwrap_or(0))),
            data: Some(request.data),
            error_code: None,
            process_1: Some(u32::from(first)),
            process_2: Some(u32::from(second)),
            decimals: None,
        };
        if let Some(address) = address {
            let (min, max) = self.address_range;
            if address < min || address > max {
                return Err(EncodeError::AddressOutOfRange {
                    protocol: self.id.clone(),
                    address,
                    min,
                    max,
                });
            }
        } else if layout
            .locate(Role::Address)
            .is_some_and(|(index, _)| !is_optional(&layout.parts[index]))
        {
            return Err(EncodeError::AddressRequired {
                protocol: self.id.clone(),
            });
        }
        Ok(roles)
    }

    /// Whether `info` can be read over this protocol: a read command serves its space and
    /// data type, and the register has a wire number for it (a register the description
    /// numbers only for other protocols, or whose number the address map cannot carry,
    /// cannot). What a backup or a watch over this protocol may include.
    pub fn can_read(&self, info: &crate::info::RegisterInfo) -> bool {
        let kind = if info.data_type == DataType::Text {
            CommandKind::ReadText
        } else {
            CommandKind::Read
        };
        self.command_for(kind, info.space, info.data_type)
            .is_some_and(|command| self.to_wire(command, info.address).is_some())
    }

    /// The station a tool addresses by default: none where the protocol's frames may leave
    /// the station out, else its lowest station (at least 1, as a drive answers out of the
    /// box). Found by encoding a probe read without a station.
    pub fn default_address(&self) -> Option<u8> {
        let mut frame = [0u8; MAX_FRAME_PROBE];
        let needs_one = (1..=16).any(|register| {
            let probe = Request::raw(CommandKind::Read, register, 0);
            matches!(
                self.encode_request(&probe, None, &mut frame),
                Err(EncodeError::AddressRequired { .. })
            )
        });
        needs_one.then_some(self.address_range.0.max(1))
    }

    /// Encodes `request` for the station `address` (or for whichever drive listens, when
    /// `None` and the protocol lets the address out) into `out`; returns the frame length.
    pub fn encode_request(
        &self,
        request: &Request,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let command = self.command_for_request(request)?;
        self.encode_request_for(command, request, address, out)
    }

    /// Like [`Protocol::encode_request`] with the command already chosen (by
    /// [`Protocol::command_for_request`]), so that a request is looked up once.
    pub fn encode_request_for(
        &self,
        command: &CommandSpec,
        request: &Request,
        address: Option<u8>,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        if let Some(plan) = &command.request.plan {
            let roles = self.request_roles(command, request, address)?;
            let size = request.data_type.size();
            let optional = &self.default_optional_parts;
            if let Some(len) = plan.encode(&command.request, &roles, size, optional, out) {
                crate::tally::encoding();
                return Ok(len);
            }
        }
        let (layout, values) = self.request_values_for(command, request, address)?;
        codec::encode(layout, &values, out)
    }

    /// Encodes `request` as a broadcast to the stations `to` addresses. Refused before
    /// anything is built: a protocol the drive takes no broadcasts over, a command the
    /// drive's rule does not list, any request that reads (only writes may be broadcast),
    /// and a group the station field cannot carry.
    pub fn encode_broadcast(
        &self,
        request: &Request,
        to: &Broadcast,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let (layout, values) = self.broadcast_values(request, to)?;
        codec::encode(layout, &values, out)
    }

    /// The frame values of `request` broadcast to `to` (see [`Protocol::encode_broadcast`]).
    pub fn broadcast_values(
        &self,
        request: &Request,
        to: &Broadcast,
    ) -> Result<(&FrameLayout, FrameValues), EncodeError> {
        let command = self.command_for_request(request)?;
        self.broadcast_values_for(command, request, to)
    }

    /// Like [`Protocol::broadcast_values`] with the command already chosen (by
    /// [`Protocol::command_for_request`]).
    pub fn broadcast_values_for<'c>(
        &self,
        command: &'c CommandSpec,
        request: &Request,
        to: &Broadcast,
    ) -> Result<(&'c FrameLayout, FrameValues), EncodeError> {
        let refuse = |reason: &'static str| EncodeError::NoBroadcast {
            protocol: self.id.clone(),
            kind: request.kind,
            reason,
        };
        if !request.kind.is_write() {
            return Err(refuse(
                "only writes may be broadcast: no station could answer a read for all of them",
            ));
        }
        let rule = self
            .broadcast
            .as_ref()
            .ok_or_else(|| refuse("the drive takes no broadcasts over this protocol"))?;
        if !rule.commands.contains(&command.code) {
            return Err(refuse(
                "the drive does not carry out this command when broadcast",
            ));
        }
        let layout = &command.request;
        let field = layout
            .field(Role::Address)
            .filter(|field| broadcasts::field_carries(field, to))
            .ok_or_else(|| refuse("the station field has no encoding for these stations"))?;
        let value = broadcasts::field_value(field, to);
        let placeholder = self.address_range.0;
        let (layout, mut values) = self.request_values_for(command, request, Some(placeholder))?;
        values.set(layout, Role::Address, value);
        Ok((layout, values))
    }

    /// Which station answers a broadcast to `to` by the drive's rule (`None`: none does, or
    /// the drive takes no broadcasts over this protocol).
    pub fn broadcast_responder(&self, request: &Request, to: &Broadcast) -> Option<u8> {
        let rule = self.broadcast.as_ref()?;
        let command = self.command_for_request(request).ok()?;
        let field = command.request.field(Role::Address)?;
        rule.responder(to, self.address_range.0, broadcasts::field_radix(field))
    }

    /// Decodes a request frame starting at `bytes[0]`.
    pub fn decode_request(&self, bytes: &[u8]) -> Result<Found<DecodedRequest<'_>>, DecodeError> {
        let mut best: Option<DecodeError> = None;
        let mut incomplete = false;
        for command in self.commands.iter() {
            let layout = &command.request;
            match crate::plan::decode(layout, bytes) {
                Ok(DecodeStatus::Complete { values, len }) => {
                    // Commands may share a layout (W and P): the code decides.
                    if values
                        .get(layout, Role::Command)
                        .is_some_and(|code| !command.answers_to(code))
                    {
                        continue;
                    }
                    if let Err(error) = self.station_in_range(layout, &values) {
                        best = Some(furthest(best, error));
                        continue;
                    }
                    let wire = values.get(layout, Role::Register).map(|r| r as u16);
                    let station = values.get(layout, Role::Address);
                    let broadcast = station.and_then(|value| {
                        layout
                            .field(Role::Address)
                            .and_then(|field| broadcasts::from_field_value(field, value))
                    });
                    return Ok(Found::Frame {
                        frame: DecodedRequest {
                            command,
                            address: station.filter(|_| broadcast.is_none()).map(|a| a as u8),
                            broadcast,
                            wire_register: wire,
                            register: wire.and_then(|w| {
                                self.from_wire(command, w, values.get(layout, Role::Data))
                            }),
                            index: values.get(layout, Role::Index).map(|i| i as u16),
                            data: values.get(layout, Role::Data).unwrap_or(0),
                            process: process_of(layout, &values),
                            words: values.words(layout, bytes),
                            data_words: values.data_words(layout, bytes),
                            values,
                            len,
                        },
                        skipped: 0,
                    });
                }
                Ok(DecodeStatus::Incomplete) => incomplete = true,
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        if incomplete {
            return Ok(Found::Incomplete);
        }
        Err(self.no_match("request", best))
    }

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
        match crate::plan::decode(layout, bytes)? {
            DecodeStatus::Incomplete => Ok(None),
            DecodeStatus::Complete { values, len } => {
                no_open_station(layout, &values)?;
                self.station_in_range(layout, &values)?;
                self.error_function_known(layout, &values)?;
                Ok(Some(self.error_reply_from(layout, values, len)))
            }
        }
    }

    /// Refuses a frame whose station field holds one station outside the protocol's
    /// station range (the description's `addressing`), as [`Protocol::encode_request`]
    /// refuses to address it: a YD1000 frame from station 64 (range 0-63) is no frame of
    /// the drive. A broadcast encoding in the field (Modbus 0, `**`, FFh) is no station.
    fn station_in_range(
        &self,
        layout: &FrameLayout,
        values: &FrameValues,
    ) -> Result<(), DecodeError> {
        let Some((index, None)) = layout.locate(Role::Address) else {
            return Ok(());
        };
        let slot = values.parts[index];
        let Part::Field(field) = &layout.parts[index] else {
            return Ok(());
        };
        if !slot.present || broadcasts::from_field_value(field, slot.value).is_some() {
            return Ok(());
        }
        let (min, max) = self.address_range;
        if (u32::from(min)..=u32::from(max)).contains(&slot.value) {
            return Ok(());
        }
        Err(DecodeError::StationOutOfRange {
            layout: layout.name.clone(),
            part: field.name.clone(),
            offset: layout.wire_span(part_offset(layout, values, index), 0).0,
            station: slot.value,
            min,
            max,
        })
    }

    /// Refuses an error reply whose function code is the error code of none of the drive's
    /// commands, when each of them names one (Modbus: a drive without function 08 sends
    /// no 88h, although the shared protocol file's layout allows it).
    fn error_function_known(
        &self,
        layout: &FrameLayout,
        values: &FrameValues,
    ) -> Result<(), DecodeError> {
        let Some(code) = values.get(layout, Role::Command) else {
            return Ok(());
        };
        let codes: Option<Vec<u32>> = self.commands.iter().map(|c| c.error_code).collect();
        match codes {
            Some(codes) if !codes.is_empty() && !codes.contains(&code) => {
                Err(DecodeError::NotAllowed {
                    layout: layout.name.clone(),
                    part: layout
                        .index_of(Role::Command)
                        .map_or(Cow::Borrowed("command"), |i| {
                            layout.parts[i].name().to_owned().into()
                        }),
                    offset: layout
                        .wire_span(
                            layout
                                .index_of(Role::Command)
                                .map_or(0, |i| part_offset(layout, values, i)),
                            0,
                        )
                        .0,
                    value: code,
                    format: Format::U8,
                })
            }
            _ => Ok(()),
        }
    }

    /// The error reply with these decoded `values`.
    fn error_reply_from(&self, layout: &FrameLayout, values: FrameValues, len: usize) -> Reply<'_> {
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
    fn data_reply_from<'p>(
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

    /// Decodes exactly one request frame: `bytes` must hold the whole frame and nothing else.
    pub fn decode_request_exact(&self, bytes: &[u8]) -> Result<DecodedRequest<'_>, DecodeError> {
        match self.decode_request(bytes)? {
            Found::Frame { frame, .. } => self.exact(frame.len, bytes.len()).map(|()| frame),
            Found::Incomplete => Err(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }),
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

    fn exact(&self, len: usize, available: usize) -> Result<(), DecodeError> {
        if len == available {
            Ok(())
        } else {
            Err(DecodeError::TrailingBytes {
                layout: self.id.clone(),
                len,
                extra: available - len,
            })
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

    fn no_match(&self, what: &'static str, best: Option<DecodeError>) -> DecodeError {
        let closest = best.unwrap_or(DecodeError::Truncated {
            layout: self.id.clone(),
            len: 0,
        });
        DecodeError::NoLayoutMatches {
            protocol: self.id.clone(),
            what,
            closest: Box::new(closest),
        }
    }
}

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

/// What [`Protocol::search_reply`] made of the bytes received so far.
#[derive(Debug, Clone, PartialEq)]
pub struct Search<'p> {
    /// The reply that answers the request, and the number of bytes before it.
    pub found: Option<(Reply<'p>, usize)>,
    /// More bytes could still bring a reply. With `found`: a frame that would answer the
    /// request starts inside the one found, and bytes follow the found one (a reply is
    /// followed by silence, so it may have been a false start).
    pub waiting: bool,
    /// The first whole frame that answers something else, and how it differs.
    pub foreign: Option<Difference>,
    /// The first whole frame whose checksum does not match its bytes.
    pub corrupt: Option<DecodeError>,
    /// The error of the attempt that got furthest, when no frame was found.
    pub last_error: Option<DecodeError>,
}

/// What the bytes at one offset may be.
enum Candidate<'p> {
    /// A whole frame that answers the request.
    Fits(Reply<'p>),
    /// The start of a frame that may still answer it.
    Waiting,
    /// A whole frame that answers something else.
    Foreign(Difference),
    /// Not a frame of the protocol.
    Invalid(DecodeError),
}

impl Protocol {
    /// Looks for the reply to a request of `command` in `bytes`, whatever comes before it:
    /// every offset where a frame may start (where the protocol's start sequence is, or
    /// every byte when it has none) is tried with the command's reply layout and the
    /// error-reply layout, and frames that do not meet `expectation` are passed over. Of
    /// frames that overlap, the one starting last wins: bytes that follow a frame and hold
    /// another one beginning inside it mean the first was a false start that a weak
    /// checksum let through. See [`Search`] for what is reported when nothing fits.
    pub fn search_reply<'p>(
        &'p self,
        command: &'p CommandSpec,
        expectation: &Expectation,
        bytes: &[u8],
    ) -> Search<'p> {
        let mut search = Search {
            found: None,
            waiting: false,
            foreign: None,
            corrupt: None,
            last_error: None,
        };
        for offset in 0..bytes.len() {
            if self.reply_may_start(&bytes[offset..]) == Some(false) {
                continue;
            }
            if let Some((frame, at)) = &search.found {
                if offset >= at + frame.len() {
                    break;
                }
            }
            match self.candidate_at(command, expectation, &bytes[offset..]) {
                Candidate::Fits(reply) => {
                    search.found = Some((reply, offset));
                    search.waiting = false;
                }
                Candidate::Waiting => search.waiting = true,
                Candidate::Foreign(difference) => {
                    search.foreign = search.foreign.or(Some(difference));
                }
                Candidate::Invalid(error) => {
                    if search.corrupt.is_none()
                        && error.kind() == crate::error::DecodeErrorKind::ChecksumMismatch
                    {
                        search.corrupt = Some(error.clone());
                    }
                    search.last_error = Some(furthest(search.last_error.take(), error));
                }
            }
        }
        if let Some((frame, at)) = &search.found {
            // Nothing follows the frame: it is the reply, whatever may start inside it.
            if at + frame.len() == bytes.len() {
                search.waiting = false;
            }
            search.last_error = None;
        }
        search
    }

    /// What the bytes starting at `bytes[0]` may be, for a request of `command`.
    fn candidate_at<'p>(
        &'p self,
        command: &'p CommandSpec,
        expectation: &Expectation,
        bytes: &[u8],
    ) -> Candidate<'p> {
        let mut waiting = false;
        let mut foreign = None;
        let mut best: Option<DecodeError> = None;
        let layouts = [
            Some((&command.reply, true)),
            self.error_reply.as_ref().map(|l| (l, false)),
        ];
        for (layout, normal) in layouts.into_iter().flatten() {
            match crate::plan::decode_prefix(layout, bytes) {
                Ok(Progress::Complete { values, len }) => {
                    let reply = if normal {
                        match self.data_reply_from(command, values, len) {
                            Ok(reply) => reply,
                            Err(error) => {
                                best = Some(furthest(best, error));
                                continue;
                            }
                        }
                    } else {
                        if let Err(error) = no_open_station(layout, &values)
                            .and_then(|()| self.station_in_range(layout, &values))
                            .and_then(|()| self.error_function_known(layout, &values))
                        {
                            best = Some(furthest(best, error));
                            continue;
                        }
                        self.error_reply_from(layout, values, len)
                    };
                    let size = expectation
                        .data_size
                        .filter(|size| normal && values.data_size != 0 && values.data_size != *size)
                        .map(|size| Difference {
                            role: Role::Data,
                            expected: u32::from(size),
                            found: u32::from(values.data_size),
                        });
                    match expectation.difference(&values.roles(layout)).or(size) {
                        None => return Candidate::Fits(reply),
                        Some(difference) => foreign = foreign.or(Some(difference)),
                    }
                }
                Ok(Progress::Incomplete { values }) => {
                    if expectation.difference(&values.roles(layout)).is_none() {
                        waiting = true;
                    }
                }
                Err(error) => best = Some(furthest(best, error)),
            }
        }
        if waiting {
            Candidate::Waiting
        } else if let Some(difference) = foreign {
            Candidate::Foreign(difference)
        } else {
            Candidate::Invalid(best.unwrap_or(DecodeError::Truncated {
                layout: self.id.clone(),
                len: bytes.len(),
            }))
        }
    }
}

/// A reply comes from one station: a station field with open digits (`**`, `*9`) is a
/// broadcast request's, never a reply's.
fn no_open_station(layout: &FrameLayout, values: &FrameValues) -> Result<(), DecodeError> {
    match layout.locate(Role::Address) {
        Some((index, None))
            if values.parts[index].present
                && crate::layout::BroadcastAddress::is_open(values.parts[index].value) =>
        {
            Err(DecodeError::NotAllowed {
                layout: layout.name.clone(),
                part: layout.parts[index].name().to_owned().into(),
                offset: 0,
                value: values.parts[index].value & 0xFF_FFFF,
                format: Format::Decimal,
            })
        }
        _ => Ok(()),
    }
}

/// Where the part at `index` of `layout` begins in a frame, counting the fixed sizes of
/// the parts before it (an optional part counted when present, digits by the count read);
/// the station field follows only fixed parts in every layout.
fn part_offset(layout: &FrameLayout, values: &FrameValues, index: usize) -> usize {
    layout.parts[..index]
        .iter()
        .zip(values.parts.iter())
        .map(|(part, slot)| match part {
            Part::Literal { bytes, .. } if slot.present => bytes.len(),
            Part::Field(_) if slot.width > 0 => usize::from(slot.width),
            part => part.fixed_size().unwrap_or(0),
        })
        .sum()
}

fn is_optional(part: &Part) -> bool {
    match part {
        Part::Field(field) => field.optional.is_some(),
        _ => false,
    }
}

/// Sorts one decoding attempt: a reply is returned, "more bytes needed" and errors are noted.
fn settle<'p>(
    attempt: Result<Option<Reply<'p>>, DecodeError>,
    best: &mut Option<DecodeError>,
    incomplete: &mut bool,
) -> Option<Reply<'p>> {
    match attempt {
        Ok(Some(reply)) => Some(reply),
        Ok(None) => {
            *incomplete = true;
            None
        }
        Err(error) => {
            *best = Some(furthest(best.take(), error));
            None
        }
    }
}

/// Keeps the error that got further into the frame: it names the most telling problem.
fn furthest(best: Option<DecodeError>, error: DecodeError) -> DecodeError {
    // A whole frame from a station the drive cannot have says more than a layout that
    // failed further on.
    let whole = |e: &DecodeError| matches!(e, DecodeError::StationOutOfRange { .. });
    match best {
        Some(best) if whole(&best) && !whole(&error) => best,
        Some(_) if whole(&error) => error,
        Some(best) if best.offset() >= error.offset() => best,
        _ => error,
    }
}
