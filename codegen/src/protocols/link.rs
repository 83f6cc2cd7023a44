//! The drive's own line rules for one protocol, from its `protocols[]` entry: the frame gap
//! (in characters, with a floor in milliseconds), the inner-gap limit, bytes before the
//! start, the reply delay set by registers, and the broadcast rule. Protocol files are
//! shared with drives whose manuals lack these rules, so they live on the drive's entry.

use super::lowered_command::LoweredCommand;
use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::{BoundModel, RegisterModel};
use std::borrow::Cow;
use std::time::Duration;
use vfd_runtime::broadcast::BroadcastRule;
use vfd_runtime::serial::{BeforeStart, LinkTiming, ReplyDelay};
use vfd_runtime::Role;

/// The frame gap in characters: the drive's override, else the protocol file's.
pub(super) fn frame_gap_chars(input: &Input<'_>, out: &mut Diagnostics) -> f32 {
    let file = input.file.protocol.frame_gap_chars;
    match input.reference.frame_gap_chars {
        Some(chars) if !(0.0..=100.0).contains(&chars) => {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{}.frame_gap_chars", input.reference_path),
                        format!("frame_gap_chars {chars} is not 0 to 100 character times"),
                    )
                    .hint("Modbus RTU and the Toshiba protocol: 3.5"),
            );
            file
        }
        Some(chars) => chars,
        None => file,
    }
}

/// The drive's timing rules for the protocol.
pub(super) fn timing(input: &Input<'_>, out: &mut Diagnostics) -> LinkTiming {
    let reference = input.reference;
    let path = |key: &str| format!("{}.{key}", input.reference_path);
    let mut timing = LinkTiming::NONE;
    if let Some(ms) = reference.frame_gap_ms {
        if (0.0..=10_000.0).contains(&ms) {
            timing.frame_gap_min = Duration::from_micros((f64::from(ms) * 1000.0).round() as u64);
        } else {
            out.push(
                input
                    .drive_source
                    .error(&path("frame_gap_ms"), format!("frame_gap_ms {ms} is not 0 to 10000 ms"))
                    .hint("the silence between frames the manual asks for, in milliseconds (DV1 Modbus RTU: 10)"),
            );
        }
    }
    if let Some(chars) = reference.max_inner_gap_chars {
        if chars > 0.0 && chars <= 100.0 {
            timing.max_inner_gap_chars = chars;
        } else {
            out.push(
                input
                    .drive_source
                    .error(
                        &path("max_inner_gap_chars"),
                        format!("max_inner_gap_chars {chars} is not above 0 and at most 100"),
                    )
                    .hint(
                        "the longest silence inside a frame, in character times (Modbus RTU: 1.5)",
                    ),
            );
        }
    }
    if let Some(before_start) = reference.before_start {
        if before_start == BeforeStart::Reject && !has_start(input) {
            out.push(
                input
                    .drive_source
                    .error(
                        &path("before_start"),
                        format!(
                            "protocol `{}` has no start sequence for bytes to come before",
                            reference.uses
                        ),
                    )
                    .hint("`before_start` applies to protocols whose layouts begin with a literal"),
            );
        } else {
            timing.before_start = before_start;
        }
    }
    timing.reply_delay = reply_delay(input, out);
    timing
}

/// Whether the protocol's frames begin with a literal start sequence.
fn has_start(input: &Input<'_>) -> bool {
    input.file.layouts.values().next().is_some_and(|parts| {
        matches!(parts.first(), Some(crate::parse::model::PartRefModel::Inline(part)) if part.literal.is_some() || part.literal_hex.is_some())
            || matches!(parts.first(), Some(crate::parse::model::PartRefModel::Named(name))
                if input.file.parts.get(name).is_some_and(|p| p.literal.is_some() || p.literal_hex.is_some()))
    })
}

/// The registers whose value delays every reply: each must be described, with a unit of
/// time and a highest value.
fn reply_delay(input: &Input<'_>, out: &mut Diagnostics) -> Option<ReplyDelay> {
    let model = input.reference.reply_delay.as_ref()?;
    let base = format!("{}.reply_delay.registers", input.reference_path);
    if model.registers.is_empty() {
        out.push(
            input
                .drive_source
                .error(&base, "reply_delay names no register")
                .hint("name the register(s) that set the wait before a reply (code or id)"),
        );
        return None;
    }
    let mut delay: Option<ReplyDelay> = None;
    let mut registers = Vec::new();
    for (index, name) in model.registers.iter().enumerate() {
        let path = format!("{base}[{index}]");
        let Some(register) = find_register(input, name) else {
            out.push(
                input
                    .drive_source
                    .error(&path, format!("no register `{name}`"))
                    .hint("name a described register by its code or id"),
            );
            return None;
        };
        let unit = match register.unit.as_deref() {
            Some("s") => 1.0,
            Some("ms") => 0.001,
            other => {
                out.push(
                    input
                        .drive_source
                        .error(
                            &path,
                            format!(
                                "register `{name}` is in {}, not a unit of time",
                                other.unwrap_or("no unit")
                            ),
                        )
                        .hint("the reply delay register's unit must be s or ms"),
                );
                return None;
            }
        };
        let Some(BoundModel::Number(max)) = register.range.as_ref().map(|r| &r.max) else {
            out.push(
                input
                    .drive_source
                    .error(
                        &path,
                        format!("register `{name}` has no numeric highest value"),
                    )
                    .hint("give the register a `range` with a number as `max`"),
            );
            return None;
        };
        let seconds = |value: f64| Duration::from_secs_f64((value * unit).max(0.0));
        let step = seconds(register.scale.unwrap_or(1.0));
        let default = seconds(register.default.unwrap_or(0.0));
        let max = seconds(*max);
        delay = Some(match delay {
            None => ReplyDelay {
                registers: Cow::Owned(Vec::new()),
                step,
                default,
                max,
            },
            Some(before) => {
                if before.step != step {
                    out.push(
                        input
                            .drive_source
                            .error(&path, format!("register `{name}` counts in other steps than the first register"))
                            .hint("the reply delay registers must share their scale and unit"),
                    );
                    return None;
                }
                ReplyDelay {
                    default: before.default.max(default),
                    max: before.max.max(max),
                    ..before
                }
            }
        });
        registers.push(u16::try_from(register.address).unwrap_or(u16::MAX));
    }
    delay.map(|delay| ReplyDelay {
        registers: Cow::Owned(registers),
        ..delay
    })
}

/// The register with this code, id or alias in the drive file.
pub(super) fn find_register<'a>(input: &'a Input<'_>, name: &str) -> Option<&'a RegisterModel> {
    input.drive.registers.iter().find(|r| r.is_named(name))
}

/// The drive's broadcast rule: its commands must be the protocol's writes, each with a
/// station field that has broadcast encodings.
pub(super) fn broadcast(
    input: &Input<'_>,
    commands: &[LoweredCommand],
    out: &mut Diagnostics,
) -> Option<BroadcastRule> {
    let model = input.reference.broadcast.as_ref()?;
    let base = format!("{}.broadcast.commands", input.reference_path);
    let mut codes = Vec::new();
    if model.commands.is_empty() {
        out.push(
            input
                .drive_source
                .error(&base, "the broadcast rule lists no command")
                .hint(
                    "list the writes the drive carries out when broadcast, e.g. [W, P] or [0x06]",
                ),
        );
        return None;
    }
    for (index, code) in model.commands.iter().enumerate() {
        let path = format!("{base}[{index}]");
        let Some(value) = code.value() else {
            out.push(
                input
                    .drive_source
                    .error(
                        &path,
                        format!("`{}` is not one character or a number", code.shown()),
                    )
                    .hint("e.g. W, or 0x06"),
            );
            return None;
        };
        let Some(command) = commands.iter().find(|c| c.spec.code == value) else {
            out.push(
                input
                    .drive_source
                    .error(
                        &path,
                        format!(
                            "protocol `{}` has no command {}",
                            input.reference.id,
                            code.shown()
                        ),
                    )
                    .hint("list commands of the protocol that the drive carries out"),
            );
            return None;
        };
        if !command.spec.kind.is_write() {
            out.push(
                input
                    .drive_source
                    .error(
                        &path,
                        format!(
                            "command {} reads; only writes may be broadcast",
                            code.shown()
                        ),
                    )
                    .hint("no station could answer a read for all of them: list writes only"),
            );
            return None;
        }
        let carries = command
            .spec
            .request
            .field(Role::Address)
            .is_some_and(|field| field.broadcast.is_some());
        if !carries {
            out.push(
                input
                    .drive_source
                    .error(
                        &path,
                        format!(
                            "the station field of command {} in `{}` has no broadcast encoding",
                            code.shown(),
                            input.reference.uses
                        ),
                    )
                    .hint("give the protocol file's address part `broadcast: { literal: ... }` or `{ value: ... }`"),
            );
            return None;
        }
        codes.push(value);
    }
    Some(BroadcastRule {
        commands: Cow::Owned(codes),
        answered_by: model.answered_by,
    })
}
