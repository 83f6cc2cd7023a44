//! Text protocols: a protocol declared `text: true` carries printable ASCII only, so no
//! binary fields and no non-printable literals other than line ends; one written as hex
//! digits (`encoding: hex_pairs`) needs literal ends that are not hex digits.

use super::layouts::Layouts;
use crate::diagnostics::Diagnostics;
use crate::parse::SourceFile;
use vfd_runtime::{Encoding, Format, Part};

/// Reports every binary part of the layouts: for a protocol written as hex digits, every
/// layout without a literal first and last part (where the digits begin and end) instead.
pub(super) fn check_text_protocol(
    layouts: &Layouts<'_>,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    for layout in layouts.iter() {
        if layout.encoding == Encoding::HexPairs {
            let (head, tail) = layout.verbatim_ends();
            let digit = |bytes: &[u8]| bytes.iter().any(u8::is_ascii_hexdigit);
            if head.is_empty() || tail.is_empty() || digit(head) || digit(tail) {
                out.push(
                    source
                        .error(&format!("layouts.{}", layout.name), format!("layout `{}` is written as hex digits, but does not begin and end with a literal that is not one", layout.name))
                        .hint("with `encoding: hex_pairs`, begin and end every layout with a required literal, e.g. \":\" and \"\\r\\n\""),
                );
            }
            continue;
        }
        let name = &layout.name;
        for (index, part) in layout.parts.iter().enumerate() {
            if is_binary(part) {
                out.push(
                    source
                        .error(&format!("layouts.{name}[{index}]"), format!("part `{}` of layout `{name}` is binary, but the protocol says `text: true`", part.name()))
                        .hint("use decimal, hex or char fields and hex checksums, or set `text: false`"),
                );
            }
        }
    }
}

/// Whether a part puts bytes other than printable ASCII and line ends on the wire.
fn is_binary(part: &Part) -> bool {
    match part {
        Part::Literal { bytes, .. } => bytes
            .iter()
            .any(|b| !(b.is_ascii_graphic() || matches!(b, b' ' | b'\r' | b'\n'))),
        Part::Field(field) => !matches!(field.format, Format::Decimal | Format::Hex | Format::Char),
        Part::Checksum(spec) => spec.format != Format::Hex,
        Part::Word(_) | Part::Length(_) => true,
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{line_of, problems, protocol_with};
    use super::*;
    use std::borrow::Cow;
    use vfd_runtime::{FieldSpec, Role, SizedBy};

    fn literal(bytes: &'static [u8]) -> Part {
        Part::Literal {
            name: "l".into(),
            bytes: Cow::Borrowed(bytes),
            optional: false,
        }
    }

    fn field(format: Format) -> Part {
        Part::Field(FieldSpec {
            name: "f".into(),
            role: Role::Data,
            format,
            width: 1,
            min_width: 1,
            optional: None,
            allowed: Cow::Borrowed(&[]),
            fold_case: false,
            sized_by: SizedBy::Format,
            broadcast: None,
        })
    }

    #[test]
    fn printable_text_and_line_ends_are_not_binary() {
        assert!(!is_binary(&literal(b"(R \r\n")));
        assert!(is_binary(&literal(b"\x02")));
        for format in [Format::Decimal, Format::Hex, Format::Char] {
            assert!(!is_binary(&field(format)), "{format:?}");
        }
        for format in [Format::U8, Format::U16Be, Format::UintLe, Format::Bytes] {
            assert!(is_binary(&field(format)), "{format:?}");
        }
    }

    #[test]
    fn a_binary_part_of_a_text_protocol_is_reported_in_every_layout() {
        let yaml = protocol_with(&[(
            "register: { field: register, format: hex, width: 4 }",
            "register: { field: register, format: u16be }",
        )]);
        let problems = problems(&yaml);
        assert_eq!(problems.len(), 3, "{problems:#?}");
        let line = line_of(&yaml, "  read_request:");
        let column = yaml
            .lines()
            .nth(line - 1)
            .unwrap()
            .find("register, sum")
            .unwrap()
            + 1;
        assert_eq!(
            problems[0],
            format!("{line}:{column} layouts.read_request[3]: part `register` of layout `read_request` is binary, but the protocol says `text: true`"),
        );
    }
}
