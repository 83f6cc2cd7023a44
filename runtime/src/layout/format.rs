//! How values and frames go on the wire: a field's [`Format`], a layout's [`Encoding`].

/// Bytes a checksum value occupies in `format`.
pub const fn checksum_size(format: Format) -> usize {
    match format {
        Format::Hex | Format::U16Be | Format::U16Le => 2,
        _ => 1,
    }
}

/// How a layout's bytes go on the wire.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Encoding {
    /// As the parts give them.
    #[default]
    Binary,
    /// A literal first part (`:`) and a literal last part (CR LF) as they are, every byte in
    /// between as two upper-case hex digits (Modbus ASCII). Lengths count, and checksums
    /// cover, the bytes before they are written as digits.
    HexPairs,
}

impl Encoding {
    /// Name as written in protocol files (`hex_pairs`).
    pub const fn as_str(self) -> &'static str {
        match self {
            Encoding::Binary => "binary",
            Encoding::HexPairs => "hex_pairs",
        }
    }
}

/// How a field's value is written on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Format {
    /// ASCII decimal digits, most significant first (`"31"`).
    Decimal,
    /// ASCII hexadecimal digits, upper case on encode, either case on decode (`"FA01"`).
    Hex,
    /// One ASCII character; the value is its byte (`'R'` is 0x52).
    Char,
    /// One binary byte.
    U8,
    /// Two binary bytes, most significant first.
    U16Be,
    /// Two binary bytes, least significant first.
    U16Le,
    /// Four binary bytes, most significant first.
    U32Be,
    /// Four binary bytes, least significant first.
    U32Le,
    /// An unsigned integer of `min_width..=width` bytes (at most 4), most significant first;
    /// its size comes from a length part or from the value's data type.
    #[cfg_attr(feature = "serde", serde(rename = "uint_be"))]
    UintBe,
    /// Like [`Format::UintBe`], least significant byte first (FC coil data).
    #[cfg_attr(feature = "serde", serde(rename = "uint_le"))]
    UintLe,
    /// Raw bytes (text); the value is their offset in the frame, the width their count.
    Bytes,
}

impl Format {
    /// The largest number a field of this format and `width` (digits, for text formats)
    /// carries.
    pub fn max_value(self, width: u8) -> u32 {
        let digits = |radix: u32| {
            radix
                .checked_pow(u32::from(width))
                .map_or(u32::MAX, |n| n - 1)
        };
        match self {
            Format::Decimal => digits(10),
            Format::Hex => digits(16),
            Format::Char | Format::U8 => 0xFF,
            Format::U16Be | Format::U16Le => 0xFFFF,
            Format::U32Be | Format::U32Le | Format::UintBe | Format::UintLe | Format::Bytes => {
                u32::MAX
            }
        }
    }

    /// Every format, in the order the description format documents them.
    pub const ALL: [Format; 11] = [
        Format::Decimal,
        Format::Hex,
        Format::Char,
        Format::U8,
        Format::U16Be,
        Format::U16Le,
        Format::U32Be,
        Format::U32Le,
        Format::UintBe,
        Format::UintLe,
        Format::Bytes,
    ];

    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Format::Decimal => "decimal",
            Format::Hex => "hex",
            Format::Char => "char",
            Format::U8 => "u8",
            Format::U16Be => "u16be",
            Format::U16Le => "u16le",
            Format::U32Be => "u32be",
            Format::U32Le => "u32le",
            Format::UintBe => "uint_be",
            Format::UintLe => "uint_le",
            Format::Bytes => "bytes",
        }
    }

    /// Whether the format is made of ASCII digits whose count may vary.
    #[inline]
    pub const fn is_digits(self) -> bool {
        matches!(self, Format::Decimal | Format::Hex)
    }

    /// The fixed byte count of a binary or character format, `None` for digit formats.
    #[inline]
    pub const fn fixed_len(self) -> Option<usize> {
        match self {
            Format::Char | Format::U8 => Some(1),
            Format::U16Be | Format::U16Le => Some(2),
            Format::U32Be | Format::U32Le => Some(4),
            Format::Decimal | Format::Hex | Format::UintBe | Format::UintLe | Format::Bytes => None,
        }
    }

    /// Whether `byte` can start a value in this format (used for optional fields).
    #[inline]
    pub fn accepts_digit(self, byte: u8) -> bool {
        match self {
            Format::Decimal => byte.is_ascii_digit(),
            Format::Hex => byte.is_ascii_hexdigit(),
            Format::Char => byte.is_ascii_graphic(),
            _ => true,
        }
    }
}
