//! The manual's examples: worked values, and example frames with their meaning, the
//! manual's misprints and whether the request is answered.

use super::error_codes::error_code_digits;
use crate::emit::words::{meaning_text, shown_bytes, value_text};
use crate::ir::*;
use serde::Serialize;
use vfd_runtime::Role;

#[derive(Serialize)]
pub(super) struct ValueExampleView<'a> {
    #[serde(flatten)]
    example: &'a ValueExampleIr,
    register_code: String,
    value_display: String,
    raw_hex: String,
}

#[derive(Serialize)]
pub(super) struct ExampleView<'a> {
    #[serde(flatten)]
    example: &'a ExampleIr,
    register_code: String,
    value_display: String,
    settings_display: String,
    request: Option<FrameView<'a>>,
    reply: Option<FrameView<'a>>,
    /// The request is never answered (its command's `reply: none`, a write of a register
    /// with `no_reply: true`, or an example saying nothing comes back).
    unanswered: bool,
    /// The bytes of the request the drive ignores, for a table cell.
    ignored_shown: String,
}

#[derive(Serialize)]
struct FrameView<'a> {
    shown: String,
    meaning: String,
    printed: Option<PrintedView<'a>>,
}

#[derive(Serialize)]
struct PrintedView<'a> {
    #[serde(flatten)]
    printed: &'a PrintedIr,
    /// The bytes as the manual prints them (its spacing, for hex frames).
    shown: String,
    /// Which layout the decoder took the printed bytes for, and why, when their command
    /// code chose another command's layout (empty otherwise).
    read_as: String,
}

/// `` `bytes` `` for a table cell: text with `<CR>`, or hex pairs.
pub(super) fn shown(bytes: &[u8]) -> String {
    format!("`{}`", shown_bytes(bytes))
}

/// When the decoder read printed bytes with the layout of another command than the
/// corrected frame's (their command code chose it), a sentence saying so: the rejection
/// then follows from that layout, not from the mistake the erratum names.
fn printed_read_as(
    drive: &DriveIr,
    example: &ExampleIr,
    frame: &FrameIr,
    printed: &PrintedIr,
) -> String {
    let Some(protocol) = drive.protocols.iter().find(|p| p.id == example.protocol) else {
        return String::new();
    };
    let Some(rest) = printed.rejection.split("failed with: ").nth(1) else {
        return String::new();
    };
    let Some(layout) = rest.split(':').next() else {
        return String::new();
    };
    let Some(command) = protocol
        .commands
        .iter()
        .find(|c| c.request == layout || c.reply == layout)
    else {
        return String::new();
    };
    let file = drive.protocol_files.iter().find(|f| f.id == protocol.uses);
    let has_command = file
        .and_then(|f| f.layouts.iter().find(|l| l.name == layout))
        .is_some_and(|l| l.has(Role::Command));
    let Some(corrected) = frame.meaning.code else {
        return String::new();
    };
    // The corrected frame's own command uses the layout too: the command code did not
    // choose another layout.
    let same_layout = protocol.commands.iter().any(|c| {
        (c.request == layout || c.reply == layout)
            && (c.code == corrected || c.reply_codes.contains(&corrected))
    });
    if !has_command || same_layout {
        return String::new();
    }
    let label = vfd_runtime::protocol::code_label(command.code);
    let code = if label.len() == 1 {
        format!("`{label}` ({:02X}h)", command.code)
    } else {
        format!("`{label}`")
    };
    let stop = if printed.rejection.ends_with('.') {
        ""
    } else {
        "."
    };
    format!(
        "{stop} The decoder chooses a layout by the command code: the printed {code} is the {} command's, so the bytes are read as `{layout}`, and that layout's check fails.",
        command.kind.as_str()
    )
}

/// Whether the request `frame` of `example` is never answered: its command says so, or it
/// writes a register whose writes are not answered.
fn request_unanswered(
    drive: &DriveIr,
    example: &ExampleIr,
    frame: &FrameIr,
    register: Option<&RegisterIr>,
) -> bool {
    let meaning = &frame.meaning;
    let command = drive
        .protocols
        .iter()
        .find(|p| p.id == example.protocol)
        .and_then(|p| {
            p.commands.iter().find(|c| {
                Some(c.kind) == meaning.kind
                    && meaning.code.is_some_and(|code| {
                        code == c.code
                            || (c.lowercase_means_sender_tripped
                                && u8::try_from(code)
                                    .is_ok_and(|b| u32::from(b.to_ascii_uppercase()) == c.code))
                    })
            })
        });
    command.is_some_and(|c| c.no_reply)
        || (meaning.kind.is_some_and(|k| k.is_write()) && register.is_some_and(|r| r.no_reply))
}

/// The worked values, each with its register and the settings it assumes.
pub(super) fn value_example_views(drive: &DriveIr) -> Vec<ValueExampleView<'_>> {
    let register = |id: &str| drive.register(id);
    drive
        .value_examples
        .iter()
        .filter_map(|example| {
            let register = register(&example.register)?;
            let given: Vec<String> = example
                .given
                .iter()
                .map(|(code, value)| format!("{code} = {value}"))
                .collect();
            let value = value_text(register, example.value);
            Some(ValueExampleView {
                example,
                register_code: register.code.clone(),
                value_display: if given.is_empty() {
                    value
                } else {
                    format!("{value} (with {})", given.join(", "))
                },
                raw_hex: format!("{:04X}h", example.raw),
            })
        })
        .collect()
}

/// The example frames, each with its meaning, misprint and whether it is answered.
pub(super) fn example_views<'a>(drive: &'a DriveIr) -> Vec<ExampleView<'a>> {
    let register = |id: &str| drive.register(id);
    drive
        .examples
        .iter()
        .map(|example| {
            let described = example.register.as_deref().and_then(register);
            let protocol = drive.protocols.iter().find(|p| p.id == example.protocol);
            let error_digits = protocol.map_or(4, |p| error_code_digits(drive, p));
            let errors = match protocol.map(|p| &p.error_table) {
                Some(ErrorTableIr::Protocol(table)) => table,
                _ => &drive.error_codes,
            };
            let frame = |frame: &'a Option<FrameIr>| {
                frame.as_ref().map(|frame| FrameView {
                    shown: shown(&frame.bytes),
                    meaning: meaning_text(drive, frame, errors, error_digits),
                    printed: frame.printed.as_ref().map(|printed| PrintedView {
                        printed,
                        shown: if printed.written.is_empty() {
                            shown(&printed.bytes)
                        } else {
                            format!("`{}`", printed.written)
                        },
                        read_as: printed_read_as(drive, example, frame, printed),
                    }),
                })
            };
            let unanswered = example.no_reply
                || example
                    .request
                    .as_ref()
                    .is_some_and(|frame| request_unanswered(drive, example, frame, described));
            ExampleView {
                unanswered,
                ignored_shown: example
                    .ignored_request
                    .as_ref()
                    .map_or_else(String::new, |ignored| shown(&ignored.bytes)),
                example,
                register_code: described.map(|r| r.code.clone()).unwrap_or_default(),
                value_display: match (example.value, described) {
                    (Some(value), Some(r)) => value_text(r, value),
                    _ => String::new(),
                },
                settings_display: example
                    .settings
                    .iter()
                    .map(|(code, value)| format!("{code} = {value}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                request: frame(&example.request),
                reply: frame(&example.reply),
            }
        })
        .collect()
}
