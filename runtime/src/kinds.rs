//! The enumerations description files name above the frame level: register access, the
//! kinds of command, a value's shape on the wire, address spaces and engineering units.
//!
//! This module imports nothing from the rest of the crate, so every other module may use it.

/// Whether a register can be read, written or both over the serial link.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Access {
    /// Read only (monitors, status words).
    ReadOnly,
    /// Read and write.
    ReadWrite,
    /// Write only.
    WriteOnly,
}

impl Access {
    /// Every access.
    pub const ALL: [Access; 3] = [Access::ReadOnly, Access::ReadWrite, Access::WriteOnly];

    /// Name as written in drive files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Access::ReadOnly => "read-only",
            Access::ReadWrite => "read-write",
            Access::WriteOnly => "write-only",
        }
    }
}

/// What a command does, independent of its code on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum CommandKind {
    /// Read one register or parameter.
    Read,
    /// Write in RAM only (lost at power-off).
    WriteRam,
    /// Write in RAM and EEPROM (persistent; EEPROM wears out).
    WritePersistent,
    /// Read a text parameter.
    ReadText,
    /// Exchange process words only (control word and reference out, status word and
    /// output value back).
    Process,
    /// A block transfer: write the words the drive's write selection names and read the
    /// words its read selection names, in one exchange (the selection is the drive's, see
    /// `crate::protocol::BlockSpec`).
    Block,
    /// A diagnostic echo: the reply repeats the request's data (Modbus 08, sub-function
    /// 0000h, whose layout gives the sub-function the `register` role).
    Echo,
}

impl CommandKind {
    /// Every kind, in the order the description format documents them.
    pub const ALL: [CommandKind; 7] = [
        CommandKind::Read,
        CommandKind::WriteRam,
        CommandKind::WritePersistent,
        CommandKind::ReadText,
        CommandKind::Process,
        CommandKind::Block,
        CommandKind::Echo,
    ];

    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            CommandKind::Read => "read",
            CommandKind::WriteRam => "write_ram",
            CommandKind::WritePersistent => "write_persistent",
            CommandKind::ReadText => "read_text",
            CommandKind::Process => "process",
            CommandKind::Block => "block",
            CommandKind::Echo => "echo",
        }
    }

    /// Whether the command writes.
    pub const fn is_write(self) -> bool {
        matches!(self, CommandKind::WriteRam | CommandKind::WritePersistent)
    }

    /// Whether the reply reports the request's data back (a write's value written, an
    /// echo's data), so a reply carrying another value answers another request.
    pub const fn reports_data(self) -> bool {
        matches!(
            self,
            CommandKind::WriteRam | CommandKind::WritePersistent | CommandKind::Echo
        )
    }

    /// Whether the command only reads: sending it again changes nothing in the drive, so a
    /// master may repeat it after a failed exchange.
    pub const fn only_reads(self) -> bool {
        matches!(
            self,
            CommandKind::Read | CommandKind::ReadText | CommandKind::Echo
        )
    }
}

/// The shape of a register's value on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum DataType {
    /// 16 bits.
    Word,
    /// 32 bits.
    DoubleWord,
    /// One coil, written as FF00h (on) or 0000h (off).
    Bit,
    /// Text (read as bytes).
    Text,
    /// 8 bits: a register whose frames carry a narrower data field than a word's (two hex
    /// digits where the protocol's words take four), served by the commands that list
    /// `byte` among their `data_types`.
    Byte,
}

impl DataType {
    /// Every data type.
    pub const ALL: [DataType; 5] = [
        DataType::Word,
        DataType::DoubleWord,
        DataType::Bit,
        DataType::Text,
        DataType::Byte,
    ];

    /// Name as written in description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            DataType::Word => "word",
            DataType::DoubleWord => "double_word",
            DataType::Bit => "bit",
            DataType::Text => "text",
            DataType::Byte => "byte",
        }
    }

    /// The lowest and highest raw values a value of this shape can hold, signed
    /// (two's complement) or not: a word's, a double word's or a byte's.
    pub const fn raw_limits(self, signed: bool) -> (i64, i64) {
        match (self, signed) {
            (DataType::DoubleWord, true) => (i32::MIN as i64, i32::MAX as i64),
            (DataType::DoubleWord, false) => (0, u32::MAX as i64),
            (DataType::Byte, true) => (i8::MIN as i64, i8::MAX as i64),
            (DataType::Byte, false) => (0, u8::MAX as i64),
            (_, true) => (i16::MIN as i64, i16::MAX as i64),
            (_, false) => (0, u16::MAX as i64),
        }
    }

    /// Bytes the value takes in a frame (text: 0, it has no fixed size).
    pub const fn size(self) -> u8 {
        match self {
            DataType::Word | DataType::Bit => 2,
            DataType::DoubleWord => 4,
            DataType::Text => 0,
            DataType::Byte => 1,
        }
    }
}

/// Which numbering a register address belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Space {
    /// Parameters and communication numbers (the default).
    Parameter,
    /// Coils (bit addresses; 16 make a word).
    Coil,
}

impl Space {
    /// Every address space.
    pub const ALL: [Space; 2] = [Space::Parameter, Space::Coil];

    /// Name as written in description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Space::Parameter => "parameter",
            Space::Coil => "coil",
        }
    }
}

/// When a written value takes effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum TakesEffect {
    /// At once (the default).
    #[default]
    Immediately,
    /// Only after the drive is reset or powered off and on.
    AfterReset,
}

impl TakesEffect {
    /// Every value.
    pub const ALL: [TakesEffect; 2] = [TakesEffect::Immediately, TakesEffect::AfterReset];

    /// Name as written in description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            TakesEffect::Immediately => "immediately",
            TakesEffect::AfterReset => "after_reset",
        }
    }
}

/// A unit a register's value is expressed in, after scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub enum Unit {
    /// A plain number (counts, codes, raw words).
    #[cfg_attr(feature = "serde", serde(rename = ""))]
    None,
    /// Hertz.
    #[cfg_attr(feature = "serde", serde(rename = "Hz"))]
    Hertz,
    /// Seconds.
    #[cfg_attr(feature = "serde", serde(rename = "s"))]
    Second,
    /// Percent.
    #[cfg_attr(feature = "serde", serde(rename = "%"))]
    Percent,
    /// Amperes.
    #[cfg_attr(feature = "serde", serde(rename = "A"))]
    Ampere,
    /// Volts.
    #[cfg_attr(feature = "serde", serde(rename = "V"))]
    Volt,
    /// Hours.
    #[cfg_attr(feature = "serde", serde(rename = "h"))]
    Hour,
    /// Kilowatts.
    #[cfg_attr(feature = "serde", serde(rename = "kW"))]
    Kilowatt,
    /// Revolutions per minute.
    #[cfg_attr(feature = "serde", serde(rename = "rpm"))]
    Rpm,
}

impl Unit {
    /// Every unit, in the order the description format documents them.
    pub const ALL: [Unit; 9] = [
        Unit::None,
        Unit::Hertz,
        Unit::Second,
        Unit::Percent,
        Unit::Ampere,
        Unit::Volt,
        Unit::Hour,
        Unit::Kilowatt,
        Unit::Rpm,
    ];

    /// The symbol written in drive files and shown to people (`Hz`); empty for [`Unit::None`].
    pub const fn symbol(self) -> &'static str {
        match self {
            Unit::None => "",
            Unit::Hertz => "Hz",
            Unit::Second => "s",
            Unit::Percent => "%",
            Unit::Ampere => "A",
            Unit::Volt => "V",
            Unit::Hour => "h",
            Unit::Kilowatt => "kW",
            Unit::Rpm => "rpm",
        }
    }

    /// The unit for a symbol as written in drive files.
    pub fn from_symbol(symbol: &str) -> Option<Unit> {
        Unit::ALL.into_iter().find(|unit| unit.symbol() == symbol)
    }

    /// Name of the quantity type in this module (`Hertz`), `None` for plain numbers.
    pub const fn quantity_type(self) -> Option<&'static str> {
        match self {
            Unit::None => None,
            Unit::Hertz => Some("Hertz"),
            Unit::Second => Some("Seconds"),
            Unit::Percent => Some("Percent"),
            Unit::Ampere => Some("Amperes"),
            Unit::Volt => Some("Volts"),
            Unit::Hour => Some("Hours"),
            Unit::Kilowatt => Some("Kilowatts"),
            Unit::Rpm => Some("Rpm"),
        }
    }
}
