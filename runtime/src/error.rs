//! Typed errors: frames that do not fit and values that must not be sent. Failed exchanges
//! are [`crate::transaction::TransactionError`]s.

use crate::info::RegisterInfo;
use crate::kinds::{CommandKind, DataType, Space};
use crate::layout::{ChecksumAlgorithm, Format, Text};

/// Renders bytes for people: printable ASCII as text, the rest as hex.
pub fn describe_bytes(bytes: &[u8]) -> String {
    if !bytes.is_empty() && bytes.iter().all(|b| b.is_ascii_graphic() || *b == b' ') {
        format!("{:?}", String::from_utf8_lossy(bytes))
    } else {
        hex(bytes)
    }
}

/// Bytes as upper-case hex pairs separated by spaces (`2F 50 FA`), with CR and LF shown
/// as such when the rest is printable text.
pub fn hex(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len() * 3);
    for (index, byte) in bytes.iter().enumerate() {
        if index > 0 {
            out.push(' ');
        }
        out.push_str(&format!("{byte:02X}"));
    }
    out
}

/// A byte sequence that cannot be a frame of the layout.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    /// A byte differs from what the layout requires at that point.
    #[error("{layout}: byte {offset} is {found:#04X} ({found_text}) in part `{part}`, expected {expected}", found_text = describe_bytes(&[*found]))]
    UnexpectedByte {
        /// Layout name.
        layout: Text,
        /// Part name.
        part: Text,
        /// Offset of the byte in the frame.
        offset: usize,
        /// The byte received.
        found: u8,
        /// What would have fitted.
        expected: String,
    },
    /// A field holds a value the layout does not allow there (e.g. an unknown command letter).
    #[error("{layout}: field `{part}` at byte {offset} holds {shown}, which this layout does not allow", shown = show_value(*value, *format))]
    NotAllowed {
        /// Layout name.
        layout: Text,
        /// Field name.
        part: Text,
        /// Offset of the field.
        offset: usize,
        /// The value found.
        value: u32,
        /// The field's wire format.
        format: Format,
    },
    /// The checksum does not match the bytes it covers.
    #[error("{layout}: {algorithm} checksum `{part}` at byte {offset} is {received:02X}h, but the covered bytes give {computed:02X}h", algorithm = algorithm.as_str())]
    ChecksumMismatch {
        /// Layout name.
        layout: Text,
        /// Checksum part name.
        part: Text,
        /// Offset of the checksum value.
        offset: usize,
        /// Algorithm.
        algorithm: ChecksumAlgorithm,
        /// Checksum computed over the covered bytes.
        computed: u32,
        /// Checksum received.
        received: u32,
    },
    /// A length part disagrees with the frame (FC LGE, Modbus byte count).
    #[error(
        "{layout}: length `{part}` at byte {offset} says {received}, but the frame gives {actual}"
    )]
    LengthMismatch {
        /// Layout name.
        layout: Text,
        /// Length part name.
        part: Text,
        /// Offset of the length.
        offset: usize,
        /// Length received.
        received: u32,
        /// Length the frame's parts give.
        actual: u32,
    },
    /// The bytes end before the frame does (only from APIs that require a whole frame).
    #[error("{layout}: the frame ends after {len} bytes, before the layout is complete")]
    Truncated {
        /// Layout name.
        layout: Text,
        /// Bytes available.
        len: usize,
    },
    /// Bytes follow a complete frame (only from APIs that require exactly one frame).
    #[error("{layout}: {extra} byte(s) follow the end of the frame at byte {len}")]
    TrailingBytes {
        /// Layout name.
        layout: Text,
        /// Frame length.
        len: usize,
        /// Extra bytes.
        extra: usize,
    },
    /// The station field holds a station outside the protocol's station range (the
    /// drive's `addressing`), which the encoder refuses as well.
    #[error("{layout}: station {station} in `{part}` at byte {offset} is outside the drive's station range {min}..={max}, which the encoder refuses too; check the station number, or the drive the frame is decoded for")]
    StationOutOfRange {
        /// Layout name.
        layout: Text,
        /// Part name.
        part: Text,
        /// Byte offset of the field.
        offset: usize,
        /// The station the frame carries.
        station: u32,
        /// Lowest station of the drive.
        min: u8,
        /// Highest station of the drive.
        max: u8,
    },
    /// No layout of the protocol matches the frame.
    #[error("{protocol}: no {what} layout matches; the closest attempt failed with: {closest}")]
    NoLayoutMatches {
        /// Protocol id.
        protocol: Text,
        /// "request" or "reply".
        what: &'static str,
        /// The error from the layout that got furthest.
        closest: Box<DecodeError>,
    },
}

fn show_value(value: u32, format: Format) -> String {
    match (format, u8::try_from(value)) {
        (Format::Char, Ok(byte)) => format!("{:?} ({byte:#04X})", byte as char),
        _ => format!("{value:#06X}"),
    }
}

/// Why a byte sequence is not a frame, without the details: what drive files name in
/// `printed_rejected_as` and what callers branch on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum DecodeErrorKind {
    /// See [`DecodeError::UnexpectedByte`].
    UnexpectedByte,
    /// See [`DecodeError::NotAllowed`].
    NotAllowed,
    /// See [`DecodeError::ChecksumMismatch`].
    ChecksumMismatch,
    /// See [`DecodeError::LengthMismatch`].
    LengthMismatch,
    /// See [`DecodeError::Truncated`].
    Truncated,
    /// See [`DecodeError::TrailingBytes`].
    TrailingBytes,
}

impl DecodeErrorKind {
    /// Every kind, in the order of [`DecodeError`]'s variants.
    pub const ALL: [DecodeErrorKind; 6] = [
        DecodeErrorKind::UnexpectedByte,
        DecodeErrorKind::NotAllowed,
        DecodeErrorKind::ChecksumMismatch,
        DecodeErrorKind::LengthMismatch,
        DecodeErrorKind::Truncated,
        DecodeErrorKind::TrailingBytes,
    ];

    /// Name as written in drive files (`checksum_mismatch`).
    pub const fn as_str(self) -> &'static str {
        match self {
            DecodeErrorKind::UnexpectedByte => "unexpected_byte",
            DecodeErrorKind::NotAllowed => "not_allowed",
            DecodeErrorKind::ChecksumMismatch => "checksum_mismatch",
            DecodeErrorKind::LengthMismatch => "length_mismatch",
            DecodeErrorKind::Truncated => "truncated",
            DecodeErrorKind::TrailingBytes => "trailing_bytes",
        }
    }

    /// The kind with this name as written in drive files.
    pub fn from_name(name: &str) -> Option<DecodeErrorKind> {
        DecodeErrorKind::ALL
            .into_iter()
            .find(|kind| kind.as_str() == name)
    }
}

impl std::fmt::Display for DecodeErrorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl DecodeError {
    /// What went wrong, without the details. For [`DecodeError::NoLayoutMatches`], the
    /// kind of the closest attempt's error.
    pub fn kind(&self) -> DecodeErrorKind {
        match self {
            DecodeError::UnexpectedByte { .. } => DecodeErrorKind::UnexpectedByte,
            DecodeError::NotAllowed { .. } | DecodeError::StationOutOfRange { .. } => {
                DecodeErrorKind::NotAllowed
            }
            DecodeError::ChecksumMismatch { .. } => DecodeErrorKind::ChecksumMismatch,
            DecodeError::LengthMismatch { .. } => DecodeErrorKind::LengthMismatch,
            DecodeError::Truncated { .. } => DecodeErrorKind::Truncated,
            DecodeError::TrailingBytes { .. } => DecodeErrorKind::TrailingBytes,
            DecodeError::NoLayoutMatches { closest, .. } => closest.kind(),
        }
    }

    /// Offset in the frame at which decoding failed.
    pub fn offset(&self) -> usize {
        match self {
            DecodeError::UnexpectedByte { offset, .. }
            | DecodeError::NotAllowed { offset, .. }
            | DecodeError::StationOutOfRange { offset, .. }
            | DecodeError::ChecksumMismatch { offset, .. }
            | DecodeError::LengthMismatch { offset, .. } => *offset,
            DecodeError::Truncated { len, .. } | DecodeError::TrailingBytes { len, .. } => *len,
            DecodeError::NoLayoutMatches { closest, .. } => closest.offset(),
        }
    }

    /// The same error with its offsets moved by `map` (from the bytes a frame carries to
    /// its wire form, for frames written as hex digits).
    pub fn at_offset(mut self, map: impl Fn(usize) -> usize + Copy) -> DecodeError {
        match &mut self {
            DecodeError::UnexpectedByte { offset, .. }
            | DecodeError::NotAllowed { offset, .. }
            | DecodeError::StationOutOfRange { offset, .. }
            | DecodeError::ChecksumMismatch { offset, .. }
            | DecodeError::LengthMismatch { offset, .. } => *offset = map(*offset),
            DecodeError::Truncated { len, .. } | DecodeError::TrailingBytes { len, .. } => {
                *len = map(*len)
            }
            DecodeError::NoLayoutMatches { closest, .. } => {
                **closest = closest.as_ref().clone().at_offset(map)
            }
        }
        self
    }
}

/// A frame that cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EncodeError {
    /// A value does not fit its field.
    #[error("{layout}: value {value:#X} does not fit field `{field}` ({width} {format} digit(s) or bytes)", format = format.as_str())]
    ValueTooWide {
        /// Layout name.
        layout: Text,
        /// Field name.
        field: Text,
        /// The value.
        value: u32,
        /// Wire format.
        format: Format,
        /// Digits requested.
        width: u8,
    },
    /// The output buffer is too small.
    #[error("{layout}: the frame does not fit in a {capacity}-byte buffer")]
    BufferTooSmall {
        /// Layout name.
        layout: Text,
        /// Buffer length.
        capacity: usize,
    },
    /// The layout has more parts than the runtime supports.
    #[error("{layout}: more than {} parts", crate::layout::MAX_PARTS)]
    TooManyParts {
        /// Layout name.
        layout: Text,
    },
    /// The protocol has no command for this kind of request.
    #[error("protocol {protocol} has no command to {kind} a {data_type} in the {space} space", kind = kind.as_str(), data_type = data_type.as_str(), space = space.as_str())]
    UnsupportedCommand {
        /// Protocol id.
        protocol: Text,
        /// Requested kind.
        kind: CommandKind,
        /// Address space.
        space: Space,
        /// Data type.
        data_type: DataType,
    },
    /// The request names a command code the protocol does not have for its kind of request.
    #[error("protocol {protocol} has no command {code} to {kind}", code = code_text(*code), kind = kind.as_str())]
    NoSuchCommand {
        /// Protocol id.
        protocol: Text,
        /// The code the request names.
        code: u32,
        /// The kind of request.
        kind: CommandKind,
    },
    /// The command addresses only some registers, and not this one.
    #[error("protocol {protocol}: command {code} cannot address register {register:04X}h", code = code_text(*code))]
    RegisterNotServed {
        /// Protocol id.
        protocol: Text,
        /// The command's code.
        code: u32,
        /// Register number.
        register: u16,
    },
    /// The command does not carry its data as a percentage of this register.
    #[error("protocol {protocol}: command {code} does not carry a percentage of {register}", code = code_text(*code))]
    NotPercentOf {
        /// Protocol id.
        protocol: Text,
        /// The command's code.
        code: u32,
        /// Code of the register given as 100 %.
        register: &'static str,
    },
    /// A block transfer with more words to write, or to read, than the drive's block
    /// selection has positions for.
    #[error("a block transfer of protocol {protocol} {what} at most {max} word(s), not {words}")]
    BlockTooLong {
        /// Protocol id.
        protocol: Text,
        /// `writes` or `reads`.
        what: &'static str,
        /// Words asked for.
        words: usize,
        /// Positions the selection has.
        max: usize,
    },
    /// A read of more consecutive registers than the protocol (or the drive) allows in one
    /// request, or a protocol that reads one register at a time.
    #[error("protocol {protocol} reads at most {max} register(s) per request, not {words}")]
    TooManyWords {
        /// Protocol id.
        protocol: Text,
        /// Registers asked for.
        words: usize,
        /// The most one request carries.
        max: u16,
    },
    /// A write of more consecutive registers than the protocol (or the drive) allows in
    /// one request, or of none.
    #[error("protocol {protocol} writes 1 to {max} register(s) per request, not {words}")]
    TooManyWordsToWrite {
        /// Protocol id.
        protocol: Text,
        /// Registers to write.
        words: usize,
        /// The most one request carries.
        max: u16,
    },
    /// The register number does not fit the protocol's wire numbering.
    #[error("protocol {protocol}: register {register:04X}h has no wire address (its address map leaves 0000h-FFFFh)")]
    RegisterOutOfRange {
        /// Protocol id.
        protocol: Text,
        /// Register number.
        register: u16,
    },
    /// The drive file gives the register its own numbers in this protocol, but none for
    /// this direction (`registers[].wire_numbers`): it cannot be read (or written) over it.
    #[error("register {register:04X}h cannot be {} over protocol {protocol}: the drive's description gives it no number there for that (wire_numbers); use another of the drive's protocols", if *writing { "written" } else { "read" })]
    NotInProtocol {
        /// Protocol id.
        protocol: Text,
        /// Register number.
        register: u16,
        /// A write was asked for (else a read).
        writing: bool,
    },
    /// A RAM write of a register whose write over this protocol goes to RAM and EEPROM:
    /// the protocol's write leaves the storage to the instruction, and the register's
    /// instruction is an EEPROM one (`storage: by_instruction`).
    #[error("register {register:04X}h cannot be written to RAM only over protocol {protocol}: its instruction there stores in RAM and EEPROM (storage: by_instruction); write it persistently, or write the register the manual gives for RAM")]
    StoredInEeprom {
        /// Protocol id.
        protocol: Text,
        /// Register number.
        register: u16,
    },
    /// The protocol needs a station address and none was given.
    #[error("protocol {protocol} needs a station address")]
    AddressRequired {
        /// Protocol id.
        protocol: Text,
    },
    /// A broadcast the protocol, the drive or the request does not allow; nothing is sent.
    #[error("protocol {protocol}: cannot broadcast a {kind}: {reason}", kind = kind.as_str())]
    NoBroadcast {
        /// Protocol id.
        protocol: Text,
        /// The request's kind.
        kind: CommandKind,
        /// Why.
        reason: &'static str,
    },
    /// The protocol has no variant of that name (see [`crate::protocol::Protocol::variant`]).
    #[error("protocol {protocol} has no variant `{variant}`{known}", known = if known.is_empty() { String::from(" (it has none)") } else { format!("; its variants: {known}") })]
    NoSuchVariant {
        /// Protocol id.
        protocol: Text,
        /// The variant asked for.
        variant: String,
        /// The protocol's variants, comma-separated (empty: it has none).
        known: String,
    },
    /// The protocol has no address field, but an address was given.
    #[error("protocol {protocol}: station address {address} is outside {min}..={max}")]
    AddressOutOfRange {
        /// Protocol id.
        protocol: Text,
        /// Address given.
        address: u8,
        /// Lowest address.
        min: u8,
        /// Highest address.
        max: u8,
    },
}

/// A command code as people read it: the letter for letters, hex otherwise (as
/// `protocol::code_label`, which this module cannot use).
fn code_text(code: u32) -> String {
    match u8::try_from(code) {
        Ok(byte) if byte.is_ascii_alphabetic() => (byte as char).to_string(),
        _ => format!("{code:02X}h"),
    }
}

/// A value that must not be sent to a register.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ValueError {
    /// The value is outside the register's range.
    #[error("{register}: {value} {unit} is outside the range {min} to {max} {unit}{bounds}", register = register.label(), unit = register.unit_symbol(), bounds = register.bound_note())]
    OutOfRange {
        /// The register.
        register: &'static RegisterInfo,
        /// Value asked for, in engineering units.
        value: f64,
        /// Lowest value accepted, in engineering units.
        min: f64,
        /// Highest value accepted, in engineering units.
        max: f64,
    },
    /// The value cannot be sent as a percentage of the reference (the reference is not
    /// positive, or the percentage does not fit a word).
    #[error("{register}: {value} {unit} is no percentage of {reference} a word can carry", register = register.label(), unit = register.unit_symbol())]
    NotAPercentage {
        /// The register.
        register: &'static RegisterInfo,
        /// Value asked for, in engineering units.
        value: f64,
        /// The value that is 100 %, in the same unit.
        reference: f64,
    },
    /// The value is NaN or infinite.
    #[error("{register}: {value} is not a finite number", register = register.label())]
    NotFinite {
        /// The register.
        register: &'static RegisterInfo,
        /// The value.
        value: f64,
    },
    /// The value cannot be written or converted this way (text parameters).
    #[error("{register}: a text parameter is read with read_text, not as a number", register = register.label())]
    NotWritable {
        /// The register.
        register: &'static RegisterInfo,
    },
    /// An array index beyond the register's array.
    #[error("{register}: index {index} is outside the array of {len} element(s)", register = register.label())]
    IndexOutOfRange {
        /// The register.
        register: &'static RegisterInfo,
        /// Index asked for.
        index: u16,
        /// Array length (0: not an array).
        len: u8,
    },
    /// A raw value read back is not one of the register's codes.
    #[error("{register}: raw value {raw:#06X} is not a known code of `{table}`", register = register.label())]
    UnknownCode {
        /// The register.
        register: &'static RegisterInfo,
        /// Code table id.
        table: &'static str,
        /// Raw value.
        raw: u32,
    },
    /// The register's scale is chosen by another register, and that register's value is
    /// not one the description gives a scale for.
    #[error("{register}: {selector} = {value} chooses no scale the description knows", register = register.label())]
    UnknownScale {
        /// The register.
        register: &'static RegisterInfo,
        /// Code of the register choosing the scale.
        selector: &'static str,
        /// The selector's value.
        value: u32,
    },
    /// A read reply states the decimal places of its value (the Eaton unit digit), and no
    /// scale the description gives the register has that many.
    #[error("{register}: the reply gives the value {received} decimal place(s), the description {expected}", register = register.label())]
    WrongDecimals {
        /// The register.
        register: &'static RegisterInfo,
        /// The decimal places of the register's own scale.
        expected: u8,
        /// The decimal places the reply states.
        received: u8,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_decode_error_kind_is_found_by_its_name() {
        for kind in DecodeErrorKind::ALL {
            assert_eq!(DecodeErrorKind::from_name(kind.as_str()), Some(kind));
            assert_eq!(kind.to_string(), kind.as_str());
        }
        assert_eq!(DecodeErrorKind::from_name("checksum"), None);
    }

    #[test]
    fn no_layout_matches_has_the_kind_of_the_closest_attempt() {
        let error = DecodeError::NoLayoutMatches {
            protocol: "ascii".into(),
            what: "reply",
            closest: Box::new(DecodeError::Truncated {
                layout: "read_reply".into(),
                len: 3,
            }),
        };
        assert_eq!(error.kind(), DecodeErrorKind::Truncated);
    }
}
