//! A protocol's line rules, one sentence each: frame gaps, bytes before the start, reply
//! delay, pages, broadcasts, variants and the answer to a function the drive lacks.

use crate::ir::*;
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::{Role, Space};

/// The code of the parameter register at `number`, or the number in hex when none is
/// described there.
fn parameter_code(drive: &DriveIr, number: u16) -> String {
    drive
        .register_at(Space::Parameter, number)
        .map_or_else(|| format!("{number:04X}h"), |r| r.code.clone())
}

/// One paragraph on a protocol's pages: the ranges, the page register, what resets it.
fn pages_rule(
    drive: &DriveIr,
    paging: &vfd_runtime::protocol::Paging,
    doc: &crate::ir::PagesDocIr,
) -> String {
    let ranges: Vec<String> = paging
        .ranges
        .iter()
        .zip(&doc.range_names)
        .map(|(range, name)| {
            let last_page = range.first_page + (range.last - range.first) / range.size;
            let missing = if range.missing.is_empty() {
                String::new()
            } else {
                let pages: Vec<String> = range.missing.iter().map(|p| p.to_string()).collect();
                format!(" (no page {})", pages.join(", "))
            };
            format!(
                "{name}: registers {:04X}h-{:04X}h, {} to a page, pages {}-{last_page}{missing}",
                range.first, range.last, range.size, range.first_page
            )
        })
        .collect();
    let select = match paging.select_read {
        Some(read) => format!("read {read:02X}h, write {:02X}h", paging.select_write),
        None => format!("write {:02X}h", paging.select_write),
    };
    let forgotten: Vec<String> = paging
        .forgotten_after
        .iter()
        .map(|number| parameter_code(drive, *number))
        .collect();
    let mut text = format!(
        "Parameter pages (manual section {}): {}. A request carries a paged register's offset in its page; the master first writes the page to the page register ({select}), only when the station is not known to be on that page, and forgets the page after any error",
        doc.source,
        ranges.join("; ")
    );
    if !forgotten.is_empty() {
        text.push_str(&format!(" and after writing {}", forgotten.join(", ")));
    }
    text.push_str(&format!(
        ". A drive starts on page {}{}.",
        paging.initial,
        if doc.assumed.iter().any(|a| a == "initial") {
            " (an assumption: the manual does not say)"
        } else {
            ""
        }
    ));
    if !doc.note.is_empty() {
        text.push(' ');
        text.push_str(&doc.note);
    }
    text
}

/// One sentence per line rule the drive states for `protocol`.
pub(super) fn link_rules(drive: &DriveIr, protocol: &ProtocolIr) -> Vec<String> {
    use vfd_runtime::serial::BeforeStart;
    let timing = &protocol.timing;
    let ms = |d: std::time::Duration| {
        let text = format!("{:.2}", d.as_secs_f64() * 1000.0);
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    };
    let mut rules = Vec::new();
    let chars = protocol.frame_gap_chars;
    match (chars > 0.0, timing.frame_gap_min.is_zero()) {
        (true, true) => rules.push(format!(
            "Frames are separated by {chars} character times of silence (derived from the baud rate)."
        )),
        (false, false) => rules.push(format!(
            "The silence between frames is at least {} ms whatever the baud rate.",
            ms(timing.frame_gap_min)
        )),
        (true, false) => {
            // Which of the two rules is the longer, at the baud rates the drive offers.
            let chars_time = |baud: u32| {
                SerialSettings {
                    baud,
                    data_bits: drive.serial.default_data_bits,
                    parity: drive.serial.default_parity,
                    stop_bits: drive.serial.default_stop_bits,
                }
                .char_time()
                .mul_f32(chars)
            };
            let floor_everywhere = drive
                .serial
                .baud_rates
                .iter()
                .all(|baud| chars_time(*baud) <= timing.frame_gap_min);
            rules.push(if floor_everywhere {
                format!(
                    "Frames are separated by at least {} ms of silence whatever the baud rate: longer than the protocol's {chars} character times at every baud rate the drive offers.",
                    ms(timing.frame_gap_min)
                )
            } else {
                format!(
                    "Frames are separated by {chars} character times of silence (derived from the baud rate), and by at least {} ms whatever the baud rate: the longer of the two applies.",
                    ms(timing.frame_gap_min)
                )
            });
        }
        (false, true) => {}
    }
    if timing.max_inner_gap_chars > 0.0 {
        rules.push(format!(
            "A frame may not hold a silence of {} character times or more: the drive drops it.",
            timing.max_inner_gap_chars
        ));
    }
    if begins_with_literal(drive, protocol) {
        rules.push(match timing.before_start {
            BeforeStart::Reject => {
                "Bytes before a frame's start sequence reject the frame (it is not answered)."
            }
            BeforeStart::Skip if protocol.before_start_stated => {
                "Bytes before a frame's start sequence are skipped: the frame begins at its start."
            }
            BeforeStart::Skip => {
                "Bytes before a frame's start sequence are skipped: the frame begins at its start (assumed: the library's default, not from the manual)."
            }
        }
        .to_owned());
    }
    if let Some(delay) = &timing.reply_delay {
        let names: Vec<String> = delay
            .registers
            .iter()
            .map(|number| parameter_code(drive, *number))
            .collect();
        rules.push(format!(
            "Every reply waits the time set by {} (0-{} ms in steps of {} ms, factory setting {} ms); the master adds it to the reply timeout{}.",
            names.join(" / "),
            ms(delay.max),
            ms(delay.step),
            ms(delay.default),
            if names.len() > 1 { ", the longer of them" } else { "" }
        ));
    }
    if let (Some(paging), Some(doc)) = (&protocol.paging, &protocol.pages_doc) {
        rules.push(pages_rule(drive, paging, doc));
    }
    if let Some(rule) = &protocol.broadcast {
        let codes: Vec<String> = rule
            .commands
            .iter()
            .map(|c| format!("`{}`", vfd_runtime::protocol::code_label(*c)))
            .collect();
        let answered = match rule.answered_by {
            vfd_runtime::BroadcastAnswer::None => "no station answers".to_owned(),
            vfd_runtime::BroadcastAnswer::LowestMatching => {
                "only the lowest station addressed answers, if it exists".to_owned()
            }
        };
        rules.push(format!(
            "Broadcasts: {} may be sent to every station{}; {answered}.",
            codes.join(", "),
            if station_wildcard(drive, protocol) {
                " or to a group of stations (`*` for an open digit of the station number)"
            } else {
                ""
            }
        ));
    }
    if let Some(variants) = &protocol.variants {
        rules.push(variants_rule(drive, protocol, variants));
    }
    rules.extend(unsupported_function_rule(drive, protocol));
    rules
}

/// One sentence on what the drive answers to a function it lacks, for protocols whose
/// error replies mark the request's function one way for every command (Modbus: function
/// + 80h): the manual's error code, or that the manual does not say.
fn unsupported_function_rule(drive: &DriveIr, protocol: &ProtocolIr) -> Option<String> {
    let mut offsets = protocol
        .commands
        .iter()
        .map(|c| c.error_code.map(|e| e.wrapping_sub(c.code)));
    let offset = offsets.next()??;
    if protocol.error_reply.is_none() || !offsets.all(|o| o == Some(offset)) {
        return None;
    }
    let codes: Vec<String> = protocol
        .commands
        .iter()
        .map(|c| format!("`{}`", vfd_runtime::protocol::code_label(c.code)))
        .collect();
    let lacked = format!(
        "a well-formed request with a function the drive does not carry out (any but {})",
        codes.join(", ")
    );
    let sentence = |rest: String| format!("A{} {rest}", &lacked[1..]);
    Some(match &protocol.unsupported_function {
        Some(entry) => {
            let table = match &protocol.error_table {
                ErrorTableIr::Drive => &drive.error_codes.codes,
                ErrorTableIr::Protocol(table) => &table.codes,
            };
            let name = table
                .iter()
                .find(|c| c.code == entry.error_code)
                .map_or_else(String::new, |c| {
                    if c.name_zh.is_empty() {
                        format!(" ({})", c.name)
                    } else {
                        format!(" ({}, {})", c.name, c.name_zh)
                    }
                });
            sentence(format!(
                "gets an error reply: the function + {offset:02X}h and error code {:02X}h{name} ({}).",
                entry.error_code, entry.source
            ))
        }
        None => sentence(
            "gets no answer from the library's virtual drive, so a master waits for its time-out: the manual does not say what the drive does with one.".to_owned(),
        ),
    })
}

/// The layouts of the protocol's requests, from its protocol file.
fn request_layouts<'a>(
    drive: &'a DriveIr,
    protocol: &'a ProtocolIr,
) -> impl Iterator<Item = &'a vfd_runtime::FrameLayout> + 'a {
    let file = drive.protocol_files.iter().find(|f| f.id == protocol.uses);
    protocol.commands.iter().filter_map(move |command| {
        file.and_then(|f| f.layouts.iter().find(|l| l.name == command.request))
    })
}

/// Whether the protocol's requests begin with a start sequence (a literal).
fn begins_with_literal(drive: &DriveIr, protocol: &ProtocolIr) -> bool {
    let mut layouts = request_layouts(drive, protocol).peekable();
    layouts.peek().is_some()
        && layouts.all(|l| {
            matches!(
                l.parts.first(),
                Some(vfd_runtime::layout::Part::Literal { .. })
            )
        })
}

/// Whether a request's station field takes a wildcard digit (group broadcasts).
fn station_wildcard(drive: &DriveIr, protocol: &ProtocolIr) -> bool {
    request_layouts(drive, protocol).any(|layout| {
        layout.parts.iter().any(|part| {
            matches!(part, vfd_runtime::layout::Part::Field(field)
                if field.role == Role::Address
                    && field.broadcast.as_ref().is_some_and(|b| b.wildcard.is_some()))
        })
    })
}

/// One sentence on a protocol's variants: each with its bytes, the register selecting one
/// and the error a frame in another variant's form gets.
fn variants_rule(
    drive: &DriveIr,
    protocol: &ProtocolIr,
    variants: &vfd_runtime::variant::Variants,
) -> String {
    let hex = |bytes: &[u8]| {
        bytes
            .iter()
            .map(|b| format!("{b:02X}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let choices: Vec<String> = variants
        .choices
        .iter()
        .map(|choice| {
            let zh = if choice.name_zh.is_empty() {
                String::new()
            } else {
                format!(", {}", choice.name_zh)
            };
            let literals: Vec<String> = choice
                .literals
                .iter()
                .map(|l| format!("`{}` = {}", l.part, hex(&l.bytes)))
                .collect();
            format!(
                "`{}` ({}{zh}: {})",
                choice.id,
                choice.name,
                literals.join(", ")
            )
        })
        .collect();
    let mut sentence = format!(
        "Variants: {}; the first is the layouts as shown, a master is told another with `{}.variant(\"ID\")` / `Master::with_variant` (`vfd --variant ID`)",
        choices.join(", "),
        protocol.const_name
    );
    if let Some(selector) = &variants.selected_by {
        let register = drive
            .register_at(Space::Parameter, selector.register)
            .map_or_else(|| format!("{:04X}h", selector.register), |r| r.code.clone());
        let values: Vec<String> = selector
            .values
            .iter()
            .filter_map(|v| {
                let id = variants.choices.get(usize::from(v.variant))?.id.as_ref();
                Some(format!("{} selects `{id}`", v.value))
            })
            .collect();
        sentence.push_str(&format!(
            "; the drive speaks the one {register} selects ({})",
            values.join(", ")
        ));
    }
    if let Some(code) = variants.mismatch_error {
        sentence.push_str(&format!(
            ", and answers a frame in another variant's form with error code {code:02X}h"
        ));
    }
    sentence.push('.');
    sentence
}
