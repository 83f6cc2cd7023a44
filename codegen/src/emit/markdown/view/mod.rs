//! The page view: the IR plus the words the templates print. Each view wraps its IR item
//! (flattened, so the template reads `r.code` and `r.range_display` alike) and adds only
//! text built for people.
//!
//! [`DriveView`] puts the page together here; each part of the page has a module of its
//! own: `serial.rs` (serial settings and ports), `protocol.rs` and `link_rules.rs` (each
//! protocol, its commands, layouts and line rules), `error_codes.rs`, `registers.rs`,
//! `bitfields.rs`, `code_tables.rs`, `scaling.rs`, `conversions.rs`, `virtual_drive.rs`,
//! `examples.rs` and `sequences.rs`.

mod bitfields;
mod code_tables;
mod conversions;
mod error_codes;
mod examples;
mod link_rules;
mod protocol;
mod registers;
mod scaling;
mod sequences;
mod serial;
mod virtual_drive;

use crate::emit::words::{address_label, warning_text};
use crate::ir::*;
use bitfields::{bitfield_views, BitfieldView};
use code_tables::{code_table_views, CodeTableView};
use conversions::{conversion_views, ConversionView};
use error_codes::{
    error_code_digits, error_codes_view, protocol_error_tables, ErrorCodesView, ProtocolErrorsView,
};
use examples::{example_views, value_example_views, ExampleView, ValueExampleView};
use protocol::{protocol_view, ProtocolView};
use registers::{held_pairs, register_views, HeldPairView, RegisterView};
use scaling::{reference_scaling_view, ScalingView};
use sequences::{sequence_view, SequenceView};
use serde::Serialize;
use serial::{line_formats, ports_view, serial_view, PortsView, SerialView};
use virtual_drive::{virtual_drive_view, VirtualDriveView};

#[derive(Serialize)]
pub(super) struct DriveView<'a> {
    #[serde(flatten)]
    drive: &'a DriveIr,
    serial: SerialView<'a>,
    protocols: Vec<ProtocolView<'a>>,
    error_codes: ErrorCodesView<'a>,
    /// The protocols the drive's table does not apply to, with the tables they use.
    protocol_error_tables: Vec<ProtocolErrorsView<'a>>,
    registers: Vec<RegisterView<'a>>,
    bitfields: Vec<BitfieldView<'a>>,
    code_tables: Vec<CodeTableView<'a>>,
    reference_scaling: Option<ScalingView<'a>>,
    value_examples: Vec<ValueExampleView<'a>>,
    examples: Vec<ExampleView<'a>>,
    /// The multi-step examples, each with its frames shown.
    sequences: Vec<SequenceView<'a>>,
    /// The drive's warnings, then each register's, as sentences.
    warning_lines: Vec<WarningView>,
    /// The serial ports, when the drive has several.
    ports: Option<PortsView<'a>>,
    /// Live registers and the registers holding their value at a trip.
    held_pairs: Vec<HeldPairView>,
    /// The manual's formulas.
    conversions: Vec<ConversionView<'a>>,
    /// What the virtual drive does and assumes.
    virtual_drive: VirtualDriveView<'a>,
    /// The registers other registers' ranges name (`FH`, `UL`), each once.
    bound_registers: Vec<String>,
    /// Some register has a fact the description infers.
    any_inferred: bool,
    /// The character format per protocol, where the drive's code tables say which format
    /// a protocol speaks; empty when the table's one format holds for every protocol.
    line_formats: Vec<(String, String)>,
    /// The code of the register holding the station number, when the description names one.
    station_register: Option<String>,
}

#[derive(Serialize)]
struct WarningView {
    /// What it is about: empty for the drive, else the register's code.
    subject: String,
    text: String,
}

impl<'a> DriveView<'a> {
    pub(super) fn new(drive: &'a DriveIr) -> Self {
        DriveView {
            drive,
            serial: serial_view(drive),
            virtual_drive: virtual_drive_view(drive),
            bound_registers: {
                let mut codes: Vec<String> = Vec::new();
                for r in &drive.registers {
                    for bound in [&r.min, &r.max].into_iter().flatten() {
                        if let Some(code) = &bound.register {
                            if !codes.contains(code) {
                                codes.push(code.clone());
                            }
                        }
                    }
                }
                codes
            },
            any_inferred: drive.registers.iter().any(|r| !r.inferred.is_empty()),
            line_formats: line_formats(drive),
            station_register: drive
                .addressing
                .register
                .as_deref()
                .and_then(|id| drive.register(id))
                .map(|r| r.code.clone()),
            warning_lines: drive
                .warnings
                .iter()
                .map(|w| (String::new(), w))
                .chain(drive.registers.iter().flat_map(|r| {
                    r.warnings.iter().map(move |w| {
                        let label = address_label(r);
                        let subject = if label == r.code {
                            r.code.clone()
                        } else {
                            format!("{} ({label})", r.code)
                        };
                        (subject, w)
                    })
                }))
                .map(|(subject, warning)| WarningView {
                    subject,
                    text: warning_text(warning),
                })
                .collect(),
            protocols: drive
                .protocols
                .iter()
                .map(|p| protocol_view(drive, p))
                .collect(),
            error_codes: error_codes_view(
                &drive.error_codes,
                drive
                    .protocols
                    .iter()
                    .filter(|p| drive.error_codes.protocols.contains(&p.id))
                    .map(|p| error_code_digits(drive, p))
                    .max()
                    .unwrap_or(4),
            ),
            protocol_error_tables: protocol_error_tables(drive),
            registers: register_views(drive),
            bitfields: bitfield_views(drive),
            code_tables: code_table_views(drive),
            reference_scaling: reference_scaling_view(drive),
            value_examples: value_example_views(drive),
            ports: ports_view(drive),
            held_pairs: held_pairs(drive),
            conversions: conversion_views(drive),
            sequences: drive
                .sequences
                .iter()
                .map(|sequence| sequence_view(drive, sequence))
                .collect(),
            examples: example_views(drive),
        }
    }
}

/// A number without float noise (`4`, `6000`, `0.5`).
fn trimmed(value: f64) -> String {
    let text = format!("{value:.6}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}
