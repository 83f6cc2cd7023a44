//! Check: an example's reply agrees with whether its request is answered at all: a request
//! its protocol gives no reply (a broadcast no station answers, a command or a register's
//! writes never answered) has no reply in its example, and an example saying nothing comes
//! back (`no_reply: true`) has no reply (an example without any frame is
//! `examples_decode`'s to report). An example whose reply the
//! description knowingly does not give (`not_simulated:`) is left to say so.

use crate::diagnostics::Diagnostics;
use crate::frames::{register_of, DecodedFrame};
use crate::validate::Context;
use vfd_runtime::broadcast::BroadcastAnswer;
use vfd_runtime::meaning::FrameMeaning;
use vfd_runtime::Protocol;

/// Every example whose request gets no reply by its protocol shows none, and every
/// `no_reply: true` example has no reply.
pub fn silent_requests_have_no_reply(drive: &Context, out: &mut Diagnostics) {
    for (index, (example, decoded)) in drive.model.examples.iter().zip(&drive.frames).enumerate() {
        let base = format!("examples[{index}]");
        if example.no_reply && example.reply.is_some() {
            out.push(
                drive
                    .source
                    .error(
                        &format!("{base}.no_reply"),
                        "`no_reply: true` says nothing comes back, and the example gives a `reply`",
                    )
                    .hint("keep what the manual shows: the reply, or `no_reply: true` without one"),
            );
        }
        // An example saying why the described drive does not give its reply records a
        // reply the manual prints that the description knowingly departs from.
        if example.reply.is_none() || example.not_simulated.is_some() {
            continue;
        }
        let Some(protocol) = decoded.protocol.map(|at| &drive.protocols[at].runtime) else {
            continue;
        };
        let Some(request) = decoded.request.as_ref().and_then(DecodedFrame::decoded) else {
            continue;
        };
        if let Some(why) = never_answered(drive, protocol, request) {
            out.push(
                drive
                    .source
                    .error(
                        &format!("{base}.reply"),
                        format!("the example gives a reply to a request that gets none: {why}"),
                    )
                    .hint("if the manual prints nothing coming back, leave `reply:` out and say `no_reply: true`; if it shows the drive answering, check the command, the register's `no_reply` or the protocol entry's `broadcast` rule against the manual"),
            );
        }
    }
}

/// Why `request` gets no reply by the description, if it gets none: a command never
/// answered, a write of a register whose writes are never answered, or a broadcast no
/// station answers.
fn never_answered(drive: &Context, protocol: &Protocol, request: &FrameMeaning) -> Option<String> {
    let command = protocol.commands.iter().find(|c| {
        Some(c.kind) == request.kind && request.code.is_none_or(|code| c.answers_to(code))
    });
    if let Some(command) = command.filter(|c| c.no_reply) {
        return Some(format!(
            "command {} is never answered (`reply: none` in protocol file `{}`)",
            command.code_label(),
            protocol.id
        ));
    }
    let writing = request.kind.is_some_and(|kind| kind.is_write());
    if let Some(register) = register_of(&drive.model, request).filter(|r| writing && r.no_reply) {
        return Some(format!(
            "writes of {} are never answered (`no_reply: true`)",
            register.code
        ));
    }
    request.broadcast?;
    let code = request.code.or(command.map(|c| c.code));
    match &protocol.broadcast {
        None => Some("a broadcast, and the protocol entry has no `broadcast` rule".to_owned()),
        Some(rule) if rule.answered_by == BroadcastAnswer::None => {
            Some("a broadcast, which no station answers (`answered_by: none`)".to_owned())
        }
        Some(rule) if !code.is_some_and(|code| rule.commands.contains(&code)) => Some(
            "a broadcast of a command the drive does not carry out when broadcast (not in the `broadcast` rule's `commands`)"
                .to_owned(),
        ),
        Some(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::silent_requests_have_no_reply as check;
    use crate::validate::testing::{assert_at, check_yaml, only, valid_with, VALID};

    /// The valid drive's example, its reply kept or replaced.
    const REPLY: &str = r#"    reply: { ascii: "(R00111F40)\r", expect: { command: R, register: 0x0011, data: 0x1F40 } }
"#;

    #[test]
    fn an_answered_request_with_its_reply_is_accepted() {
        assert!(check_yaml(check, VALID).is_empty());
    }

    #[test]
    fn a_reply_to_a_write_never_answered_is_reported() {
        let yaml = valid_with(&[
            (
                "code: FA00, name: Command, bitfield: command_word, ram_only: true,",
                "code: FA00, name: Command, bitfield: command_word, ram_only: true, no_reply: true,",
            ),
            (r#"(R0011)\r"#, r#"(PFA008400)\r"#),
            (
                "request: { ascii: \"(PFA008400)\\r\", expect: { command: R, register: 0x0011 } }",
                "request: { ascii: \"(PFA008400)\\r\", expect: { command: P, register: 0xFA00, data: 0x8400 } }",
            ),
            (REPLY, "    reply: { ascii: \"(PFA008400)\\r\", expect: { command: P, register: 0xFA00, data: 0x8400 } }\n"),
            ("    value: 80.0\n", ""),
        ]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].reply",
            "the example gives a reply to a request that gets none: writes of FA00 are never answered (`no_reply: true`)",
            "    reply:",
        );
    }

    #[test]
    fn a_reply_to_a_broadcast_without_a_rule_is_reported() {
        let yaml = valid_with(&[
            (r#"(R0011)\r"#, r#"(**P00111F40)\r"#),
            (
                "expect: { command: R, register: 0x0011 } }",
                "expect: { command: P, register: 0x0011, data: 0x1F40 } }",
            ),
        ]);
        let found = check_yaml(check, &yaml);
        assert_eq!(
            only(&found).message,
            "the example gives a reply to a request that gets none: a broadcast, and the protocol entry has no `broadcast` rule"
        );
    }

    #[test]
    fn no_reply_with_a_reply_is_reported() {
        let yaml = valid_with(&[("    value: 80.0\n", "    value: 80.0\n    no_reply: true\n")]);
        let found = check_yaml(check, &yaml);
        assert_at(
            only(&found),
            &yaml,
            "examples[0].no_reply",
            "`no_reply: true` says nothing comes back, and the example gives a `reply`",
            "no_reply",
        );
    }

    #[test]
    fn no_reply_with_a_request_alone_is_accepted() {
        let yaml = valid_with(&[("    value: 80.0\n", "    no_reply: true\n"), (REPLY, "")]);
        assert!(check_yaml(check, &yaml).is_empty());
    }
}
