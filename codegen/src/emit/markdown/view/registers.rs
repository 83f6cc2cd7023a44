//! The registers table and the registers held at a trip.

use super::code_tables::code_table_link;
use crate::emit::words::{address_label, default_text, inferred_text, range_text, value_type_text};
use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct HeldPairView {
    live: String,
    held: String,
    name: String,
    /// The held register keeps its value only while tripped (no live partner).
    live_except_while_tripped: bool,
}

#[derive(Serialize)]
pub(super) struct RegisterView<'a> {
    #[serde(flatten)]
    register: &'a RegisterIr,
    address_display: String,
    address_hex: String,
    scale_display: String,
    range_display: String,
    default_display: String,
    value_type_display: String,
    /// The inferred facts in words, empty when there are none.
    inferred_display: String,
    /// Its relations to other registers (held copy, scale selector, port copies), as
    /// sentences; empty when there are none.
    relations_display: String,
    /// The typed API's aliases of its type (`registers::P195`).
    alias_types: Vec<String>,
}

/// Every register, with its address, range, default, type and relations in words.
pub(super) fn register_views(drive: &DriveIr) -> Vec<RegisterView<'_>> {
    drive
        .registers
        .iter()
        .map(|register| RegisterView {
            register,
            address_display: if register.wire_only {
                "none: wire numbers only".to_owned()
            } else {
                let mut label = address_label(register);
                for (protocol, page, offset) in &register.on_page {
                    label.push_str(&format!(", {protocol} page {page} offset {offset:02X}h"));
                }
                label
            },
            address_hex: format!("{:04X}", register.address),
            scale_display: format!("{}", register.scale),
            range_display: match code_table_link(drive, register.code_table.as_deref()) {
                Some(link) => format!("codes: {link}"),
                None => range_text(register),
            },
            default_display: default_text(register),
            value_type_display: format!("`{}`", value_type_text(register)),
            inferred_display: inferred_text(&register.inferred),
            relations_display: crate::emit::rust::relation_lines(register).join(" "),
            alias_types: register
                .aliases
                .iter()
                .filter_map(|alias| crate::naming::alias_type_name(alias))
                .map(|name| format!("registers::{name}"))
                .collect(),
        })
        .collect()
}

/// Live registers and the registers holding their value at a trip.
pub(super) fn held_pairs(drive: &DriveIr) -> Vec<HeldPairView> {
    drive
        .registers
        .iter()
        .filter_map(|r| {
            if let Some(live) = &r.held_at_trip_of {
                Some(HeldPairView {
                    live: live.clone(),
                    held: r.code.clone(),
                    name: r.name.clone(),
                    live_except_while_tripped: false,
                })
            } else if r.live_except_while_tripped {
                Some(HeldPairView {
                    live: r.code.clone(),
                    held: r.code.clone(),
                    name: r.name.clone(),
                    live_except_while_tripped: true,
                })
            } else {
                None
            }
        })
        .collect()
}
