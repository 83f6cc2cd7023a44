//! Stage 8: rehearsal. Each example's request is played to the virtual drive built from
//! the description itself (its run-time values, [`crate::emit::live`]), at the request's
//! station, set to the example's protocol variant, under its `settings` and in the state
//! its frames show (`prepare`: the value its reply reads, the mode and bounds its write
//! needs), so that frames are compared, not states. The virtual drive must answer with the
//! example's reply, byte for byte, and stay silent to an example's request that gets none
//! (`no_reply: true`). Where it does not, `vfd check` warns, naming the bytes and fields
//! that differ (`difference`), unless the example says why it cannot (`not_simulated:`);
//! an example saying so whose reply the drive gives after all is an error. So whatever
//! `vfd check` accepts without warnings, `vfd sim` answers as the manual prints it.

mod difference;
mod prepare;

use crate::diagnostics::Diagnostics;
use crate::ir::{DriveIr, ExampleIr, FrameIr};
use crate::parse::model::DriveFile;
use crate::parse::SourceFile;
use vfd_runtime::virtual_drive::{Outcome, VirtualDrive};
use vfd_runtime::{DriveInfo, Protocol, RegisterInfo};

/// Plays every example with a request and the reply that answers it, or a request that
/// gets none; problems (errors and warnings) go to `out`. The drive's run-time values are
/// built into `runtime` when an example needs them (and taken from it when it holds them),
/// so that a tool loading the file uses the same values instead of building them again.
pub(crate) fn examples(
    source: &SourceFile,
    model: &DriveFile,
    ir: &DriveIr,
    runtime: &mut Option<&'static DriveInfo>,
    out: &mut Diagnostics,
) {
    if !ir.examples.iter().any(|e| e.answers || e.no_reply) {
        return;
    }
    let drive = *runtime.get_or_insert_with(|| crate::emit::live::drive_info(ir));
    for example in &ir.examples {
        let Some(index) = model.examples.iter().position(|e| e.id == example.id) else {
            continue;
        };
        let base = format!("examples[{index}]");
        if example.no_reply {
            unanswered(source, drive, example, &base, out);
            continue;
        }
        let Some((protocol, heard)) = rehearse(drive, example) else {
            continue;
        };
        let Some(reply) = &example.reply else {
            continue;
        };
        let same = matches!(&heard, Outcome::Reply(bytes) if *bytes == reply.bytes);
        match (same, &example.not_simulated) {
            (true, None) | (false, Some(_)) => {}
            (true, Some(_)) => out.push(
                source
                    .error(
                        &format!("{base}.not_simulated"),
                        "the virtual drive gives this example's reply, byte for byte, although `not_simulated` says it cannot",
                    )
                    .hint("remove `not_simulated`"),
            ),
            (false, None) => out.push(
                source
                    .warning(
                        &format!("{base}.reply"),
                        format!(
                            "the virtual drive built from this file {}, not with the example's reply {}{}",
                            match &heard {
                                Outcome::Reply(bytes) => format!(
                                    "answers the request with {}{}",
                                    shown(reply, bytes),
                                    refusal(drive, example, bytes)
                                ),
                                Outcome::Silent(why) => format!("stays silent ({why})"),
                            },
                            shown(reply, &reply.bytes),
                            match &heard {
                                Outcome::Reply(bytes) => format!(
                                    ": {}",
                                    difference::difference(&protocol, reply, bytes)
                                ),
                                Outcome::Silent(_) => String::new(),
                            }
                        ),
                    )
                    .hint(
                        "the rehearsal set what the example shows (the value its reply reads, the mode and bounds its write needs) before playing it; where the reply still differs, give the settings the frames assume in `settings:`, check the register's storage, access, range and scale against the manual, or say in `not_simulated:` why the virtual drive cannot give this reply",
                    ),
            ),
        }
    }
}

/// Plays an example whose request gets no reply (`no_reply: true`): the virtual drive must
/// stay silent, else a warning says what it answers.
fn unanswered(
    source: &SourceFile,
    drive: &'static DriveInfo,
    example: &ExampleIr,
    base: &str,
    out: &mut Diagnostics,
) {
    let Some((_, Outcome::Reply(bytes))) = rehearse(drive, example) else {
        return;
    };
    let Some(request) = &example.request else {
        return;
    };
    out.push(
        source
            .warning(
                &format!("{base}.no_reply"),
                format!(
                    "the virtual drive built from this file answers the request with {}{}, although the example says nothing comes back",
                    shown(request, &bytes),
                    refusal(drive, example, &bytes)
                ),
            )
            .hint("if the manual says the drive does not answer, describe why: the command's `reply: none` in its protocol file, the register's `no_reply: true`, or the protocol entry's `broadcast` rule (`answered_by: none`)"),
    );
}

/// The protocol (in the example's variant) and what the virtual drive answers to the
/// example's request; `None` when the example has no request, or (unless it gets no reply)
/// no reply that answers it.
fn rehearse(drive: &'static DriveInfo, example: &ExampleIr) -> Option<(Protocol, Outcome)> {
    let request = example.request.as_ref()?;
    if !example.no_reply && !example.answers {
        return None;
    }
    let lowered = drive.protocol(&example.protocol)?;
    // In a named variant, the drive is set to it, as on its panel before power-on.
    let in_variant = example.variant.as_deref().and_then(|id| {
        let index = lowered.variants.as_ref()?.index_of(id)?;
        lowered.in_variant(index)
    });
    let protocol = in_variant.as_ref().unwrap_or(lowered);
    let mut virtual_drive = VirtualDrive::new(drive);
    if in_variant.is_some() {
        virtual_drive.select_variant(protocol);
    }
    // A broadcast is answered by the station the reply names.
    let station = match (request.meaning.broadcast, &example.reply) {
        (Some(_), Some(reply)) => reply.meaning.address,
        _ => request.meaning.address,
    };
    if let Some(station) = station {
        virtual_drive.set_address(station);
    }
    for (code, value) in &example.settings {
        if let Some(info) = drive.register(code) {
            virtual_drive.preset(code, raw_of(info, *value));
        }
    }
    // On the page the example names, as the manual's page switch before it left the drive.
    if let Some(page) = example.page {
        virtual_drive.set_page(protocol, page);
    }
    if let Some(reply) = &example.reply {
        prepare::prepare(&mut virtual_drive, drive, example, request, reply);
    }
    let heard = virtual_drive.respond(protocol, &request.bytes);
    Some((protocol.clone(), heard))
}

/// The raw word for `value` in `info`'s unit (a code for code tables), as the panel would
/// set it; negative values of signed registers in two's complement.
fn raw_of(info: &RegisterInfo, value: f64) -> u32 {
    if info.codes.is_some() || info.scale == 0.0 {
        return value as u32;
    }
    let raw = (value / info.scale).round() as i64;
    match (raw < 0, info.data_type) {
        (true, vfd_runtime::DataType::DoubleWord) => raw as i32 as u32,
        (true, _) => u32::from(raw as i16 as u16),
        (false, _) => raw as u32,
    }
}

/// `, an error reply: code 0002h (Unknown register: meaning)` when the virtual drive's
/// answer is an error reply its protocol names; empty otherwise.
fn refusal(drive: &DriveInfo, example: &ExampleIr, bytes: &[u8]) -> String {
    let Some(protocol) = drive.protocol(&example.protocol) else {
        return String::new();
    };
    match protocol.decode_reply(None, bytes) {
        Ok(vfd_runtime::protocol::Found::Frame {
            frame: vfd_runtime::Reply::Error { error, .. },
            ..
        }) => match protocol.error_code(error) {
            Some(info) => format!(
                ", an error reply: code {error:04X}h ({}{}: {})",
                info.name,
                if info.name_zh.is_empty() {
                    String::new()
                } else {
                    format!(" / {}", info.name_zh)
                },
                info.meaning
            ),
            None => format!(", an error reply: code {error:04X}h"),
        },
        _ => String::new(),
    }
}

/// `bytes` as the example writes its frame: text with escapes, or hex pairs.
fn shown(like: &FrameIr, bytes: &[u8]) -> String {
    if like.text {
        let text: String = bytes
            .iter()
            .map(|&b| match b {
                b'\r' => "\\r".to_owned(),
                b'\n' => "\\n".to_owned(),
                0x20..=0x7E => (b as char).to_string(),
                other => format!("\\x{other:02X}"),
            })
            .collect();
        format!("\"{text}\"")
    } else {
        let hex: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
        format!("\"{}\"", hex.join(" "))
    }
}
