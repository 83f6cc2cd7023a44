//! Check: the behaviour model's refusals (`behaviour.refusals.<protocol>`) answer with
//! codes of the table that names the protocol's error replies (the drive's, or the
//! protocol's own), so that a master turns each into the manual's meaning; the refusals
//! of unreadable frames (`bad_character`, `malformed`, `retries_exceeded`) are given only
//! for a protocol whose requests end in a terminator (how the drive tells where such a
//! frame ends); and `retries_exceeded.after` is a count or names a register.

use crate::diagnostics::Diagnostics;
use crate::parse::model::{BoundModel, RefusalsModel};
use crate::validate::ranges::RegisterIndex;
use crate::validate::Context;
use vfd_runtime::layout::Part;

/// Refusal codes are error codes of their protocol.
pub fn refusal_codes_resolve(drive: &Context, out: &mut Diagnostics) {
    let Some(behaviour) = &drive.model.behaviour else {
        return;
    };
    let index = RegisterIndex::new(&drive.model);
    for (id, refusals) in &behaviour.refusals {
        // A protocol that is not the drive's is `behaviour_resolves`'s to report; one that
        // failed to lower is reported where it is written.
        let Some(protocol) = drive.protocols.iter().find(|p| &p.id == id) else {
            continue;
        };
        let base = format!("behaviour.refusals.{id}");
        let table = &protocol.runtime.error_codes;
        if !table.is_empty() {
            for (key, code) in codes(refusals) {
                if !table.iter().any(|entry| entry.code == code) {
                    let known: Vec<String> = table
                        .iter()
                        .map(|e| format!("{:X}h {}", e.code, e.id))
                        .collect();
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{base}.{key}"),
                                format!(
                                    "{code:X}h is not an error code of protocol `{id}`: its error replies are named by {}",
                                    known.join(", ")
                                ),
                            )
                            .hint("give the code the manual's error table gives the refusal, so that a master reports its meaning"),
                    );
                }
            }
        }
        let unreadable = [
            ("bad_character", refusals.bad_character.is_some()),
            ("malformed", refusals.malformed.is_some()),
            ("retries_exceeded", refusals.retries_exceeded.is_some()),
        ];
        let terminated = protocol.runtime.commands.first().is_some_and(|c| {
            matches!(c.request.parts.last(), Some(Part::Literal { bytes, optional: false, .. }) if !bytes.is_empty())
        });
        if !terminated {
            for (key, given) in unreadable {
                if given {
                    out.push(
                        drive
                            .source
                            .error(
                                &format!("{base}.{key}"),
                                format!("protocol `{id}`'s requests end in no terminator: the drive cannot tell where an unreadable frame ends"),
                            )
                            .hint("these refusals are for framings whose requests end in a terminator (CR); leave it out"),
                    );
                }
            }
        }
        if let Some(rule) = &refusals.retries_exceeded {
            let path = format!("{base}.retries_exceeded.after");
            match &rule.after {
                BoundModel::Register(name) if index.find(name).is_none() => out.push(
                    drive
                        .source
                        .error(&path, format!("register `{name}` is not defined"))
                        .hint("name the register setting the allowed retries by its code or id, or give the number"),
                ),
                BoundModel::Number(n) if *n < 0.0 || n.fract() != 0.0 => out.push(
                    drive
                        .source
                        .error(&path, format!("{n} is not a count of frames"))
                        .hint("the number of unreadable frames in a row the drive answers with their own errors: 0, 1, 2, ..."),
                ),
                _ => {}
            }
        }
    }
}

/// Every code the refusals give, with its key.
fn codes(refusals: &RefusalsModel) -> Vec<(&'static str, u16)> {
    [
        ("unknown_register", refusals.unknown_register),
        ("read_only", refusals.read_only),
        ("out_of_range", refusals.out_of_range),
        ("while_running", refusals.while_running),
        ("bad_checksum", refusals.bad_checksum),
        ("wrong_mode", refusals.wrong_mode),
        ("bad_character", refusals.bad_character),
        ("malformed", refusals.malformed),
        (
            "retries_exceeded.code",
            refusals.retries_exceeded.as_ref().map(|r| r.code),
        ),
    ]
    .into_iter()
    .filter_map(|(key, code)| code.map(|code| (key, code)))
    .collect()
}
