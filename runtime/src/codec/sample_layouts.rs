//! Layouts the codec's tests share: an ASCII read, an ETX outside its sum, a block reply
//! and a hex-pairs write.

use crate::layout::{
    ChecksumAlgorithm, ChecksumSpec, Counts, Encoding, FieldSpec, Format, FrameLayout, LengthSpec,
    List, Part, Presence, Role, SizedBy,
};
use std::borrow::Cow;

pub(super) fn toshiba_ascii_read() -> FrameLayout {
    FrameLayout {
        name: "read_request".into(),
        encoding: Encoding::Binary,
        plan: None,
        parts: List::Owned(vec![
            Part::Literal {
                name: "start".into(),
                bytes: Cow::Borrowed(b"("),
                optional: false,
            },
            Part::Field(FieldSpec {
                name: "address".into(),
                role: Role::Address,
                format: Format::Decimal,
                width: 2,
                min_width: 2,
                optional: Some(Presence::IfFormatMatches),
                allowed: Cow::Borrowed(&[]),
                fold_case: false,
                sized_by: crate::layout::SizedBy::Format,
                broadcast: None,
            }),
            Part::Field(FieldSpec {
                name: "command".into(),
                role: Role::Command,
                format: Format::Char,
                width: 1,
                min_width: 1,
                optional: None,
                allowed: Cow::Borrowed(&[b'R' as u32]),
                fold_case: true,
                sized_by: crate::layout::SizedBy::Format,
                broadcast: None,
            }),
            Part::Field(FieldSpec {
                name: "register".into(),
                role: Role::Register,
                format: Format::Hex,
                width: 4,
                min_width: 4,
                optional: None,
                allowed: Cow::Borrowed(&[]),
                fold_case: false,
                sized_by: crate::layout::SizedBy::Format,
                broadcast: None,
            }),
            Part::Checksum(ChecksumSpec {
                name: "sum".into(),
                algorithm: ChecksumAlgorithm::Sum8,
                format: Format::Hex,
                marker: Cow::Borrowed(b"&"),
                covers_from: 0,
                covers_through: None,
                optional: true,
            }),
            Part::Literal {
                name: "end".into(),
                bytes: Cow::Borrowed(b")"),
                optional: true,
            },
            Part::Literal {
                name: "cr".into(),
                bytes: Cow::Borrowed(b"\r"),
                optional: false,
            },
        ]),
    }
}

pub(super) fn hex_field(name: &'static str, role: Role, width: u8) -> Part {
    Part::Field(FieldSpec {
        name: name.into(),
        role,
        format: Format::Hex,
        width,
        min_width: width,
        optional: None,
        allowed: Cow::Borrowed(&[]),
        fold_case: false,
        sized_by: crate::layout::SizedBy::Format,
        broadcast: None,
    })
}

/// An Eaton-style data reply: STX, station, data, a unit digit, ETX, then a sum that
/// covers station through unit digit but not ETX (DV1 manual, 例三 step 4).
pub(super) fn etx_outside_the_sum(covers_through: Option<u8>) -> FrameLayout {
    FrameLayout {
        name: "data_reply".into(),
        encoding: Encoding::Binary,
        plan: None,
        parts: Cow::Owned(vec![
            Part::Literal {
                name: "stx".into(),
                bytes: Cow::Borrowed(b"\x02"),
                optional: false,
            },
            hex_field("station", Role::Address, 2),
            hex_field("data", Role::Data, 4),
            hex_field("unit", Role::Index, 1),
            Part::Literal {
                name: "etx".into(),
                bytes: Cow::Borrowed(b"\x03"),
                optional: false,
            },
            Part::Checksum(ChecksumSpec {
                name: "sum".into(),
                algorithm: ChecksumAlgorithm::Sum8,
                format: Format::Hex,
                marker: Cow::Borrowed(b""),
                covers_from: 1,
                covers_through,
                optional: false,
            }),
            Part::Literal {
                name: "cr".into(),
                bytes: Cow::Borrowed(b"\r"),
                optional: false,
            },
        ]),
    }
}

/// A block-transfer reply: start, command, a count of words, a status byte, the words
/// (each high byte first), a sum.
pub(super) fn block_reply() -> FrameLayout {
    let field = |name: &'static str, role: Role, format: Format| {
        Part::Field(FieldSpec {
            sized_by: if role == Role::Words {
                SizedBy::Length
            } else {
                SizedBy::Format
            },
            ..FieldSpec::new(name, role, format, 1)
        })
    };
    FrameLayout {
        name: "block_reply".into(),
        encoding: Encoding::Binary,
        plan: None,
        parts: List::Owned(vec![
            Part::literal("start", b"/"),
            field("command", Role::Command, Format::Char),
            Part::Length(
                LengthSpec::new(
                    "count",
                    Format::U8,
                    Counts::Parts {
                        from: 4,
                        through: 4,
                    },
                )
                .with_ratio(1, 2),
            ),
            field("write_status", Role::WriteStatus, Format::U8),
            field("words", Role::Words, Format::U16Be),
            Part::Checksum(ChecksumSpec::new(
                "sum",
                ChecksumAlgorithm::Sum8,
                Format::U8,
                0,
            )),
        ]),
    }
}

/// Modbus ASCII's write-register frame: ":", address, function, register, data, LRC, CR LF.
pub(super) fn hex_pairs_write() -> FrameLayout {
    let field = |name: &'static str, role, format, width| {
        Part::Field(FieldSpec {
            name: name.into(),
            role,
            format,
            width,
            min_width: width,
            optional: None,
            allowed: Cow::Borrowed(&[]),
            fold_case: false,
            sized_by: crate::layout::SizedBy::Format,
            broadcast: None,
        })
    };
    let literal = |name: &'static str, bytes: &'static [u8]| Part::Literal {
        name: name.into(),
        bytes: Cow::Borrowed(bytes),
        optional: false,
    };
    FrameLayout {
        name: "write_register".into(),
        encoding: Encoding::HexPairs,
        plan: None,
        parts: Cow::Owned(vec![
            literal("start", b":"),
            field("address", Role::Address, Format::U8, 1),
            field("function", Role::Command, Format::U8, 1),
            field("register", Role::Register, Format::U16Be, 2),
            field("data", Role::Data, Format::U16Be, 2),
            Part::Checksum(ChecksumSpec {
                name: "lrc".into(),
                algorithm: ChecksumAlgorithm::Lrc8,
                format: Format::U8,
                marker: Cow::Borrowed(b""),
                covers_from: 1,
                covers_through: None,
                optional: false,
            }),
            literal("end", b"\r\n"),
        ]),
    }
}
