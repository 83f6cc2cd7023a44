//! Protocols as run-time values: each `vfd_runtime::Protocol` with its commands naming
//! their layouts, as `emit/rust/protocols.rs` writes them. Layouts keep the plan the IR
//! computed for them, run step by step (no compiled functions).

use crate::ir::{CommandIr, DriveIr, ErrorCodeIr, ErrorTableIr, ProtocolIr};
use std::borrow::Cow;
use vfd_runtime::protocol::{FollowUp, PercentOf, VariantCache};
use vfd_runtime::{CommandSpec, ErrorCodeInfo, FrameLayout, Protocol};

/// The protocol `protocol` of `ir`.
pub(super) fn protocol(ir: &DriveIr, protocol: &ProtocolIr) -> Protocol {
    let layout = |name: &str| layout(ir, protocol, name);
    let error_codes: Vec<ErrorCodeInfo> = match &protocol.error_table {
        ErrorTableIr::Drive => ir.error_codes.codes.iter().map(error_code).collect(),
        ErrorTableIr::Protocol(table) => table.codes.iter().map(error_code).collect(),
    };
    Protocol {
        id: Cow::Owned(protocol.id.clone()),
        name: Cow::Owned(protocol.name.clone()),
        commands: Cow::Owned(
            protocol
                .commands
                .iter()
                .map(|command| command_spec(command, &layout))
                .collect(),
        ),
        error_reply: protocol.error_reply.as_deref().map(layout),
        lowercase_means_tripped: protocol.lowercase_means_tripped,
        max_frame_len: protocol.max_frame_len,
        address_range: protocol.address_range,
        default_optional_parts: Cow::Owned(
            protocol
                .default_optional_parts
                .iter()
                .map(|p| Cow::Owned(p.clone()))
                .collect(),
        ),
        error_codes: Cow::Owned(error_codes),
        pre_steps: Cow::Owned(protocol.pre_steps.clone()),
        default_process: protocol.default_process.unwrap_or([0, 0]),
        frame_gap_chars: protocol.frame_gap_chars,
        max_words_per_read: protocol.max_words_per_read,
        max_words_per_write: protocol.max_words_per_write,
        partial_blocks: protocol.partial_blocks,
        block: protocol.block.clone(),
        timing: protocol.timing.clone(),
        broadcast: protocol.broadcast.clone(),
        wire_numbers: Cow::Owned(protocol.wire_numbers.clone()),
        paging: protocol.paging.clone(),
        persistence: protocol.persistence.clone(),
        variants: protocol.variants.clone(),
        unsupported_function: protocol.unsupported_function.as_ref().map(|u| u.error_code),
        variant_cache: VariantCache::new(),
    }
}

/// The layout `name` of the protocol file `protocol` uses. Lowering names only layouts
/// the file has; an empty layout of that name stands in should one be missing.
fn layout(ir: &DriveIr, protocol: &ProtocolIr, name: &str) -> FrameLayout {
    ir.protocol_files
        .iter()
        .find(|file| file.id == protocol.uses)
        .and_then(|file| file.layouts.iter().find(|l| l.name == name))
        .cloned()
        .unwrap_or_else(|| FrameLayout {
            name: Cow::Owned(name.to_owned()),
            parts: Cow::Borrowed(&[]),
            encoding: vfd_runtime::Encoding::Binary,
            plan: None,
        })
}

/// One command, as `CommandSpec::new(..)` and its `with_*` calls build it.
fn command_spec(command: &CommandIr, layout: &dyn Fn(&str) -> FrameLayout) -> CommandSpec {
    let mut spec = CommandSpec::new(
        command.code,
        command.kind,
        layout(&command.request),
        layout(&command.reply),
    );
    spec.data_types = Cow::Owned(command.data_types.clone());
    spec.space = command.space;
    spec.address_map = command.address_map;
    spec.reply_codes = Cow::Owned(command.reply_codes.clone());
    spec.error_code = command.error_code;
    spec.no_reply = command.no_reply;
    spec.extra = command.extra;
    spec.lowercase_means_sender_tripped = command.lowercase_means_sender_tripped;
    spec.stored_by_instruction = command.stored_by_instruction;
    spec.registers = Cow::Owned(command.registers.clone());
    spec.percent_of = command
        .percent_of
        .as_ref()
        .map(|(register, step, received_by)| PercentOf {
            register: Cow::Owned(register.clone()),
            step: *step,
            received_by: Cow::Owned(
                received_by
                    .iter()
                    .map(|id| Cow::Owned(id.clone()))
                    .collect(),
            ),
        });
    spec.follow_up = command.follow_up.as_ref().map(|(ok, again)| FollowUp {
        ok: layout(ok),
        again: layout(again),
    });
    spec
}

/// One entry of an error-code table.
fn error_code(code: &ErrorCodeIr) -> ErrorCodeInfo {
    ErrorCodeInfo {
        code: code.code,
        id: Cow::Owned(code.id.clone()),
        name: Cow::Owned(code.name.clone()),
        name_zh: Cow::Owned(code.name_zh.clone()),
        meaning: Cow::Owned(code.meaning.clone()),
        printed_as: Cow::Owned(code.printed.clone()),
    }
}
