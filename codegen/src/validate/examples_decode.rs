//! Check: every example frame decodes to what it says; printed errata are rejected for the stated reason.

use crate::diagnostics::Diagnostics;

use crate::frames::DecodedFrame;
use crate::parse::model::{ExpectModel, FrameModel, PrintedRejection};
use crate::validate::{ranges, Context};
use vfd_runtime::meaning::{Direction, FrameMeaning};
use vfd_runtime::protocol::NotAnAnswer;
use vfd_runtime::{DecodeError, DecodeErrorKind};

/// Every example frame decodes to what it says; printed errata are rejected for the stated reason.
pub fn examples_decode(drive: &Context, out: &mut Diagnostics) {
    for (index, example) in drive.model.examples.iter().enumerate() {
        let base = format!("examples[{index}]");
        if drive.frames[index].protocol.is_none() {
            if drive
                .model
                .protocols
                .iter()
                .any(|p| p.id == example.protocol)
            {
                continue; // The protocol is declared but failed to load; that is reported already.
            }
            let known: Vec<&str> = drive
                .model
                .protocols
                .iter()
                .map(|p| p.id.as_str())
                .collect();
            out.push(
                drive
                    .source
                    .error(
                        &format!("{base}.protocol"),
                        format!("unknown protocol `{}`", example.protocol),
                    )
                    .hint(format!(
                        "use one of the drive's protocols: {}",
                        known.join(", ")
                    )),
            );
            continue;
        }
        if example.request.is_none()
            && example.reply.is_none()
            && example.unanswered_request.is_none()
        {
            out.push(
                drive
                    .source
                    .error(&base, "an example needs a `request`, a `reply` or both")
                    .hint("copy the frames from the manual"),
            );
        }
        let decoded = &drive.frames[index];
        // The protocol the frames are meant in (its first variant, the one the layouts are
        // written in, unless the example names another).
        let runtime = decoded.protocol.map(|at| &drive.protocols[at].runtime);
        if let (Some(runtime), Some(variant)) = (runtime, &example.variant) {
            if crate::frames::in_variant(runtime, variant).is_none() {
                out.push(unknown_variant(
                    drive,
                    &format!("{base}.variant"),
                    runtime,
                    variant,
                ));
                continue;
            }
        }
        let written_in = runtime.filter(|_| example.variant.is_none());
        if let (Some(model), Some(frame)) = (&example.unanswered_request, &decoded.unanswered) {
            check_unanswered(
                drive,
                &format!("{base}.unanswered_request"),
                model.rejected_as,
                frame,
                out,
            );
        }
        // Frames of the example in another variant share one cause (the example names no
        // `variant`): the first such frame reports it.
        let mut variant_reported = false;
        for (key, model, frame, printed_answers) in [
            ("request", &example.request, &decoded.request, None),
            (
                "reply",
                &example.reply,
                &decoded.reply,
                decoded.printed_answers.as_ref(),
            ),
        ] {
            if let (Some(model), Some(frame)) = (model, frame) {
                check_frame(
                    drive,
                    &format!("{base}.{key}"),
                    model,
                    frame,
                    printed_answers,
                    written_in.map(|runtime| (runtime, direction_of(key))),
                    &mut variant_reported,
                    out,
                );
            }
        }
        if let Some(value) = example.value {
            super::example_values::check_example_value(drive, &base, value, decoded, out);
        }
        check_settings(drive, &base, &example.settings, out);
    }
}

/// Each assumed setting names a described register and a value it can hold (a code of its
/// table, or a raw value in its range).
fn check_settings(
    drive: &Context,
    base: &str,
    settings: &std::collections::BTreeMap<String, f64>,
    out: &mut Diagnostics,
) {
    let index = ranges::RegisterIndex::new(&drive.model);
    for (name, value) in settings {
        let path = format!("{base}.settings.{name}");
        let Some(register) = index.find(name) else {
            out.push(
                drive
                    .source
                    .error(&path, format!("no register `{name}`"))
                    .hint("name a register of this drive by its code or id"),
            );
            continue;
        };
        let table = register
            .code_table
            .as_ref()
            .and_then(|id| drive.model.codes.iter().find(|t| &t.id == id));
        let fits = match table {
            Some(table) => table.values.iter().any(|v| f64::from(v.value) == *value),
            // A scale that is not positive is `scales_are_positive`'s to report.
            None if !ranges::has_sound_scale(register) => true,
            None => {
                let raw = (value / ranges::scale_of(register)).round() as i64;
                let (min, max) = index.raw_range(register);
                (min..=max).contains(&raw)
            }
        };
        if !fits {
            out.push(
                drive
                    .source
                    .error(&path, format!("{} cannot hold {value}", register.code))
                    .hint("give a code of its table, or a value in its range and unit"),
            );
        }
    }
}

/// The direction of an example's frame by its key (`request` or `reply`).
fn direction_of(key: &str) -> Direction {
    if key == "request" {
        Direction::Request
    } else {
        Direction::Reply
    }
}

/// The id of a protocol's first variant, shown after a space, or nothing.
pub(crate) fn protocol_variant_label(protocol: Option<&vfd_runtime::Protocol>) -> String {
    protocol
        .and_then(|p| p.variants.as_ref())
        .and_then(|v| v.choices.first())
        .map(|first| format!(" `{}`", first.id))
        .unwrap_or_default()
}

/// An example or sequence names a variant its protocol does not have.
pub(crate) fn unknown_variant(
    drive: &Context,
    path: &str,
    protocol: &vfd_runtime::Protocol,
    variant: &str,
) -> crate::diagnostics::Diagnostic {
    let known: Vec<String> = protocol
        .variants
        .as_ref()
        .map(|v| v.choices.iter().map(|c| c.id.to_string()).collect())
        .unwrap_or_default();
    let hint = if known.is_empty() {
        "the protocol has no `variants:`; leave `variant` out".to_owned()
    } else {
        format!("use one of the protocol's variants: {}", known.join(", "))
    };
    drive
        .source
        .error(path, format!("unknown variant `{variant}`"))
        .hint(hint)
}

/// `written_in`: the protocol in the variant its layouts are written in, and the frame's
/// direction, when the example names no variant (a frame that decodes only in another
/// variant is then reported as such, not as a manual mistake).
#[allow(clippy::too_many_arguments)]
fn check_frame(
    drive: &Context,
    path: &str,
    model: &FrameModel,
    frame: &DecodedFrame,
    printed_answers: Option<&Result<(), NotAnAnswer>>,
    written_in: Option<(&vfd_runtime::Protocol, Direction)>,
    variant_reported: &mut bool,
    out: &mut Diagnostics,
) {
    if let Err(message) = &frame.bytes {
        out.push(drive.source.error(path, message.clone()).hint(
            "write text frames as ascii: \"(R0501)\\r\" and binary ones as hex: \"2F 52 05 01 87\"",
        ));
        return;
    }
    let expect = &model.expect;
    let expected_code = match &expect.command {
        Some(code) => match code.value() {
            Some(value) => Some(value),
            None => {
                out.push(
                    drive
                        .source
                        .error(
                            &format!("{path}.expect.command"),
                            format!("`{}` is not one character or a number", code.shown()),
                        )
                        .hint("e.g. command: R, or command: 0x03"),
                );
                None
            }
        },
        None => None,
    };
    let other_variants = match (&frame.meaning, &frame.bytes, written_in) {
        (Some(Err(_)), Ok(bytes), Some((protocol, direction))) => {
            crate::frames::other_variants_decoding(protocol, direction, bytes)
        }
        _ => Vec::new(),
    };
    match &frame.meaning {
        None => {}
        Some(Err(_)) if !other_variants.is_empty() && *variant_reported => {}
        Some(Err(error)) if !other_variants.is_empty() => {
            *variant_reported = true;
            let first = protocol_variant_label(written_in.map(|(p, _)| p));
            out.push(
                drive
                    .source
                    .error(
                        path,
                        format!(
                            "the frame is in variant `{}` of the protocol, not in its first variant{first} (in which it does not decode: {error})",
                            other_variants.join("` or `")
                        ),
                    )
                    .hint(format!(
                        "not a manual mistake: state the variant on the example, `variant: {}`",
                        other_variants[0]
                    )),
            )
        }
        Some(Err(error)) => out.push(
            drive
                .source
                .error(path, format!("the frame does not decode: {error}"))
                .hint(match error.kind() {
                    DecodeErrorKind::ChecksumMismatch => "if the manual prints a wrong checksum, put the corrected bytes here and the printed ones under `printed:` with an `erratum:`",
                    _ => "check the bytes against the manual; record a manual mistake as `printed:` + `erratum:`",
                }),
        ),
        Some(Ok(_)) => {
            // A paged offset stands for the register it reaches on the example's page.
            let stated = frame.as_stated();
            let decoded = stated.as_deref().expect("the frame decoded");
            // Without its page, a paged offset names no register: the page is reported. A
            // register known by its wire numbers only has no number `expect` could state.
            let wire_only = crate::frames::register_of(&drive.model, decoded)
                .is_some_and(|r| r.given_address.is_none() && r.on_page.is_empty());
            let adjusted;
            let expect = if frame.register_unknown_for_its_page() {
                adjusted = ExpectModel {
                    register: None,
                    ..expect.clone()
                };
                &adjusted
            } else if wire_only && expect.register.is_none() {
                adjusted = ExpectModel {
                    register: decoded.register.map(u32::from),
                    ..expect.clone()
                };
                &adjusted
            } else {
                expect
            };
            let mismatches = mismatches(expect, expected_code, decoded);
            if !mismatches.is_empty() {
                out.push(drive.source.error(&format!("{path}.expect"), format!("the frame decodes differently: {}", mismatches.join("; "))).hint("`expect` states what the manual says the frame means (register numbers before the protocol's address map)"));
            }
        }
    }
    match (&model.printed, &model.erratum, &model.printed_rejected_as, &frame.printed) {
        (None, None, None, _) => {}
        (Some(_), Some(_), Some(reason), Some(printed)) => match (&printed.bytes, &printed.meaning) {
            (Err(message), _) => out.push(drive.source.error(&format!("{path}.printed"), message.clone()).hint("give the bytes exactly as printed")),
            (Ok(_), None) => {}
            (Ok(_), Some(decoded)) => check_printed(drive, path, *reason, decoded, expect, expected_code, printed_answers, out),
        },
        _ => out.push(
            drive
                .source
                .error(path, "an erratum needs `printed`, `erratum` and `printed_rejected_as` together")
                .hint("printed: the manual's bytes; erratum: why they are wrong; printed_rejected_as: the decoder's reason (checksum_mismatch, length_mismatch, not_allowed, unexpected_byte, truncated, trailing_bytes) or, for a frame valid on its own, does_not_answer_request or contradicts_expect"),
        ),
    }
}

/// A request the manual prints as one the drive does not answer is refused by the decoder
/// for the stated reason.
fn check_unanswered(
    drive: &Context,
    path: &str,
    reason: DecodeErrorKind,
    frame: &crate::frames::PrintedFrame,
    out: &mut Diagnostics,
) {
    match (&frame.bytes, &frame.meaning) {
        (Err(message), _) => out.push(
            drive
                .source
                .error(path, message.clone())
                .hint("give the bytes exactly as printed"),
        ),
        (Ok(_), Some(Ok(_))) => out.push(
            drive
                .source
                .error(path, "the frame decodes as a request, so a drive would answer it")
                .hint("an unanswered request is one the decoder refuses (a format error); give it as `request:` otherwise"),
        ),
        (Ok(_), Some(Err(error))) if error.kind() != reason => out.push(
            drive
                .source
                .error(
                    &format!("{path}.rejected_as"),
                    format!(
                        "the frame is rejected as {}, not {}: {error}",
                        error.kind().as_str(),
                        reason.as_str()
                    ),
                )
                .hint("state the reason the decoder gives"),
        ),
        _ => {}
    }
}

/// The manual's misprinted frame is wrong for the reason the erratum states.
#[allow(clippy::too_many_arguments)]
fn check_printed(
    drive: &Context,
    path: &str,
    reason: PrintedRejection,
    decoded: &Result<FrameMeaning, DecodeError>,
    expect: &ExpectModel,
    expected_code: Option<u32>,
    printed_answers: Option<&Result<(), NotAnAnswer>>,
    out: &mut Diagnostics,
) {
    let at = format!("{path}.printed_rejected_as");
    let problem = match (reason.decode_kind(), decoded) {
        (Some(_), Ok(_)) => Some((
            format!("{path}.printed"),
            "the printed frame decodes without error, so the decoder cannot tell it is wrong".to_owned(),
            "if it is wrong in its exchange, say `does_not_answer_request` or `contradicts_expect`; describe other meaning-only mistakes under manual_errata",
        )),
        (Some(kind), Err(error)) if error.kind() != kind => Some((
            at,
            format!("the printed frame is rejected as {}, not {}: {error}", error.kind().as_str(), reason.as_str()),
            "state the reason the decoder gives",
        )),
        (Some(_), Err(_)) => None,
        (None, Err(error)) => Some((
            at,
            format!("the printed frame does not decode ({error}), so it is rejected as {}, not {}", error.kind().as_str(), reason.as_str()),
            "state the reason the decoder gives",
        )),
        (None, Ok(meaning)) => match reason {
            PrintedRejection::ContradictsExpect if mismatches(expect, expected_code, meaning).is_empty() => Some((
                at,
                "the printed frame decodes to exactly what `expect` says".to_owned(),
                "`contradicts_expect` records a printed frame whose meaning differs from the corrected one",
            )),
            PrintedRejection::DoesNotAnswerRequest => match printed_answers {
                None => Some((
                    at,
                    "only a reply whose example has a request can fail to answer it".to_owned(),
                    "give the request the printed reply should answer",
                )),
                Some(Ok(())) => Some((
                    at,
                    "the printed reply answers its request".to_owned(),
                    "`does_not_answer_request` records a reply carrying another station, register, index or written value",
                )),
                Some(Err(NotAnAnswer::Differs(_))) => None,
                Some(Err(other)) => Some((
                    at,
                    format!("the printed reply is refused for another reason: {other}"),
                    "state the reason the decoder gives",
                )),
            },
            _ => None,
        },
    };
    if let Some((at, message, hint)) = problem {
        out.push(drive.source.error(&at, message).hint(hint));
    }
}

/// How a decoded frame differs from what `expect:` says, field by field.
fn mismatches(
    expect: &ExpectModel,
    expected_code: Option<u32>,
    decoded: &FrameMeaning,
) -> Vec<String> {
    let mut mismatches = Vec::new();
    let show = |v: Option<u32>| v.map_or("absent".to_owned(), |v| format!("{v:04X}h"));
    if expected_code != decoded.code {
        let label =
            |c: Option<u32>| c.map_or("absent".to_owned(), vfd_runtime::protocol::code_label);
        mismatches.push(format!(
            "command is {}, expected {}",
            label(decoded.code),
            label(expected_code)
        ));
    }
    let wide = |v: Option<u16>| v.map(u32::from);
    for (name, wanted, got) in [
        ("register", expect.register, wide(decoded.register)),
        (
            "wire_register",
            expect.wire_register,
            if expect.wire_register.is_some() {
                wide(decoded.wire_register)
            } else {
                None
            },
        ),
        ("index", expect.index, wide(decoded.index)),
        ("data", expect.data, decoded.data),
        ("error_code", expect.error_code, wide(decoded.error_code)),
        ("read_count", expect.read_count, decoded.read_count),
        ("write_status", expect.write_status, decoded.write_status),
        (
            "reply_wait",
            expect.reply_wait,
            if expect.reply_wait.is_some() {
                decoded.reply_wait
            } else {
                None
            },
        ),
        (
            "address",
            expect.address.map(u32::from),
            decoded.address.map(u32::from),
        ),
    ] {
        if wanted != got {
            mismatches.push(format!(
                "{name} is {}, expected {}",
                show(got),
                show(wanted)
            ));
        }
    }
    let wanted = expect.broadcast.as_deref().map(|text| {
        text.parse::<vfd_runtime::Broadcast>().map_or_else(
            |_| format!("`{text}` (not all or a group like *9)"),
            |b| b.to_string(),
        )
    });
    let got = decoded.broadcast.map(|b| b.to_string());
    if wanted != got {
        let shown = |v: Option<String>| v.unwrap_or_else(|| "absent".to_owned());
        mismatches.push(format!(
            "broadcast is {}, expected {}",
            shown(got),
            shown(wanted)
        ));
    }
    let process = decoded.process.map(|[a, b]| [u32::from(a), u32::from(b)]);
    if expect.process != process {
        mismatches.push(format!(
            "process words are {:X?}, expected {:X?}",
            process, expect.process
        ));
    }
    if expect.text != decoded.text {
        mismatches.push(format!(
            "text is {:?}, expected {:?}",
            decoded.text, expect.text
        ));
    }
    let words = decoded
        .words
        .as_ref()
        .map(|words| words.iter().map(|w| u32::from(*w)).collect::<Vec<_>>());
    if expect.words != words {
        mismatches.push(format!(
            "words are {:X?}, expected {:X?}",
            words, expect.words
        ));
    }
    if expect.tripped != decoded.tripped {
        mismatches.push(format!(
            "tripped is {}, expected {}",
            decoded.tripped, expect.tripped
        ));
    }
    mismatches
}

#[cfg(test)]
mod tests {
    use super::examples_decode as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    const REQUEST: &str =
        r#"request: { ascii: "(R0011)\r", expect: { command: R, register: 0x0011 } }"#;
    const REPLY: &str = r#"reply: { ascii: "(R00111F40)\r", expect: { command: R, register: 0x0011, data: 0x1F40 } }"#;

    #[test]
    fn accepts_frames_that_decode_as_stated() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn reports_an_unknown_protocol_and_lists_the_known_ones() {
        let yaml = valid_with(&[("protocol: ascii", "protocol: binary")]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "examples[0].protocol",
            "unknown protocol `binary`",
            "protocol: binary",
        );
        assert_eq!(
            diagnostic.hint.as_deref(),
            Some("use one of the drive's protocols: ascii")
        );
    }

    #[test]
    fn reports_an_example_without_frames() {
        let yaml = valid_with(&[(REQUEST, ""), (REPLY, ""), ("    value: 80.0\n", "")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0]",
            "an example needs a `request`, a `reply` or both",
            "id: read_maximum_frequency",
        );
    }

    #[test]
    fn reports_frame_bytes_that_are_missing_or_not_hex() {
        let yaml = valid_with(&[(r#"ascii: "(R0011)\r","#, r#"hex: "2F 5G","#)]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_eq!(diagnostic.path, "examples[0].request");
        assert!(diagnostic.message.contains("5G"), "{}", diagnostic.message);
        let yaml = valid_with(&[(
            r#"ascii: "(R0011)\r","#,
            r#"ascii: "(R0011)\r", hex: "28","#,
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].request",
            "give exactly one of `ascii` and `hex`",
            "request:",
        );
    }

    #[test]
    fn reports_a_frame_that_does_not_decode() {
        let yaml = valid_with(&[(r#""(R0011)\r""#, r#""(R0011&00)\r""#)]);
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_at(
            diagnostic,
            &yaml,
            "examples[0].request",
            "the frame does not decode: ascii: no request layout matches; the closest attempt failed with: read_request: sum8 checksum `sum` at byte 7 is 00h, but the covered bytes give 62h",
            "request:",
        );
        assert!(diagnostic
            .hint
            .as_deref()
            .is_some_and(|hint| hint.contains("printed:")));
    }

    #[test]
    fn reports_every_field_that_decodes_differently() {
        let yaml = valid_with(&[(
            "expect: { command: R, register: 0x0011, data: 0x1F40 }",
            "expect: { command: W, register: 0x0012, data: 0x1F41, tripped: true }",
        )]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].reply.expect",
            "the frame decodes differently: command is R, expected W; register is 0011h, expected 0012h; data is 1F40h, expected 1F41h; tripped is false, expected true",
            "reply:",
        );
    }

    #[test]
    fn reports_a_command_that_is_not_one_character() {
        let yaml = valid_with(&[(
            "expect: { command: R, register: 0x0011 }",
            "expect: { command: RD, register: 0x0011 }",
        )]);
        let found = check_yaml(check, &yaml);
        assert_eq!(found.len(), 2, "{found:#?}");
        assert_at(
            &found[0],
            &yaml,
            "examples[0].request.expect.command",
            "`RD` is not one character or a number",
            "request:",
        );
        assert_eq!(found[1].path, "examples[0].request.expect");
    }

    fn with_erratum(printed: &str, rest: &str) -> String {
        valid_with(&[(
            "expect: { command: R, register: 0x0011 } }",
            &format!("expect: {{ command: R, register: 0x0011 }}, {printed}{rest} }}"),
        )])
    }

    #[test]
    fn accepts_an_erratum_rejected_for_the_stated_reason() {
        let yaml = with_erratum(
            r#"printed: { ascii: "(R0011&00)\r" }"#,
            ", erratum: Wrong sum., printed_rejected_as: checksum_mismatch",
        );
        assert!(check_yaml(check, &yaml).is_empty());
    }

    #[test]
    fn reports_an_erratum_rejected_for_another_reason() {
        let yaml = with_erratum(
            r#"printed: { ascii: "(R0011&00)\r" }"#,
            ", erratum: Wrong sum., printed_rejected_as: truncated",
        );
        let found = check_yaml(check, &yaml);
        let diagnostic = only(&found);
        assert_eq!(diagnostic.path, "examples[0].request.printed_rejected_as");
        assert!(
            diagnostic
                .message
                .starts_with("the printed frame is rejected as checksum_mismatch, not truncated: "),
            "{}",
            diagnostic.message
        );
    }

    #[test]
    fn reports_an_erratum_whose_printed_frame_decodes() {
        let yaml = with_erratum(
            r#"printed: { ascii: "(R0012)\r" }"#,
            ", erratum: Wrong register., printed_rejected_as: checksum_mismatch",
        );
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].request.printed",
            "the printed frame decodes without error, so the decoder cannot tell it is wrong",
            "request:",
        );
    }

    #[test]
    fn reports_an_incomplete_erratum() {
        let yaml = with_erratum(
            r#"printed: { ascii: "(R0011&00)\r" }"#,
            ", erratum: Wrong sum.",
        );
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].request",
            "an erratum needs `printed`, `erratum` and `printed_rejected_as` together",
            "request:",
        );
    }

    #[test]
    fn reports_a_value_the_data_does_not_give() {
        let yaml = valid_with(&[("    value: 80.0", "    value: 60.0")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].value",
            "data 1F40h is 80.00 Hz in `FH`, not 60 Hz",
            "value: 60.0",
        );
    }

    #[test]
    fn reports_a_value_without_a_described_register_or_data() {
        let yaml = valid_with(&[
            ("(R0011)", "(R0013)"),
            ("register: 0x0011 } }", "register: 0x0013 } }"),
            ("(R00111F40)", "(R00131F40)"),
            ("register: 0x0011, data", "register: 0x0013, data"),
        ]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].value",
            "`value` needs a frame naming a described register",
            "    value: 80.0",
        );
        let yaml = valid_with(&[(REPLY, "")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].value",
            "`value` needs a frame carrying data",
            "    value: 80.0",
        );
    }
}
