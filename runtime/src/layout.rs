//! Frame layouts as data: the parts a protocol description builds frames from.
//!
//! A [`FrameLayout`] is an ordered list of [`Part`]s. Generated code holds layouts in
//! `static` items (every list is a borrowed [`Cow`]); the code generator builds the same
//! types at run time (owned) to check a description's example frames while reading it.

use std::borrow::Cow;

/// Text that is `&'static str` in generated code and owned in the generator.
pub type Text = Cow<'static, str>;
/// A list that is a `&'static [T]` in generated code and a `Vec<T>` in the generator.
pub type List<T> = Cow<'static, [T]>;

/// The most parts one layout may have; decoded values live in a fixed array of this size.
pub const MAX_PARTS: usize = 16;

/// One frame layout, for example "ASCII read request" or "binary error reply".
#[derive(Debug, Clone, PartialEq)]
pub struct FrameLayout {
    /// Name used in error messages, e.g. `read_request`.
    pub name: Text,
    /// The parts in wire order.
    pub parts: List<Part>,
}

/// One part of a frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Part {
    /// Fixed bytes, such as a start character or a terminator.
    Literal {
        /// Name used in error messages, e.g. `start`.
        name: Text,
        /// The bytes.
        bytes: List<u8>,
        /// An optional literal is present on decode when the next bytes equal it.
        optional: bool,
    },
    /// A value carried by the frame.
    Field(FieldSpec),
    /// A checksum over earlier bytes.
    Checksum(ChecksumSpec),
}

/// What a field means to the transaction engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Role {
    /// Station (inverter) address.
    Address,
    /// Command letter or function code.
    Command,
    /// Register (communication number) address.
    Register,
    /// Data word written or read.
    Data,
    /// Error code in an error reply.
    ErrorCode,
}

impl Role {
    /// The role's name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Role::Address => "address",
            Role::Command => "command",
            Role::Register => "register",
            Role::Data => "data",
            Role::ErrorCode => "error_code",
        }
    }
}

/// How a field's value is written on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
}

impl Format {
    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Format::Decimal => "decimal",
            Format::Hex => "hex",
            Format::Char => "char",
            Format::U8 => "u8",
            Format::U16Be => "u16be",
            Format::U16Le => "u16le",
        }
    }

    /// Whether the format is made of ASCII digits whose count may vary.
    pub const fn is_digits(self) -> bool {
        matches!(self, Format::Decimal | Format::Hex)
    }

    /// The fixed byte count of a binary or character format, `None` for digit formats.
    pub const fn fixed_len(self) -> Option<usize> {
        match self {
            Format::Char | Format::U8 => Some(1),
            Format::U16Be | Format::U16Le => Some(2),
            Format::Decimal | Format::Hex => None,
        }
    }

    /// Whether `byte` can start a value in this format (used for optional fields).
    pub fn accepts_digit(self, byte: u8) -> bool {
        match self {
            Format::Decimal => byte.is_ascii_digit(),
            Format::Hex => byte.is_ascii_hexdigit(),
            Format::Char => byte.is_ascii_graphic(),
            Format::U8 | Format::U16Be | Format::U16Le => true,
        }
    }
}

/// How a decoder decides whether an optional field is present.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Presence {
    /// Present when the next byte can start a value of the field's format
    /// (a digit for decimal fields).
    IfFormatMatches,
    /// Present when the next byte is at most this value (binary station addresses
    /// 0x00-0x3F never collide with command letters).
    IfByteAtMost(u8),
}

/// A value field.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldSpec {
    /// Field name, e.g. `register`.
    pub name: Text,
    /// What the field means.
    pub role: Role,
    /// Wire format.
    pub format: Format,
    /// Digit count on encode, and the most digits accepted on decode (digit formats only).
    pub width: u8,
    /// The fewest digits accepted on decode (digit formats only; equals `width` when fixed).
    pub min_width: u8,
    /// `Some` when the field may be left out.
    pub optional: Option<Presence>,
    /// Values the decoder accepts; empty means any.
    pub allowed: List<u32>,
    /// Compare `allowed` character values without regard to ASCII case.
    pub fold_case: bool,
}

/// Checksum algorithms the runtime supplies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChecksumAlgorithm {
    /// Low byte of the arithmetic sum of the covered bytes.
    Sum8,
    /// Exclusive-or of the covered bytes.
    Xor8,
}

impl ChecksumAlgorithm {
    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            ChecksumAlgorithm::Sum8 => "sum8",
            ChecksumAlgorithm::Xor8 => "xor8",
        }
    }
}

/// A checksum part.
#[derive(Debug, Clone, PartialEq)]
pub struct ChecksumSpec {
    /// Name used in error messages, e.g. `sum`.
    pub name: Text,
    /// The algorithm.
    pub algorithm: ChecksumAlgorithm,
    /// `Hex` (two ASCII digits) or `U8` (one byte).
    pub format: Format,
    /// Bytes that announce the checksum (`"&"`); they are covered by it.
    pub marker: List<u8>,
    /// Index of the first part covered; coverage runs up to the checksum value.
    pub covers_from: u8,
    /// Whether the checksum (with its marker) may be left out.
    pub optional: bool,
}

impl FrameLayout {
    /// Index of the first field with this role.
    pub fn index_of(&self, role: Role) -> Option<usize> {
        self.parts
            .iter()
            .position(|part| matches!(part, Part::Field(field) if field.role == role))
    }

    /// The field with this role.
    pub fn field(&self, role: Role) -> Option<&FieldSpec> {
        self.parts.iter().find_map(|part| match part {
            Part::Field(field) if field.role == role => Some(field),
            _ => None,
        })
    }

    /// The first byte sequence of the layout when it is a required literal (the start character).
    pub fn start_bytes(&self) -> Option<&[u8]> {
        match self.parts.first() {
            Some(Part::Literal {
                bytes,
                optional: false,
                ..
            }) => Some(bytes),
            _ => None,
        }
    }
}

impl Part {
    /// The part's name.
    pub fn name(&self) -> &str {
        match self {
            Part::Literal { name, .. } => name,
            Part::Field(field) => &field.name,
            Part::Checksum(checksum) => &checksum.name,
        }
    }
}
