//! Lowers the drive's protocols: each protocol file once with the layouts it uses, and
//! each protocol as the drive speaks it, with the table naming its error replies.

use crate::ir::types::*;
use crate::naming::{const_name, module_name, type_name};
use crate::parse::model::{DriveFile, ErrorCodeModel};
use crate::protocols::{drive_table_applies, LoweredProtocol};
use vfd_runtime::FrameLayout;

/// Each protocol file once, with every layout its commands and error reply use.
pub(super) fn protocol_files(protocols: &[LoweredProtocol]) -> Vec<ProtocolFileIr> {
    let mut files: Vec<ProtocolFileIr> = Vec::new();
    for protocol in protocols {
        if files.iter().any(|f| f.id == protocol.uses) {
            continue;
        }
        let mut layouts: Vec<FrameLayout> = Vec::new();
        let runtime = &protocol.runtime;
        let used = runtime
            .commands
            .iter()
            .flat_map(|c| {
                [&c.request, &c.reply]
                    .into_iter()
                    .chain(c.follow_up.iter().flat_map(|f| [&f.ok, &f.again]))
            })
            .chain(runtime.error_reply.iter());
        for layout in used {
            if !layouts.iter().any(|l| l.name == layout.name) {
                layouts.push(layout.clone());
            }
        }
        let meta = &protocol.file.protocol;
        files.push(ProtocolFileIr {
            id: protocol.uses.clone(),
            module: module_name(&protocol.uses),
            name: meta.name.clone(),
            name_zh: meta.name_zh.clone(),
            description: meta.description.trim().to_owned(),
            text: meta.text,
            layouts,
            based_on: protocol.file.based_on.as_ref().map(|b| b.protocol.clone()),
        });
    }
    files
}

pub(super) fn lower_error_codes(
    codes: &[ErrorCodeModel],
    notation: Option<&crate::parse::model::CodeNotationModel>,
) -> Vec<ErrorCodeIr> {
    codes
        .iter()
        .map(|c| ErrorCodeIr {
            code: c.code as u16,
            id: c.id.clone(),
            variant: type_name(&c.id),
            name: c.name.clone(),
            name_zh: c.name_zh.clone(),
            meaning: c.meaning.clone(),
            printed: notation.map_or_else(String::new, |n| n.print(c.code)),
        })
        .collect()
}

/// The drive's `block:` on the protocol with this id.
fn block_model<'m>(model: &'m DriveFile, id: &str) -> Option<&'m crate::parse::model::BlockModel> {
    model
        .protocols
        .iter()
        .find(|p| p.id == id)
        .and_then(|p| p.block.as_ref())
}

pub(super) fn lower_protocol(model: &DriveFile, protocol: &LoweredProtocol) -> ProtocolIr {
    let runtime = &protocol.runtime;
    let reference = model.protocols.iter().find(|p| p.id == protocol.id);
    let own_table = reference.and_then(|r| r.error_codes.as_ref());
    ProtocolIr {
        id: protocol.id.clone(),
        const_name: const_name(&protocol.id),
        uses: protocol.uses.clone(),
        source: protocol.source_section.clone(),
        name: runtime.name.to_string(),
        commands: runtime
            .commands
            .iter()
            .map(|c| CommandIr {
                code: c.code,
                kind: c.kind,
                data_types: c.data_types.to_vec(),
                space: c.space,
                address_map: c.address_map,
                request: c.request.name.to_string(),
                reply: c.reply.name.to_string(),
                reply_codes: c.reply_codes.to_vec(),
                error_code: c.error_code,
                no_reply: c.no_reply,
                extra: c.extra,
                lowercase_means_sender_tripped: c.lowercase_means_sender_tripped,
                stored_by_instruction: c.stored_by_instruction,
                registers: c.registers.to_vec(),
                percent_of: c.percent_of.as_ref().map(|p| {
                    (
                        p.register.to_string(),
                        p.step,
                        p.received_by.iter().map(|id| id.to_string()).collect(),
                    )
                }),
                follow_up: c
                    .follow_up
                    .as_ref()
                    .map(|f| (f.ok.name.to_string(), f.again.name.to_string())),
            })
            .collect(),
        error_reply: runtime.error_reply.as_ref().map(|l| l.name.to_string()),
        lowercase_means_tripped: runtime.lowercase_means_tripped,
        max_frame_len: runtime.max_frame_len,
        address_range: runtime.address_range,
        default_optional_parts: runtime
            .default_optional_parts
            .iter()
            .map(|p| p.to_string())
            .collect(),
        pre_steps: runtime.pre_steps.to_vec(),
        default_process: protocol.file.protocol.default_process,
        frame_gap_chars: runtime.frame_gap_chars,
        max_words_per_read: runtime.max_words_per_read,
        max_words_per_write: runtime.max_words_per_write,
        partial_blocks: runtime.partial_blocks,
        block: runtime.block.clone(),
        block_source: block_model(model, &protocol.id).map_or_else(String::new, |b| {
            let modes: Vec<&str> = b.modes.iter().map(|m| m.source.as_str()).collect();
            if modes.is_empty() {
                b.source.clone()
            } else {
                format!("{}; modes: {}", b.source, modes.join(", "))
            }
        }),
        block_note: block_model(model, &protocol.id)
            .map_or_else(String::new, |b| b.note.trim().to_owned()),
        timing: runtime.timing.clone(),
        before_start_stated: model
            .protocols
            .iter()
            .any(|p| p.id == protocol.id && p.before_start.is_some()),
        broadcast: runtime.broadcast.clone(),
        wire_numbers: runtime.wire_numbers.to_vec(),
        paging: runtime.paging.clone(),
        pages_doc: model
            .protocols
            .iter()
            .find(|p| p.id == protocol.id)
            .and_then(|p| p.pages.as_ref())
            .map(|pages| PagesDocIr {
                source: pages.source.clone(),
                range_names: pages.ranges.iter().map(|r| r.name.clone()).collect(),
                assumed: pages.assumed.clone(),
                note: pages.note.trim().to_owned(),
            }),
        persistence: runtime.persistence.clone(),
        error_table: if let Some(table) = own_table {
            ErrorTableIr::Protocol(ErrorCodesIr {
                source: table.source.clone(),
                protocols: vec![protocol.id.clone()],
                codes: lower_error_codes(&table.codes, table.notation.as_ref()),
                silent: Vec::new(),
            })
        } else if drive_table_applies(model, &protocol.id) {
            ErrorTableIr::Drive
        } else {
            ErrorTableIr::Protocol(protocol.file.error_codes.as_ref().map_or_else(
                || ErrorCodesIr {
                    source: String::new(),
                    protocols: vec![protocol.id.clone()],
                    codes: Vec::new(),
                    silent: Vec::new(),
                },
                |table| ErrorCodesIr {
                    source: table.source.clone(),
                    protocols: vec![protocol.id.clone()],
                    codes: lower_error_codes(&table.codes, table.notation.as_ref()),
                    silent: Vec::new(),
                },
            ))
        },
        variants: runtime.variants.clone(),
        unsupported_function: runtime.unsupported_function.and_then(|error_code| {
            let entry = model
                .protocols
                .iter()
                .find(|p| p.id == protocol.id)?
                .unsupported_function
                .as_ref()?;
            Some(UnsupportedFunctionIr {
                error_code,
                source: entry.source.clone(),
            })
        }),
    }
}
