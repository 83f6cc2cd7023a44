//! Frame layouts as data: the parts a protocol description builds frames from.
//!
//! A [`FrameLayout`] is an ordered list of [`Part`]s. Generated code holds layouts in
//! `static` items (every list is a borrowed [`Cow`]); the code generator builds the same
//! types at run time (owned) to check a description's example frames while reading it.

use std::borrow::Cow;

// Sizes of fixed parts, used by the codec to size rest-of-frame fields.
impl Part {
    /// The part's size in bytes when it does not depend on the frame, `None` otherwise.
    pub fn fixed_size(&self) -> Option<usize> {
        match self {
            Part::Literal {
                bytes,
                optional: false,
                ..
            } => Some(bytes.len()),
            Part::Literal { .. } => None,
            Part::Field(field) if field.optional.is_some() || field.role == Role::Words => None,
            Part::Field(field) => match field.format {
                Format::Decimal | Format::Hex if field.min_width == field.width => {
                    Some(usize::from(field.width))
                }
                Format::UintBe | Format::UintLe | Format::Bytes
                    if field.sized_by == SizedBy::Format && field.min_width == field.width =>
                {
                    Some(usize::from(field.width))
                }
                format => format.fixed_len(),
            },
            Part::Checksum(spec) if !spec.optional => {
                Some(spec.marker.len() + checksum_size(spec.format))
            }
            Part::Checksum(_) => None,
            Part::Word(word) => word.format.fixed_len(),
            Part::Length(length) => length.format.fixed_len(),
        }
    }
}

/// Bytes a checksum value occupies in `format`.
pub const fn checksum_size(format: Format) -> usize {
    match format {
        Format::Hex | Format::U16Be | Format::U16Le => 2,
        _ => 1,
    }
}

/// Text that is `&'static str` in generated code and owned in the generator.
pub type Text = Cow<'static, str>;
/// A list that is a `&'static [T]` in generated code and a `Vec<T>` in the generator.
pub type List<T> = Cow<'static, [T]>;

/// The most parts one layout may have; decoded values live in a fixed array of this size.
pub const MAX_PARTS: usize = 16;

/// One frame layout, for example "ASCII read request" or "binary error reply".
///
/// Two layouts are equal when their name, parts and encoding are: the plan is derived
/// from them.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameLayout {
    /// Name used in error messages, e.g. `read_request`.
    pub name: Text,
    /// The parts in wire order.
    pub parts: List<Part>,
    /// How the frame's bytes go on the wire.
    pub encoding: Encoding,
    /// The layout's [`FramePlan`] (its fast encoder and decoder), computed from the parts
    /// by [`FramePlan::of`] (generated layouts hold it as const data; see
    /// [`FrameLayout::planned`]); `None`: the interpreter handles every frame. A plan must
    /// be the one computed from these parts: after changing the parts, call
    /// [`FrameLayout::planned`] again.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub plan: Option<FramePlan>,
}

impl PartialEq for FrameLayout {
    fn eq(&self, other: &FrameLayout) -> bool {
        self.name == other.name && self.parts == other.parts && self.encoding == other.encoding
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

/// One part of a frame.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
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
    /// A word made of bit fields.
    Word(WordSpec),
    /// A computed length.
    Length(LengthSpec),
}

/// What a field means to the transaction engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
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
    /// Array index of an indexed parameter.
    Index,
    /// First process word (control word out, status word back).
    #[cfg_attr(feature = "serde", serde(rename = "process_1"))]
    Process1,
    /// Second process word (reference out, output value back).
    #[cfg_attr(feature = "serde", serde(rename = "process_2"))]
    Process2,
    /// Text carried by the frame (raw bytes).
    Text,
    /// How many decimal places the data has, as a number (an Eaton data reply's unit digit:
    /// 0 for whole units, 1 for tenths, 2 for hundredths, 3 for thousandths).
    Decimals,
    /// A run of 16-bit words, each in the field's format (`u16be` or `u16le`), sized by a
    /// length part: the words a block transfer writes (request) or reads (reply). Held
    /// like a bytes field: its offset in the frame and its byte count.
    Words,
    /// How many words a block-transfer request asks the reply to carry (the reply says how
    /// many it carries with a length part counting its words).
    ReadCount,
    /// A block-transfer reply's write status: bit `n` set means the word at position `n`
    /// of the request (0: the first) was not written.
    WriteStatus,
    /// How long the drive waits before it replies, in tens of milliseconds, as the request
    /// asks (the Eaton protocol's wait-time digit, 0-F): the master adds it to its reply
    /// timeout ([`crate::transaction::Master::with_reply_wait`]), the virtual drive waits.
    ReplyWait,
}

impl Role {
    /// Every role, in the order the description format documents them.
    pub const ALL: [Role; 14] = [
        Role::Address,
        Role::Command,
        Role::Register,
        Role::Data,
        Role::ErrorCode,
        Role::Index,
        Role::Process1,
        Role::Process2,
        Role::Text,
        Role::Decimals,
        Role::Words,
        Role::ReadCount,
        Role::WriteStatus,
        Role::ReplyWait,
    ];

    /// The role's name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Role::Address => "address",
            Role::Command => "command",
            Role::Register => "register",
            Role::Data => "data",
            Role::ErrorCode => "error_code",
            Role::Index => "index",
            Role::Process1 => "process_1",
            Role::Process2 => "process_2",
            Role::Text => "text",
            Role::Decimals => "decimals",
            Role::Words => "words",
            Role::ReadCount => "read_count",
            Role::WriteStatus => "write_status",
            Role::ReplyWait => "reply_wait",
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

/// How a decoder decides whether an optional field is present.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Presence {
    /// Present when the next byte can start a value of the field's format
    /// (a digit for decimal fields).
    IfFormatMatches,
    /// Present when the next byte is at most this value (binary station addresses
    /// 0x00-0x3F never collide with command letters).
    IfByteAtMost(u8),
}

/// Where a variable-size field's size comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum SizedBy {
    /// The format: fixed bytes, or as many digits as are there (`min_width..=width`).
    Format,
    /// Whatever the frame's length part leaves between this field and the fixed-size
    /// parts after it (FC text blocks).
    Rest,
    /// A length part that covers exactly this field (Modbus byte count).
    Length,
}

impl SizedBy {
    /// Every rule.
    pub const ALL: [SizedBy; 3] = [SizedBy::Format, SizedBy::Rest, SizedBy::Length];

    /// Name of the rule: `rest` and `length` as written under `size:` in protocol
    /// description files; `format` is what leaving `size` out means.
    pub const fn as_str(self) -> &'static str {
        match self {
            SizedBy::Format => "format",
            SizedBy::Rest => "rest",
            SizedBy::Length => "length",
        }
    }
}

/// A value field.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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
    /// Where the field's size comes from.
    pub sized_by: SizedBy,
    /// How a station address field addresses several stations at once (broadcast and
    /// group addressing); `None` for other fields and for protocols without broadcasts.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub broadcast: Option<BroadcastAddress>,
}

/// The broadcast encodings of a station address field (protocol file: `broadcast:` on the
/// address part): what stands in the field's place to address every station, and the
/// character that leaves one digit open to address a group.
///
/// In [`crate::codec::FrameValues`] a station number with open digits (a group, or every
/// station written as `**`) is held as [`BroadcastAddress::OPEN`] | the open digits' mask
/// (bit 0: the last digit) << [`BroadcastAddress::MASK_SHIFT`] | the value of the closed
/// digits; [`crate::broadcast`] converts it.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BroadcastAddress {
    /// Bytes written instead of the station number to address every station (`"**"`);
    /// empty when a value does it.
    pub all_bytes: List<u8>,
    /// The station value that addresses every station (FFh; Modbus 0), when a value does.
    pub all_value: Option<u32>,
    /// A character standing for any one digit of a digit-format station number (`*`):
    /// group addressing (`*9`: every station whose last digit is 9).
    pub wildcard: Option<u8>,
}

impl BroadcastAddress {
    /// Flag of a field value holding open digits.
    pub const OPEN: u32 = 1 << 31;
    /// Position of the open digits' mask in a field value.
    pub const MASK_SHIFT: u32 = 24;

    /// Every station is addressed by `bytes` in the field's place.
    pub const fn bytes(bytes: &'static [u8]) -> BroadcastAddress {
        BroadcastAddress {
            all_bytes: Cow::Borrowed(bytes),
            all_value: None,
            wildcard: None,
        }
    }

    /// Every station is addressed by the field value `value`.
    pub const fn value(value: u32) -> BroadcastAddress {
        BroadcastAddress {
            all_bytes: Cow::Borrowed(&[]),
            all_value: Some(value),
            wildcard: None,
        }
    }

    /// `character` leaves one digit open (group addressing).
    pub const fn with_wildcard(mut self, character: u8) -> BroadcastAddress {
        self.wildcard = Some(character);
        self
    }

    /// Whether a field value holds open digits.
    #[inline]
    pub const fn is_open(value: u32) -> bool {
        value & Self::OPEN != 0
    }

    /// Whether `byte` can begin a broadcast station field.
    #[inline]
    pub fn starts_with(&self, byte: u8) -> bool {
        self.all_bytes.first() == Some(&byte)
            || self.wildcard == Some(byte)
            || self.all_value == Some(u32::from(byte))
    }
}

/// A word whose bits hold several fields (the FC PKE: command nibble + parameter number).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct WordSpec {
    /// Name used in error messages, e.g. `pke`.
    pub name: Text,
    /// `U16Be`, `U16Le`, `U32Be` or `U32Le`.
    pub format: Format,
    /// The fields, each a run of bits.
    pub fields: List<BitsSpec>,
}

/// A run of bits inside a [`WordSpec`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BitsSpec {
    /// Field name, e.g. `ak`.
    pub name: Text,
    /// What it means.
    pub role: Role,
    /// Lowest bit.
    pub lsb: u8,
    /// Bit count.
    pub width: u8,
    /// Values the decoder accepts; empty means any.
    pub allowed: List<u32>,
}

impl BitsSpec {
    /// The bits' mask within the word.
    #[inline]
    pub const fn mask(&self) -> u32 {
        (((1u64 << self.width) - 1) << self.lsb) as u32
    }
}

/// A length computed on encode and checked on decode: the byte count of a run of parts
/// (FC LGE, Modbus byte count), or the size of the request's data (Modbus quantity).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LengthSpec {
    /// Name used in error messages, e.g. `lge`.
    pub name: Text,
    /// `U8` or `U16Be`.
    pub format: Format,
    /// What is counted.
    pub counts: Counts,
    /// The value is the byte count times `times` divided by `per` (16 coils per 2 bytes:
    /// times 8; registers: per 2).
    pub times: u8,
    /// See `times`.
    pub per: u8,
}

/// What a [`LengthSpec`] counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Counts {
    /// The bytes of parts `from..=through` (indexes into the layout).
    Parts {
        /// First counted part.
        from: u8,
        /// Last counted part.
        through: u8,
    },
    /// The size of the request's data (its data type), which the frame itself does not carry.
    DataSize,
}

/// Checksum algorithms the runtime supplies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ChecksumAlgorithm {
    /// Low byte of the arithmetic sum of the covered bytes.
    Sum8,
    /// Exclusive-or of the covered bytes.
    Xor8,
    /// CRC-16 as Modbus RTU defines it (polynomial A001h reflected, initial FFFFh),
    /// sent low byte first.
    Crc16Modbus,
    /// Two's complement of the byte sum (Modbus ASCII LRC).
    Lrc8,
}

impl ChecksumAlgorithm {
    /// Every algorithm.
    pub const ALL: [ChecksumAlgorithm; 4] = [
        ChecksumAlgorithm::Sum8,
        ChecksumAlgorithm::Xor8,
        ChecksumAlgorithm::Crc16Modbus,
        ChecksumAlgorithm::Lrc8,
    ];

    /// Name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            ChecksumAlgorithm::Sum8 => "sum8",
            ChecksumAlgorithm::Xor8 => "xor8",
            ChecksumAlgorithm::Crc16Modbus => "crc16_modbus",
            ChecksumAlgorithm::Lrc8 => "lrc8",
        }
    }
}

/// A checksum part.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ChecksumSpec {
    /// Name used in error messages, e.g. `sum`.
    pub name: Text,
    /// The algorithm.
    pub algorithm: ChecksumAlgorithm,
    /// `Hex` (two ASCII digits), `U8` (one byte) or `U16Le` (CRC-16).
    pub format: Format,
    /// Bytes that announce the checksum (`"&"`); they are covered by it.
    pub marker: List<u8>,
    /// Index of the first part covered; coverage runs up to the checksum value.
    pub covers_from: u8,
    /// Index of the last part covered, where coverage ends before the checksum (an ETX
    /// between the data and the sum that the sum leaves out); `None`: up to the value.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub covers_through: Option<u8>,
    /// Whether the checksum (with its marker) may be left out.
    pub optional: bool,
}

impl FrameLayout {
    /// The literal bytes sent as they are around a [`Encoding::HexPairs`] frame: the first
    /// part's and the last part's, when they are required literals.
    pub fn verbatim_ends(&self) -> (&[u8], &[u8]) {
        fn literal(part: Option<&Part>) -> &[u8] {
            match part {
                Some(Part::Literal {
                    bytes,
                    optional: false,
                    ..
                }) => bytes,
                _ => &[],
            }
        }
        let head = literal(self.parts.first());
        let tail = if self.parts.len() > 1 {
            literal(self.parts.last())
        } else {
            &[]
        };
        (head, tail)
    }

    /// Where `len` bytes that begin at byte `start` of the frame's bytes lie on the wire:
    /// the same place, or for [`Encoding::HexPairs`] the hex digits that carry them.
    pub fn wire_span(&self, start: usize, len: usize) -> (usize, usize) {
        match self.encoding {
            Encoding::Binary => (start, len),
            Encoding::HexPairs => {
                let head = self.verbatim_ends().0.len();
                (head + 2 * start.saturating_sub(head), 2 * len)
            }
        }
    }

    /// Index of the first field with this role (plain fields only; see [`Self::locate`]).
    pub fn index_of(&self, role: Role) -> Option<usize> {
        self.parts
            .iter()
            .position(|part| matches!(part, Part::Field(field) if field.role == role))
    }

    /// Where the value with this role lives: a field, or bits of a word.
    pub fn locate(&self, role: Role) -> Option<(usize, Option<&BitsSpec>)> {
        self.parts
            .iter()
            .enumerate()
            .find_map(|(index, part)| match part {
                Part::Field(field) if field.role == role => Some((index, None)),
                Part::Word(word) => word
                    .fields
                    .iter()
                    .find(|bits| bits.role == role)
                    .map(|bits| (index, Some(bits))),
                _ => None,
            })
    }

    /// Whether the layout carries a value with this role.
    pub fn has(&self, role: Role) -> bool {
        self.locate(role).is_some()
    }

    /// The codes the layout's command field (or command bits of a word) allows; empty when
    /// it allows any or has none.
    pub fn allowed_commands(&self) -> &[u32] {
        for part in self.parts.iter() {
            match part {
                Part::Field(field) if field.role == Role::Command => return &field.allowed,
                Part::Word(word) => {
                    if let Some(bits) = word.fields.iter().find(|b| b.role == Role::Command) {
                        return &bits.allowed;
                    }
                }
                _ => {}
            }
        }
        &[]
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
            Part::Word(word) => &word.name,
            Part::Length(length) => &length.name,
        }
    }
}

/// Const constructors: generated code writes each part as one of these followed by the
/// `with_*` calls for what differs from the defaults, so layouts stay short and readable.
impl Part {
    /// Fixed bytes that are always present.
    pub const fn literal(name: &'static str, bytes: &'static [u8]) -> Part {
        Part::Literal {
            name: Cow::Borrowed(name),
            bytes: Cow::Borrowed(bytes),
            optional: false,
        }
    }

    /// Fixed bytes that may be left out (present on decode when the next bytes equal them).
    pub const fn optional_literal(name: &'static str, bytes: &'static [u8]) -> Part {
        Part::Literal {
            name: Cow::Borrowed(name),
            bytes: Cow::Borrowed(bytes),
            optional: true,
        }
    }
}

impl FieldSpec {
    /// A field of exactly `width` digits or bytes, always present, any value, sized by its
    /// format.
    pub const fn new(name: &'static str, role: Role, format: Format, width: u8) -> FieldSpec {
        FieldSpec {
            name: Cow::Borrowed(name),
            role,
            format,
            width,
            min_width: width,
            optional: None,
            allowed: Cow::Borrowed(&[]),
            fold_case: false,
            sized_by: SizedBy::Format,
            broadcast: None,
        }
    }

    /// A station address that may also address every station, or a group.
    pub const fn with_broadcast(mut self, broadcast: BroadcastAddress) -> FieldSpec {
        // A const fn cannot drop the old value; it is `None` when built by `new`.
        core::mem::forget(self.broadcast.replace(broadcast));
        self
    }

    /// Accepts as few as `min_width` digits or bytes on decode.
    pub const fn with_min_width(mut self, min_width: u8) -> FieldSpec {
        self.min_width = min_width;
        self
    }

    /// Present only when `presence` says so.
    pub const fn with_optional(mut self, presence: Presence) -> FieldSpec {
        self.optional = Some(presence);
        self
    }

    /// Only these values are accepted.
    pub const fn with_allowed(mut self, allowed: &'static [u32]) -> FieldSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(
            &mut self.allowed,
            Cow::Borrowed(allowed),
        ));
        self
    }

    /// A lower-case letter is accepted and means "tripped".
    pub const fn with_fold_case(mut self) -> FieldSpec {
        self.fold_case = true;
        self
    }

    /// Sized other than by its format.
    pub const fn with_sized_by(mut self, sized_by: SizedBy) -> FieldSpec {
        self.sized_by = sized_by;
        self
    }
}

impl ChecksumSpec {
    /// A checksum covering the parts from `covers_from` to the byte before it, always
    /// present, with no marker.
    pub const fn new(
        name: &'static str,
        algorithm: ChecksumAlgorithm,
        format: Format,
        covers_from: u8,
    ) -> ChecksumSpec {
        ChecksumSpec {
            name: Cow::Borrowed(name),
            algorithm,
            format,
            marker: Cow::Borrowed(&[]),
            covers_from,
            covers_through: None,
            optional: false,
        }
    }

    /// Covers the parts up to and including the one at `index` only.
    pub const fn with_covers_through(mut self, index: u8) -> ChecksumSpec {
        self.covers_through = Some(index);
        self
    }

    /// Announced by these bytes.
    pub const fn with_marker(mut self, marker: &'static [u8]) -> ChecksumSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(&mut self.marker, Cow::Borrowed(marker)));
        self
    }

    /// May be left out.
    pub const fn with_optional(mut self) -> ChecksumSpec {
        self.optional = true;
        self
    }
}

impl BitsSpec {
    /// `width` bits from `lsb`, any value.
    pub const fn new(name: &'static str, role: Role, lsb: u8, width: u8) -> BitsSpec {
        BitsSpec {
            name: Cow::Borrowed(name),
            role,
            lsb,
            width,
            allowed: Cow::Borrowed(&[]),
        }
    }

    /// Only these values are accepted.
    pub const fn with_allowed(mut self, allowed: &'static [u32]) -> BitsSpec {
        // A const fn cannot drop the old value, so it is forgotten: nothing to free when it
        // is borrowed, as in generated code (an owned one would leak).
        core::mem::forget(core::mem::replace(
            &mut self.allowed,
            Cow::Borrowed(allowed),
        ));
        self
    }
}

impl LengthSpec {
    /// A length in `format` counting `counts` one for one.
    pub const fn new(name: &'static str, format: Format, counts: Counts) -> LengthSpec {
        LengthSpec {
            name: Cow::Borrowed(name),
            format,
            counts,
            times: 1,
            per: 1,
        }
    }

    /// The count is multiplied by `times` and divided by `per`.
    pub const fn with_ratio(mut self, times: u8, per: u8) -> LengthSpec {
        self.times = times;
        self.per = per;
        self
    }
}

/// The value of one part of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FieldValue {
    /// Whether the part is in the frame (always true for required parts after decoding).
    pub present: bool,
    /// The value: a field's number, a word's bits, a checksum's or length's received
    /// value, the offset of a bytes field in the frame; 0 for literals.
    pub value: u32,
    /// Digits (digit formats) or bytes (variable binary formats) on the wire; 0 means
    /// the layout's width.
    pub width: u8,
}

/// Values of every part of one frame, indexed like the layout's parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameValues {
    /// One slot per layout part.
    pub parts: [FieldValue; MAX_PARTS],
    /// Size in bytes of the request's data, for length parts that count it (Modbus
    /// quantity) and for variable-width data fields. Above 4, the data field carries a
    /// block of registers: its slot holds the block's offset in the frame and its width,
    /// as a bytes field does ([`FrameValues::bytes`] gives the bytes).
    pub data_size: u8,
}

impl FrameValues {
    /// Sets the value with `role` (a field or bits of a word) and marks it present.
    /// Returns false when the layout has no such value.
    pub fn set(&mut self, layout: &FrameLayout, role: Role, value: u32) -> bool {
        match layout.locate(role) {
            Some((index, None)) => {
                self.parts[index].present = true;
                self.parts[index].value = value;
                true
            }
            Some((index, Some(bits))) => {
                let slot = &mut self.parts[index];
                slot.present = true;
                slot.value = (slot.value & !bits.mask()) | ((value << bits.lsb) & bits.mask());
                true
            }
            None => false,
        }
    }

    /// The value with `role`, when the layout has it and the frame carries it. For a
    /// bytes field this is the offset of the bytes; see [`FrameValues::bytes`].
    pub fn get(&self, layout: &FrameLayout, role: Role) -> Option<u32> {
        let (index, bits) = layout.locate(role)?;
        let slot = self.parts[index];
        if !slot.present {
            return None;
        }
        Some(match bits {
            None => slot.value,
            Some(bits) => (slot.value & bits.mask()) >> bits.lsb,
        })
    }

    /// The bytes of the bytes field with `role` in `frame` (the frame these values were
    /// decoded from), as they lie on the wire: for an [`Encoding::HexPairs`] layout, the
    /// hex digits that carry them (two per byte; [`FrameValues::words`] and
    /// [`FrameValues::data_words`] give their values).
    pub fn bytes<'f>(&self, layout: &FrameLayout, role: Role, frame: &'f [u8]) -> Option<&'f [u8]> {
        let index = layout.index_of(role)?;
        let slot = self.parts[index];
        let (start, len) = layout.wire_span(slot.value as usize, usize::from(slot.width));
        slot.present
            .then(|| frame.get(start..start + len))
            .flatten()
    }
    /// Marks every optional part named in `names` present (e.g. `["sum", "end"]`).
    pub fn include(&mut self, layout: &FrameLayout, names: &[&str]) {
        for (index, part) in layout.parts.iter().enumerate() {
            if names.iter().any(|name| *name == part.name()) {
                self.parts[index].present = true;
            }
        }
    }
}

/// The values of every role of a frame, gathered in one pass over the layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Roles {
    /// Station address.
    pub address: Option<u32>,
    /// Command code.
    pub command: Option<u32>,
    /// Register (wire number).
    pub register: Option<u32>,
    /// Array index.
    pub index: Option<u32>,
    /// Data.
    pub data: Option<u32>,
    /// Error code.
    pub error_code: Option<u32>,
    /// First process word.
    pub process_1: Option<u32>,
    /// Second process word.
    pub process_2: Option<u32>,
    /// Decimal places of the data.
    pub decimals: Option<u32>,
}

impl Roles {
    /// The value given for `role`, for the roles this type holds.
    #[inline]
    pub fn value(&self, role: Role) -> Option<u32> {
        match role {
            Role::Address => self.address,
            Role::Command => self.command,
            Role::Register => self.register,
            Role::Index => self.index,
            Role::Data => self.data,
            Role::ErrorCode => self.error_code,
            Role::Process1 => self.process_1,
            Role::Process2 => self.process_2,
            Role::Decimals => self.decimals,
            Role::Text | Role::Words | Role::ReadCount | Role::WriteStatus | Role::ReplyWait => {
                None
            }
        }
    }

    #[inline]
    pub(crate) fn slot(&mut self, role: Role) -> Option<&mut Option<u32>> {
        match role {
            Role::Address => Some(&mut self.address),
            Role::Command => Some(&mut self.command),
            Role::Register => Some(&mut self.register),
            Role::Index => Some(&mut self.index),
            Role::Data => Some(&mut self.data),
            Role::ErrorCode => Some(&mut self.error_code),
            Role::Process1 => Some(&mut self.process_1),
            Role::Process2 => Some(&mut self.process_2),
            Role::Decimals => Some(&mut self.decimals),
            Role::Text | Role::Words | Role::ReadCount | Role::WriteStatus | Role::ReplyWait => {
                None
            }
        }
    }
}

impl FrameValues {
    /// Every role's value in one pass (the hot path's alternative to repeated [`FrameValues::get`]).
    pub fn roles(&self, layout: &FrameLayout) -> Roles {
        let mut roles = Roles::default();
        for (index, part) in layout.parts.iter().enumerate() {
            let slot = self.parts[index];
            if !slot.present {
                continue;
            }
            match part {
                Part::Field(field) => {
                    if let Some(target) = roles.slot(field.role) {
                        *target = Some(slot.value);
                    }
                }
                Part::Word(word) => {
                    for bits in word.fields.iter() {
                        if let Some(target) = roles.slot(bits.role) {
                            *target = Some((slot.value & bits.mask()) >> bits.lsb);
                        }
                    }
                }
                _ => {}
            }
        }
        roles
    }

    /// Sets every role given in `roles` in one pass; roles the layout lacks are ignored.
    pub fn fill(&mut self, layout: &FrameLayout, roles: &Roles) {
        let mut roles = *roles;
        for (index, part) in layout.parts.iter().enumerate() {
            match part {
                Part::Field(field) => {
                    if let Some(Some(value)) = roles.slot(field.role).map(|v| *v) {
                        self.parts[index].present = true;
                        self.parts[index].value = value;
                    }
                }
                Part::Word(word) => {
                    for bits in word.fields.iter() {
                        if let Some(Some(value)) = roles.slot(bits.role).map(|v| *v) {
                            let slot = &mut self.parts[index];
                            slot.present = true;
                            slot.value =
                                (slot.value & !bits.mask()) | ((value << bits.lsb) & bits.mask());
                        }
                    }
                }
                _ => {}
            }
        }
    }
}

/// The steps of one layout, one per part, in wire order (see the module documentation).
#[derive(Debug, Clone)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FramePlan {
    /// One step per part of the layout, at the part's index.
    pub steps: List<Step>,
    /// The same steps compiled for this layout alone: functions the generator writes
    /// for each generated layout, which run the steps one after the other with every
    /// argument a constant (see [`crate::plan::Decoder`] and [`crate::plan::Encoder`]). `None` for a plan computed at
    /// run time, which [`FramePlan::decode`] and [`FramePlan::encode`] run step by step.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub compiled: Option<Compiled>,
}

/// Two plans are equal when their steps are (compiled functions run the same steps).
impl PartialEq for FramePlan {
    fn eq(&self, other: &FramePlan) -> bool {
        self.steps == other.steps
    }
}

/// A plan's steps compiled for one layout by the generator.
#[derive(Debug, Clone, Copy)]
pub struct Compiled {
    /// Runs [`FramePlan::decode`]'s steps.
    pub decode: fn(&[u8]) -> Option<PlannedFrame>,
    /// Runs [`FramePlan::encode`]'s steps.
    pub encode: EncodeFn,
}

/// The signature of a compiled encoder: roles, data size, the protocol's default optional
/// parts, the output buffer (see [`FramePlan::encode`]).
pub type EncodeFn = fn(&Roles, u8, &[Text], &mut [u8]) -> Option<usize>;

/// What a plan does for one part. Lists (literal bytes, allowed values, bit fields,
/// markers) stay in the layout's part; a step holds what the fast path decides on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Step {
    /// Fixed bytes (the part's).
    Literal {
        /// Present on decode only when the next bytes equal them; on encode only when named
        /// among the protocol's default optional parts.
        optional: bool,
    },
    /// A value field.
    Field(FieldStep),
    /// A word of bit fields, in a fixed binary format.
    Word {
        /// `u16be`, `u16le`, `u32be` or `u32le`.
        format: Format,
    },
    /// A computed length, in a fixed binary format.
    Length(LengthStep),
    /// A checksum over earlier parts.
    Checksum(ChecksumStep),
}

/// A value field's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FieldStep {
    /// What it means.
    pub role: Role,
    /// Wire format: a digit format, a fixed binary format, or `uint_be`/`uint_le`.
    pub format: Format,
    /// Digits or bytes written (and the most digits read).
    pub width: u8,
    /// The fewest digits read.
    pub min_width: u8,
    /// How a decoder tells it is there, when it may be left out.
    pub optional: Option<Presence>,
    /// Sized by the length part that covers it alone (a Modbus byte count).
    pub by_length: bool,
    /// The part lists the values it accepts.
    pub checked: bool,
    /// The part has broadcast encodings with open digits (`**`, `*9`): frames holding
    /// one go to the interpreter.
    pub open_digits: bool,
}

/// A length's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LengthStep {
    /// `u8` or `u16be`.
    pub format: Format,
    /// What it counts.
    pub counts: Counts,
    /// See [`crate::LengthSpec::times`].
    pub times: u8,
    /// See [`crate::LengthSpec::per`].
    pub per: u8,
}

/// A checksum's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ChecksumStep {
    /// The algorithm.
    pub algorithm: ChecksumAlgorithm,
    /// `hex` (two digits) or a fixed binary format.
    pub format: Format,
    /// First part covered.
    pub covers_from: u8,
    /// Last part covered, when coverage stops before the checksum.
    pub covers_through: Option<u8>,
    /// May be left out (present when its marker is there).
    pub optional: bool,
}

/// A frame decoded by a plan: what [`crate::codec::decode`] returns for it, with its
/// roles gathered as [`FrameValues::roles`] gathers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlannedFrame {
    /// Every part's value.
    pub values: FrameValues,
    /// The values of the roles the frame carries.
    pub roles: Roles,
    /// Frame length in bytes.
    pub len: usize,
}
