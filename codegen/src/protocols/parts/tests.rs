//! Layouts lowered part by part, and each kind of part reporting its first problem at its
//! key.

use super::super::test_support::{at, lowered, parts, problems, protocol_with, PROTOCOL};
use super::*;
use vfd_runtime::{ChecksumSpec, Counts, FieldSpec, LengthSpec, Presence, SizedBy};

fn field(name: &str, role: Role, format: Format, width: u8) -> FieldSpec {
    FieldSpec {
        name: name.to_owned().into(),
        role,
        format,
        width,
        min_width: width,
        optional: None,
        allowed: Vec::new().into(),
        fold_case: false,
        sized_by: SizedBy::Format,
        broadcast: None,
    }
}

#[test]
fn a_text_layout_lowers_to_literals_fields_and_a_checksum() {
    let protocol = lowered(PROTOCOL);
    let expected = vec![
        literal("start", b"(".to_vec(), false),
        Part::Field(FieldSpec {
            optional: Some(Presence::IfFormatMatches),
            ..field("address", Role::Address, Format::Decimal, 2)
        }),
        Part::Field(FieldSpec {
            allowed: vec![u32::from(b'R')].into(),
            ..field("command", Role::Command, Format::Char, 1)
        }),
        Part::Field(field("register", Role::Register, Format::Hex, 4)),
        Part::Checksum(ChecksumSpec {
            name: "sum".into(),
            algorithm: ChecksumAlgorithm::Sum8,
            format: Format::Hex,
            marker: b"&".to_vec().into(),
            covers_from: 0,
            covers_through: None,
            optional: true,
        }),
        literal("cr", b"\r".to_vec(), false),
    ];
    assert_eq!(parts(&protocol, "read_request"), expected.as_slice());
}

#[test]
fn binary_parts_lower_to_a_length_a_word_and_a_hex_literal() {
    let yaml = protocol_with(&[
        ("text: true", "text: false"),
        (
            "  read_request: [start, address, { field: command, format: char, allowed: [R] }, register, sum, cr]",
            "  read_request:\n    - { literal_hex: \"02\", name: stx }\n    - { length: u8, name: lge, counts: { from: addr, through: bcc } }\n    - { field: address, name: addr, format: u8 }\n    - { word: u16be, name: pke, fields: [{ field: command, name: ak, bits: \"15:12\", allowed: [1] }, { field: register, name: pnu, bits: \"10:0\" }] }\n    - { field: data, format: uint_be, size: rest }\n    - { checksum: xor8, name: bcc, format: u8, covers_from: stx }",
        ),
        ("{ code: R, kind: read,", "{ code: 1, kind: read,"),
    ]);
    let protocol = lowered(&yaml);
    let parts = parts(&protocol, "read_request");
    assert_eq!(parts[0], literal("stx", vec![0x02], false));
    assert_eq!(
        parts[1],
        Part::Length(LengthSpec {
            name: "lge".into(),
            format: Format::U8,
            counts: Counts::Parts {
                from: 2,
                through: 5
            },
            times: 1,
            per: 1,
        })
    );
    let Part::Word(word) = &parts[3] else {
        panic!("not a word: {:?}", parts[3]);
    };
    assert_eq!(word.format, Format::U16Be);
    let bits: Vec<(&str, Role, u8, u8)> = word
        .fields
        .iter()
        .map(|b| (b.name.as_ref(), b.role, b.lsb, b.width))
        .collect();
    assert_eq!(
        bits,
        [("ak", Role::Command, 12, 4), ("pnu", Role::Register, 0, 11)]
    );
    assert_eq!(
        parts[4],
        Part::Field(FieldSpec {
            min_width: 1,
            sized_by: SizedBy::Rest,
            broadcast: None,
            ..field("data", Role::Data, Format::UintBe, 4)
        })
    );
    assert!(
        matches!(&parts[5], Part::Checksum(c) if c.algorithm == ChecksumAlgorithm::Xor8 && c.covers_from == 0)
    );
}

#[test]
fn a_part_of_two_kinds_is_reported_at_the_part() {
    let yaml = protocol_with(&[(
        "cr: { literal: \"\\r\" }",
        "cr: { literal: \"\\r\", field: data }",
    )]);
    assert_eq!(
        problems(&yaml),
        [format!("{} parts.cr: a part must be exactly one of `literal`, `literal_hex`, `field`, `checksum`, `word` or `length`", at(&yaml, "cr: {"))]
    );
}

#[test]
fn each_part_reports_its_first_problem_at_its_key() {
    let yaml = protocol_with(&[
        ("width: 2, optional", "width: 12, optional"),
        (
            "cr: { literal: \"\\r\" }",
            "cr: { literal: \"\\r\", optional: { if_byte_at_most: 3 } }",
        ),
        ("covers_from: start", "covers_from: cr"),
        (
            "{ field: data, format: hex, width: 4 }, sum, cr]\n  reply",
            "{ field: data, format: hex, width: 4, size: rest }, sum, cr]\n  reply",
        ),
    ]);
    assert_eq!(
        problems(&yaml),
        [
            format!("{} parts.address.width: `width: 12` is out of range for decimal", at(&yaml, "12")),
            format!("{} parts.sum.covers_from: `covers_from: cr` does not name an earlier part of the layout", at(&yaml, "cr, optional")),
            format!("{} parts.cr.optional: `optional: {{ if_byte_at_most: ... }}` is a rule for fields; a literal or checksum is optional with `optional: true`", at(&yaml, "optional: { if_byte_at_most")),
            format!("{} layouts.write_request[4].size: `size` applies to uint_be, uint_le and bytes fields, not hex", at(&yaml, "rest")),
        ]
    );
}

#[test]
fn words_and_lengths_check_their_formats_and_bits() {
    let yaml = protocol_with(&[(
        "  read_request: [start, address, { field: command, format: char, allowed: [R] }, register, sum, cr]",
        "  read_request:\n    - start\n    - { word: u8, name: w1 }\n    - { word: u16be, name: w2, fields: [{ field: command, bits: \"15:8\" }, { field: register, bits: \"8:0\" }] }\n    - { length: u32be, counts: data_size }\n    - { length: u8, name: n }\n    - cr",
    )]);
    assert_eq!(
        problems(&yaml),
        [
            format!("{} layouts.read_request[1].word: `word: u8` is not a word format", at(&yaml, "u8, name: w1")),
            format!("{} layouts.read_request[2].fields[1].bits: bit field `register` overlaps an earlier field of word `w2`", at(&yaml, "\"8:0\"")),
            format!("{} layouts.read_request[3].length: `length: u32be` is not a length format", at(&yaml, "u32be")),
            format!("{} layouts.read_request[4].counts: a length needs `counts: {{ from: part, through: part }}` or `counts: data_size`", at(&yaml, "length: u8, name: n")),
        ]
    );
}

#[test]
fn a_misspelt_value_is_reported_at_its_key() {
    let yaml = protocol_with(&[(
        "format: hex, width: 4 }, sum, cr]\n  error",
        "format: u16bee, width: 4 }, sum, cr]\n  error",
    )]);
    assert_eq!(
        problems(&yaml),
        [format!(
            "{} layouts.reply[4].format: unknown value `u16bee`",
            at(&yaml, "u16bee")
        )]
    );
    let yaml = protocol_with(&[("optional: if_format_matches", "optional: sometimes")]);
    assert_eq!(
        problems(&yaml),
        [format!("{} parts.address.optional: invalid value: string \"sometimes\", expected true, false, `if_format_matches` or `{{ if_byte_at_most: N }}`", at(&yaml, "sometimes"))]
    );
    let yaml = protocol_with(&[("checksum: sum8", "checksum: sum16")]);
    assert_eq!(
        problems(&yaml),
        [format!(
            "{} parts.sum.checksum: unknown value `sum16`",
            at(&yaml, "sum16")
        )]
    );
}

#[test]
fn counts_name_what_is_wrong_with_them() {
    let yaml = protocol_with(&[(
        "register, sum, cr]\n  write",
        "register, { length: u8, counts: bytes }, sum, cr]\n  write",
    )]);
    assert_eq!(
        problems(&yaml),
        [format!("{} layouts.read_request[4].counts: invalid value: string \"bytes\", expected `data_size` or `{{ from: part, through: part }}`", at(&yaml, "bytes"))]
    );
    let yaml = protocol_with(&[(
        "register, sum, cr]\n  write",
        "register, { length: u8, counts: { from: sum } }, sum, cr]\n  write",
    )]);
    assert_eq!(
        problems(&yaml),
        [format!(
            "{} layouts.read_request[4].counts: missing key `through`",
            at(&yaml, "counts: { from: sum }")
        )]
    );
}

#[test]
fn bits_and_hex_parse() {
    assert_eq!(parse_bits("15:12"), Some((12, 4)));
    assert_eq!(parse_bits(" 7 "), Some((7, 1)));
    assert_eq!(parse_bits("3:4"), None);
    assert_eq!(parse_bits("255:0"), None);
    assert_eq!(parse_bits("x"), None);
    assert_eq!(parse_hex("2F 50fa"), Ok(vec![0x2F, 0x50, 0xFA]));
    assert_eq!(
        parse_hex("2F5"),
        Err("`2F5` has an odd number of hex digits".to_owned())
    );
    assert_eq!(
        parse_hex("2G"),
        Err("`2G` in `2G` is not a hex byte".to_owned())
    );
}
