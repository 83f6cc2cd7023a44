//! The longest frame of a protocol as one drive speaks it: the protocol file's
//! `max_frame_len`, or the drive's own where its manual allows less
//! (`protocols[].max_frame_len`; the DV1's Modbus carries at most 12 registers, so its
//! longest RTU frame is 33 bytes, not the protocol's 256). A drive may only lower it, and
//! not below the longest frame its commands make at its word limits.

use super::lowered_command::LoweredCommand;
use super::Input;
use crate::diagnostics::Diagnostics;
use vfd_runtime::layout::{Encoding, Part, Role, SizedBy};
use vfd_runtime::{CommandKind, FrameLayout};

/// The longest frame in bytes on the wire; the protocol file's when the drive gives none
/// or a wrong one (reported).
pub(super) fn max_frame_len(
    input: &Input<'_>,
    commands: &[LoweredCommand],
    words_read: u16,
    words_written: u16,
    out: &mut Diagnostics,
) -> u16 {
    let file = input.file.protocol.max_frame_len;
    let Some(drive) = input.reference.max_frame_len else {
        return file;
    };
    let path = format!("{}.max_frame_len", input.reference_path);
    if drive > file {
        out.push(
            input
                .drive_source
                .error(
                    &path,
                    format!("max_frame_len {drive} is above the protocol file's {file}"),
                )
                .hint("a drive may only lower the protocol's longest frame"),
        );
        return file;
    }
    let longest = commands
        .iter()
        .flat_map(|command| {
            let spec = &command.spec;
            // A block of registers, or one register of the widest type the command carries.
            let widest = spec.data_types.iter().map(|t| usize::from(t.size())).max();
            let bytes = |words: u16| (usize::from(words) * 2).max(widest.unwrap_or(0));
            let (request_words, reply_words) = match spec.kind {
                CommandKind::Read => (0, words_read),
                CommandKind::WriteRam | CommandKind::WritePersistent => (words_written, 0),
                _ => (0, 0),
            };
            [
                (&spec.request, request_words, bytes(request_words)),
                (&spec.reply, reply_words, bytes(reply_words)),
            ]
        })
        .filter_map(|(layout, words, data)| {
            longest_frame(layout, data).map(|len| (layout, words, len))
        })
        .max_by_key(|(_, _, len)| *len);
    if let Some((layout, words, len)) = longest.filter(|(_, _, len)| *len > usize::from(drive)) {
        let carrying = if words > 1 {
            format!(" carrying {words} registers (the drive's word limit)")
        } else {
            String::new()
        };
        out.push(
            input
                .drive_source
                .error(
                    &path,
                    format!(
                        "max_frame_len {drive} is shorter than layout `{}`{carrying}: {len} bytes",
                        layout.name
                    ),
                )
                .hint("give the longest frame the drive's commands make at its word limits (max_words_per_read, max_words_per_write)"),
        );
        return file;
    }
    drive
}

/// `layout`'s longest frame on the wire when its data field, sized by a length part, holds
/// at most `data` bytes; `None` when another part has no bound (a text, words, an optional
/// part), or the data has none (`data` 0 for a variable data field).
fn longest_frame(layout: &FrameLayout, data: usize) -> Option<usize> {
    let mut bytes = 0;
    for part in layout.parts.iter() {
        bytes += match (part.fixed_size(), part) {
            (Some(size), _) => size,
            (None, Part::Field(field))
                if field.role == Role::Data
                    && field.sized_by == SizedBy::Length
                    && field.optional.is_none()
                    && data > 0 =>
            {
                data
            }
            _ => return None,
        };
    }
    Some(match layout.encoding {
        Encoding::Binary => bytes,
        Encoding::HexPairs => {
            let (head, tail) = layout.verbatim_ends();
            let ends = head.len() + tail.len();
            ends + 2 * bytes.saturating_sub(ends)
        }
    })
}
