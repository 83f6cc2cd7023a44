//! Text protocols: a protocol declared `text: true` carries printable ASCII only, so no
//! binary fields and no non-printable literals other than line ends.

use super::layouts::Layouts;
use crate::diagnostics::Diagnostics;
use crate::parse::SourceFile;
use vfd_runtime::{Format, Part};

/// Reports every binary part of the layouts.
pub(super) fn check_text_protocol(
    layouts: &Layouts<'_>,
    source: &SourceFile,
    out: &mut Diagnostics,
) {
    for layout in layouts.iter() {
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
