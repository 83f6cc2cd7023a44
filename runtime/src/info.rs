//! Static metadata a generated drive module supplies: one entry per register and one per
//! error code of the manual's tables.
//!
//! Below everything that works with registers or protocols: it imports only [`crate::kinds`]
//! and [`crate::layout`], so error types can name a register or an error code.

use crate::kinds::{Access, DataType, Space, TakesEffect, Unit};
use crate::layout::Text;
use std::borrow::Cow;

/// Everything the manual says about one register, as static data.
#[derive(Debug, Clone, PartialEq)]
pub struct RegisterInfo {
    /// Communication number, parameter number or coil number (before any protocol's address
    /// map). For a register the manual gives no number of its own (`has_address` false:
    /// its protocols reach it by its wire numbers only), a number of its own that no frame
    /// carries.
    pub address: u16,
    /// Whether `address` is the manual's (or follows from its place on a page); false for a
    /// register known by its wire numbers only, which is not found by number.
    pub has_address: bool,
    /// Identifier in the drive file (`deceleration_time_1`).
    pub id: &'static str,
    /// The manual's code or mnemonic (`Dec`, `F800`, `FA01`).
    pub code: &'static str,
    /// Other names the manual gives it (the DV1's P numbers: `P.33` for 07-00); a client
    /// may name the register by any of them ([`crate::DriveInfo::register`]).
    pub aliases: &'static [&'static str],
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// Engineering unit.
    pub unit: Unit,
    /// Engineering value of one raw step (0.01 for 0.01 Hz).
    pub scale: f64,
    /// Whether the raw word is two's-complement signed.
    pub signed: bool,
    /// Lowest raw value accepted (static bound).
    pub raw_min: i64,
    /// Highest raw value accepted (static bound).
    pub raw_max: i64,
    /// Shape on the wire (word, double word, text).
    pub data_type: DataType,
    /// Address space of `address` (parameters, coils).
    pub space: Space,
    /// Number of array elements for indexed parameters; 0 when it is not an array.
    pub array_len: u8,
    /// Code of the register that bounds the value from below at run time (`LL`), if any.
    pub min_bound: Option<&'static str>,
    /// Code of the register that bounds the value from above at run time (`FH`), if any.
    pub max_bound: Option<&'static str>,
    /// Access over the serial link.
    pub access: Access,
    /// Writes go to RAM only; a persistent (EEPROM) write is not allowed.
    pub ram_only: bool,
    /// A persistent (EEPROM) write is accepted, but the value is stored in RAM only (lost
    /// at power-off): a storage rule of its own, distinct from [`RegisterInfo::ram_only`]'s
    /// refusal.
    pub persistent_write_to_ram: bool,
    /// May be written while the motor runs (false when the manual does not say).
    pub writable_while_running: bool,
    /// The manual does not say whether it may be written while running (its table has no
    /// such column): a master attempts the write while the motor runs and reports the
    /// drive's refusal if one comes; the virtual drive accepts it.
    pub while_running_unknown: bool,
    /// Only effective when set from the operator panel.
    pub panel_only: bool,
    /// When a written value takes effect.
    pub takes_effect: TakesEffect,
    /// Factory value as a raw word (what the drive holds after a factory reset), when the
    /// manual gives one.
    pub default_raw: Option<u32>,
    /// The bit-field layout of its value, for bit-field words.
    pub bits: Option<&'static BitWordInfo>,
    /// The code table naming its values, when the manual gives one (complete or not).
    pub codes: Option<&'static CodeTableInfo>,
    /// The manual's description of the register and the description's remarks, as one
    /// text (empty when there are none).
    pub text: &'static str,
    /// Writes to it are never answered (an inverter reset): a master returns once the
    /// frame is on the line, and the virtual drive stays silent.
    pub no_reply: bool,
    /// Code of the live register whose value this one holds from the moment of the last
    /// trip (FE00 holds FD00's), if it is such a copy.
    pub held_at_trip_of: Option<&'static str>,
    /// It shows the live value, but keeps the value it had while the drive is tripped.
    pub live_except_while_tripped: bool,
    /// Its scale and range chosen by another register's value, if they are.
    pub scale_by: Option<&'static ScaleBy>,
    /// Its copies on each serial port (port id, register code), when it exists once per
    /// port; empty otherwise.
    pub per_port: &'static [(&'static str, &'static str)],
    /// Values it takes besides its range, each carried by its own raw word (99999 as
    /// FFFFh); empty for most registers.
    pub special_values: &'static [SpecialValue],
}

/// A value a register takes besides its range, with its own raw word.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecialValue {
    /// The value as the manual writes it (99999).
    pub value: f64,
    /// The raw word carrying it (FFFFh).
    pub raw: u32,
    /// Identifier in the drive file (`no_check`).
    pub id: &'static str,
    /// What it means.
    pub name: &'static str,
}

/// A register's scale chosen by another register's value.
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleBy {
    /// Code of the selector register.
    pub register: &'static str,
    /// One choice per selector value.
    pub choices: &'static [ScaleChoice],
    /// The register as it is for every selector value `choices` does not list (`None`:
    /// such values choose no scale).
    pub otherwise: Option<&'static RegisterInfo>,
}

/// The register as it is for one selector value: the same register with that choice's
/// scale and range.
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleChoice {
    /// The selector's value.
    pub value: u32,
    /// The register with this choice's scale and raw range (and no `scale_by`).
    pub info: &'static RegisterInfo,
}

impl ScaleBy {
    /// The register as it is when the selector holds `selector`, if the description gives
    /// that value (or a choice for every other value).
    pub fn choice(&self, selector: u32) -> Option<&'static RegisterInfo> {
        self.choices
            .iter()
            .find(|choice| choice.value == selector)
            .map(|choice| choice.info)
            .or(self.otherwise)
    }

    /// Every scale the selector can choose: the listed choices', then the other values'.
    pub fn scales(&self) -> impl Iterator<Item = &'static RegisterInfo> + '_ {
        self.choices
            .iter()
            .map(|choice| choice.info)
            .chain(self.otherwise)
    }
}

/// Const builders: generated code writes a register as `RegisterInfo::new(..)` followed by
/// the `with_*` calls for what differs from the defaults.
impl RegisterInfo {
    /// [`RegisterInfo::DEFAULT`] at this address, with this code and id.
    pub const fn new(address: u16, code: &'static str, id: &'static str) -> Self {
        RegisterInfo {
            address,
            id,
            code,
            ..Self::DEFAULT
        }
    }

    /// With the English and the manual's Chinese name.
    pub const fn with_names(mut self, name: &'static str, name_zh: &'static str) -> Self {
        self.name = name;
        self.name_zh = name_zh;
        self
    }

    /// With a unit and the engineering value of one raw step.
    pub const fn with_unit(mut self, unit: Unit, scale: f64) -> Self {
        self.unit = unit;
        self.scale = scale;
        self
    }

    /// The raw value is two's-complement signed.
    pub const fn with_signed(mut self) -> Self {
        self.signed = true;
        self
    }

    /// With static raw bounds.
    pub const fn with_raw_range(mut self, min: i64, max: i64) -> Self {
        self.raw_min = min;
        self.raw_max = max;
        self
    }

    /// The register with this code bounds the value from below at run time.
    pub const fn with_min_bound(mut self, code: &'static str) -> Self {
        self.min_bound = Some(code);
        self
    }

    /// The register with this code bounds the value from above at run time.
    pub const fn with_max_bound(mut self, code: &'static str) -> Self {
        self.max_bound = Some(code);
        self
    }

    /// With this access over the serial link.
    pub const fn with_access(mut self, access: Access) -> Self {
        self.access = access;
        self
    }

    /// Writes go to RAM only.
    pub const fn with_ram_only(mut self) -> Self {
        self.ram_only = true;
        self
    }

    /// A persistent write is accepted but stored in RAM only.
    pub const fn with_persistent_write_to_ram(mut self) -> Self {
        self.persistent_write_to_ram = true;
        self
    }

    /// Known by its wire numbers only: `address` is no number of the manual's.
    pub const fn without_address(mut self) -> Self {
        self.has_address = false;
        self
    }

    /// Whether a value written to it stays in RAM only, whatever the command (RAM only, or
    /// a persistent write stored in RAM).
    pub const fn stored_in_ram_only(&self) -> bool {
        self.ram_only || self.persistent_write_to_ram
    }

    /// May be written while the motor runs.
    pub const fn with_writable_while_running(mut self) -> Self {
        self.writable_while_running = true;
        self
    }

    /// The manual does not say whether it may be written while running.
    pub const fn with_while_running_unknown(mut self) -> Self {
        self.while_running_unknown = true;
        self
    }

    /// Only effective when set from the operator panel.
    pub const fn with_panel_only(mut self) -> Self {
        self.panel_only = true;
        self
    }

    /// Takes effect as given.
    pub const fn with_takes_effect(mut self, takes_effect: TakesEffect) -> Self {
        self.takes_effect = takes_effect;
        self
    }

    /// With this factory value, as a raw word.
    pub const fn with_default_raw(mut self, raw: u32) -> Self {
        self.default_raw = Some(raw);
        self
    }

    /// Its value is a bit-field word laid out as `bits` says.
    pub const fn with_bits(mut self, bits: &'static BitWordInfo) -> Self {
        self.bits = Some(bits);
        self
    }

    /// Its values are named by the code table `codes`.
    pub const fn with_codes(mut self, codes: &'static CodeTableInfo) -> Self {
        self.codes = Some(codes);
        self
    }

    /// With the manual's description and remarks.
    pub const fn with_text(mut self, text: &'static str) -> Self {
        self.text = text;
        self
    }

    /// Writes to it are never answered.
    pub const fn with_no_reply(mut self) -> Self {
        self.no_reply = true;
        self
    }

    /// With this shape on the wire.
    pub const fn with_data_type(mut self, data_type: DataType) -> Self {
        self.data_type = data_type;
        self
    }

    /// In this address space.
    pub const fn with_space(mut self, space: Space) -> Self {
        self.space = space;
        self
    }

    /// An array (indexed) parameter of `len` elements.
    pub const fn with_array(mut self, len: u8) -> Self {
        self.array_len = len;
        self
    }

    /// It holds the value of the live register `code` from the moment of the last trip.
    pub const fn with_held_at_trip_of(mut self, code: &'static str) -> Self {
        self.held_at_trip_of = Some(code);
        self
    }

    /// It shows the live value except while the drive is tripped.
    pub const fn with_live_except_while_tripped(mut self) -> Self {
        self.live_except_while_tripped = true;
        self
    }

    /// Its scale and range are chosen by another register.
    pub const fn with_scale_by(mut self, scale_by: &'static ScaleBy) -> Self {
        self.scale_by = Some(scale_by);
        self
    }

    /// It takes these values besides its range.
    pub const fn with_special_values(mut self, special_values: &'static [SpecialValue]) -> Self {
        self.special_values = special_values;
        self
    }

    /// Other names the manual gives it (`P.33`).
    pub const fn with_aliases(mut self, aliases: &'static [&'static str]) -> Self {
        self.aliases = aliases;
        self
    }

    /// It exists once per serial port: (port id, register code) of every copy.
    pub const fn with_per_port(
        mut self,
        per_port: &'static [(&'static str, &'static str)],
    ) -> Self {
        self.per_port = per_port;
        self
    }
}

impl RegisterInfo {
    /// Whether `name` is its code, id or one of its aliases (exactly as written).
    pub fn is_named(&self, name: &str) -> bool {
        self.code == name || self.id == name || self.aliases.contains(&name)
    }

    /// A read-write, unsigned, unscaled word parameter without unit, array or run-time
    /// bounds, over the whole word range; address 0 and empty names. A literal can write
    /// only the fields that differ: `RegisterInfo { address: 0x0011, id: "maximum_frequency",
    /// ..RegisterInfo::DEFAULT }`.
    pub const DEFAULT: RegisterInfo = RegisterInfo {
        address: 0,
        has_address: true,
        id: "",
        code: "",
        aliases: &[],
        name: "",
        name_zh: "",
        unit: Unit::None,
        scale: 1.0,
        signed: false,
        raw_min: 0,
        raw_max: 0xFFFF,
        data_type: DataType::Word,
        space: Space::Parameter,
        array_len: 0,
        min_bound: None,
        max_bound: None,
        access: Access::ReadWrite,
        ram_only: false,
        persistent_write_to_ram: false,
        writable_while_running: false,
        while_running_unknown: false,
        panel_only: false,
        takes_effect: TakesEffect::Immediately,
        default_raw: None,
        bits: None,
        codes: None,
        text: "",
        no_reply: false,
        held_at_trip_of: None,
        live_except_while_tripped: false,
        scale_by: None,
        per_port: &[],
        special_values: &[],
    };

    /// `register 0011 FH (Maximum frequency / 最高频率)`: how errors name the register.
    /// The code is left out when it only repeats the address (`FA01`).
    pub fn label(&self) -> String {
        if !self.has_address {
            // Known by its wire numbers only: its code is its name.
            return if self.name_zh.is_empty() {
                format!("register {} ({})", self.code, self.name)
            } else {
                format!("register {} ({} / {})", self.code, self.name, self.name_zh)
            };
        }
        let number = manual_number(self.space, self.address, self.code);
        let names = if self.name_zh.is_empty() {
            format!("({})", self.name)
        } else {
            format!("({} / {})", self.name, self.name_zh)
        };
        if self.space == Space::Coil {
            return format!("{number} {} {names}", self.code);
        }
        if self.code.parse::<u16>().ok() == Some(self.address) {
            // Parameters numbered in decimal (FC 303).
            return format!("parameter {number} {names}");
        }
        if self.code.eq_ignore_ascii_case(&number) {
            format!("register {number} {names}")
        } else {
            format!("register {number} {} {names}", self.code)
        }
    }

    /// The unit's symbol.
    pub fn unit_symbol(&self) -> &'static str {
        self.unit.symbol()
    }

    /// Decimal places implied by the scale (0.01 -> 2).
    pub fn decimals(&self) -> u8 {
        decimals_of(self.scale)
    }

    /// The register as it is when a reply says its value has `decimals` decimal places
    /// (the Eaton unit digit): itself when its own scale has them, else the `scale_by`
    /// choice that has them; `None` when no scale of the register has that many (a master
    /// refuses such a reply with `ValueError::WrongDecimals`).
    pub fn scaled_for_decimals(&'static self, decimals: u8) -> Option<&'static RegisterInfo> {
        if self.decimals() == decimals {
            return Some(self);
        }
        self.scale_by
            .and_then(|scale_by| scale_by.scales().find(|info| info.decimals() == decimals))
    }

    /// The register as it is when its scale selector holds `selector` (itself when its
    /// scale is fixed, or the selector's value is not one the description gives).
    pub fn scaled_for(&'static self, selector: Option<u32>) -> &'static RegisterInfo {
        match (self.scale_by, selector) {
            (Some(scale_by), Some(selector)) => scale_by.choice(selector).unwrap_or(self),
            _ => self,
        }
    }

    /// The special value (taken besides the range) carried by `raw`, if any.
    pub fn special_raw(&self, raw: u32) -> Option<&'static SpecialValue> {
        self.special_values.iter().find(|s| s.raw == raw)
    }

    /// The special value (taken besides the range) equal to `value`, if any.
    pub fn special_value(&self, value: f64) -> Option<&'static SpecialValue> {
        self.special_values.iter().find(|s| s.value == value)
    }

    /// The code of its copy on the port `port`: itself when it is not per port or the
    /// port is not one of its ports.
    pub fn code_on_port(&self, port: &str) -> &'static str {
        self.per_port
            .iter()
            .find(|(id, _)| *id == port)
            .map_or(self.code, |(_, code)| code)
    }

    /// Explains run-time bounds named after other registers, for error messages.
    pub fn bound_note(&self) -> String {
        match (self.min_bound, self.max_bound) {
            (None, None) => String::new(),
            (Some(low), None) => format!(" (at run time the lower bound is {low})"),
            (None, Some(high)) => format!(" (at run time the upper bound is {high})"),
            (Some(low), Some(high)) => format!(" (at run time the bounds are {low} and {high})"),
        }
    }
}

/// How the manual numbers a register: coils by number (`coil 17`), parameters whose code
/// is their decimal number as written (`303`), communication numbers in hex (`FA01`).
pub fn manual_number(space: Space, address: u16, code: &str) -> String {
    if space == Space::Coil {
        format!("coil {address}")
    } else if code.parse::<u16>().ok() == Some(address) {
        address.to_string()
    } else {
        format!("{address:04X}")
    }
}

/// One serial port of a drive with several (a 2-wire and a 4-wire RS-485 port).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInfo {
    /// Identifier in the drive file (`two_wire`).
    pub id: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// The registers setting this port: (what they set, register code).
    pub settings: &'static [(&'static str, &'static str)],
}

/// A drive's serial ports: each port's settings, the registers they share and the
/// registers that exist once per port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ports {
    /// The ports, the first being the one a client uses when it names none.
    pub ports: &'static [PortInfo],
    /// Codes of the registers both ports share.
    pub shared: &'static [&'static str],
    /// Registers that exist once per port: each row one code per port, in port order.
    pub registers: &'static [&'static [&'static str]],
}

impl Ports {
    /// The port with this identifier (case-insensitive) or English name.
    pub fn port(&self, name: &str) -> Option<&'static PortInfo> {
        self.ports
            .iter()
            .find(|port| port.id.eq_ignore_ascii_case(name) || port.name.eq_ignore_ascii_case(name))
    }

    /// The identifiers of the ports, for messages (`two_wire, four_wire`).
    pub fn ids(&self) -> String {
        let ids: Vec<&str> = self.ports.iter().map(|port| port.id).collect();
        ids.join(", ")
    }
}

/// One value of a code table: the number, its identifier and its names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeInfo {
    /// The value on the wire.
    pub value: u16,
    /// Identifier in the drive file (`even`).
    pub id: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name (empty when the manual gives none).
    pub name_zh: &'static str,
}

/// A code table (enumeration) of the manual, as data: what tools show beside a value and
/// accept instead of a number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeTableInfo {
    /// Identifier in the drive file (`parity`).
    pub id: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// The manual lists every value (otherwise a value may have no entry).
    pub exhaustive: bool,
    /// The values, in the manual's order.
    pub values: &'static [CodeInfo],
}

impl CodeTableInfo {
    /// The entry for `value`, if the table has one.
    pub fn find(&self, value: u16) -> Option<&'static CodeInfo> {
        self.values.iter().find(|code| code.value == value)
    }

    /// The entry whose identifier, English or Chinese name is `name` (case-insensitive).
    pub fn lookup(&self, name: &str) -> Option<&'static CodeInfo> {
        self.values.iter().find(|code| {
            code.id.eq_ignore_ascii_case(name)
                || code.name.eq_ignore_ascii_case(name)
                || (!code.name_zh.is_empty() && code.name_zh == name)
        })
    }
}

/// One named field of a bit-field word (reserved bits are left out).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BitFieldInfo {
    /// Identifier in the drive file (`run`).
    pub id: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// The field's bits within the word.
    pub mask: u16,
    /// What 0 means (empty when the manual does not say).
    pub zero: &'static str,
    /// What 1 means (empty when the manual does not say).
    pub one: &'static str,
    /// The code table naming a multi-bit field's values, if any.
    pub codes: Option<&'static CodeTableInfo>,
}

impl BitFieldInfo {
    /// The field's value in `word`, shifted down to bit 0.
    pub fn value(&self, word: u16) -> u16 {
        if self.mask == 0 {
            0
        } else {
            (word & self.mask) >> self.mask.trailing_zeros()
        }
    }

    /// Whether the field is one bit wide.
    pub fn is_flag(&self) -> bool {
        self.mask.count_ones() == 1
    }
}

/// The layout of a bit-field word, as data.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BitWordInfo {
    /// Identifier in the drive file (`command_word`).
    pub id: &'static str,
    /// English name.
    pub name: &'static str,
    /// The manual's Chinese name.
    pub name_zh: &'static str,
    /// Named fields, from the most significant bit down.
    pub fields: &'static [BitFieldInfo],
}

impl BitWordInfo {
    /// The field with this identifier or English name (case-insensitive).
    pub fn field(&self, name: &str) -> Option<&'static BitFieldInfo> {
        self.fields.iter().find(|field| {
            field.id.eq_ignore_ascii_case(name) || field.name.eq_ignore_ascii_case(name)
        })
    }
}

/// One entry of a drive's error-code table.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ErrorCodeInfo {
    /// The code carried by the error reply.
    pub code: u16,
    /// Identifier (`data_error`).
    pub id: Text,
    /// English name.
    pub name: Text,
    /// The manual's Chinese name.
    pub name_zh: Text,
    /// The manual's explanation.
    pub meaning: Text,
    /// The code as the manual prints it (`H0C`, `000Ch`, `17`); empty: not stated, shown as
    /// two hex digits and `h` ([`ErrorCodeInfo::shown`]).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "str::is_empty"))]
    pub printed_as: Text,
}

impl ErrorCodeInfo {
    /// An entry of a generated error-code table.
    pub const fn new(
        code: u16,
        id: &'static str,
        name: &'static str,
        name_zh: &'static str,
        meaning: &'static str,
    ) -> ErrorCodeInfo {
        ErrorCodeInfo::new_printed(code, id, name, name_zh, meaning, "")
    }

    /// An entry of a generated error-code table whose manual prints the code as `printed`
    /// (the DV1's `H0C`).
    pub const fn new_printed(
        code: u16,
        id: &'static str,
        name: &'static str,
        name_zh: &'static str,
        meaning: &'static str,
        printed: &'static str,
    ) -> ErrorCodeInfo {
        ErrorCodeInfo {
            code,
            id: Cow::Borrowed(id),
            name: Cow::Borrowed(name),
            name_zh: Cow::Borrowed(name_zh),
            meaning: Cow::Borrowed(meaning),
            printed_as: Cow::Borrowed(printed),
        }
    }

    /// The code in the manual's notation (`H0C`), else as two hex digits and `h` (`0Ch`).
    pub fn shown(&self) -> String {
        if self.printed_as.is_empty() {
            format!("{:02X}h", self.code)
        } else {
            self.printed_as.to_string()
        }
    }
}

/// Decimal places a scale implies: 0.01 gives 2, 1 gives 0 (at most 6).
pub fn decimals_of(scale: f64) -> u8 {
    let mut decimals = 0u8;
    let mut step = scale;
    while decimals < 6 && (step - step.round()).abs() > 1e-9 {
        step *= 10.0;
        decimals += 1;
    }
    decimals
}

#[cfg(test)]
mod manual_number_tests {
    use super::*;

    #[test]
    fn registers_are_numbered_as_their_manual_numbers_them() {
        assert_eq!(manual_number(Space::Coil, 17, "FREEZE"), "coil 17");
        assert_eq!(manual_number(Space::Parameter, 303, "303"), "303");
        assert_eq!(manual_number(Space::Parameter, 0xFA01, "FA01"), "FA01");
        assert_eq!(manual_number(Space::Parameter, 0x0011, "FH"), "0011");
        let fh = RegisterInfo::new(0x0011, "FH", "maximum_frequency")
            .with_names("Maximum frequency", "最高频率");
        assert_eq!(
            fh.label(),
            "register 0011 FH (Maximum frequency / 最高频率)"
        );
        let p303 = RegisterInfo::new(303, "303", "maximum_reference")
            .with_names("Maximum reference", "最大参考值");
        assert_eq!(
            p303.label(),
            "parameter 303 (Maximum reference / 最大参考值)"
        );
        let coil = RegisterInfo::new(17, "CTW", "control")
            .with_names("Control", "控制")
            .with_space(Space::Coil);
        assert_eq!(coil.label(), "coil 17 CTW (Control / 控制)");
    }
}
