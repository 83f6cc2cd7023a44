//! The serial settings and ports: character time, line facts, assumed timings, the
//! character format each protocol speaks, and the ports' setting registers and copies.

use crate::emit::words::{bit_order_text, duplex_text, synchronisation_text, topology_text};
use crate::ir::*;
use serde::Serialize;
use vfd_runtime::serial::SerialSettings;

#[derive(Serialize)]
pub(super) struct PortsView<'a> {
    #[serde(flatten)]
    ports: &'a PortsIr,
    /// The settings' names (the columns of the ports table).
    setting_names: Vec<&'a str>,
    /// Per port: its id, names and the register setting each named setting.
    rows: Vec<(String, String, String, Vec<String>)>,
    /// Per-port register groups: (name of the first copy, the copies in port order).
    pairs: Vec<(String, Vec<String>)>,
}

#[derive(Serialize)]
pub(super) struct SerialView<'a> {
    #[serde(flatten)]
    serial: &'a SerialIr,
    /// Character time at the default settings, in microseconds.
    char_time_us: u128,
    /// Line facts as (setting, value) rows.
    line_rows: Vec<(&'static str, &'static str)>,
    /// Which timings are assumed, by their key.
    assumed: Vec<&'static str>,
}

/// The character format each protocol speaks, from the code tables whose values choose a
/// protocol and set the line, with the format of the selecting register's factory value;
/// empty when no code table says.
pub(super) fn line_formats(drive: &DriveIr) -> Vec<(String, String)> {
    let format = |(data_bits, parity, stop_bits): (u8, vfd_runtime::serial::Parity, u8)| {
        let parity = match parity {
            vfd_runtime::serial::Parity::None => 'N',
            vfd_runtime::serial::Parity::Even => 'E',
            vfd_runtime::serial::Parity::Odd => 'O',
        };
        format!("{data_bits}{parity}{stop_bits}")
    };
    let mut rows = Vec::new();
    for protocol in &drive.protocols {
        for table in &drive.code_tables {
            let values: Vec<&CodeValueIr> = table
                .values
                .iter()
                .filter(|v| {
                    v.line.is_some_and(|l| l.format().is_some())
                        && v.protocol.as_deref() == Some(&protocol.id)
                })
                .collect();
            if values.is_empty() {
                continue;
            }
            let Some(selector) = drive
                .registers
                .iter()
                .find(|r| r.code_table.as_deref() == Some(&table.id))
            else {
                continue;
            };
            let factory = selector.default.map(|d| d as u16);
            let choices: Vec<String> = values
                .iter()
                .filter_map(|v| {
                    let line = format(v.line?.format()?);
                    Some(if Some(v.value) == factory {
                        format!(
                            "**{line}** ({} = {}, the factory setting)",
                            selector.code, v.value
                        )
                    } else {
                        format!("{line} ({} = {})", selector.code, v.value)
                    })
                })
                .collect();
            let mut row = choices.join(", ");
            if let Some(line) = drive
                .serial
                .protocol_lines
                .iter()
                .find(|l| l.protocol == protocol.id)
                .filter(|_| {
                    !drive
                        .serial
                        .protocol_lines
                        .iter()
                        .any(|l| l.protocol == protocol.id && l.factory)
                })
            {
                row.push_str(&format!(
                    "; the factory setting chooses another protocol: a master starts from {} ({} = {}, the first offered; assumed)",
                    format((line.data_bits, line.parity, line.stop_bits)),
                    line.selector,
                    line.value
                ));
            }
            rows.push((protocol.id.clone(), row));
        }
    }
    rows
}

/// A register's name without the port it names at its end (`Command word 1 (2-wire
/// RS-485)` → `Command word 1`), for the table of per-port copies.
fn without_port(name: &str, ports: &PortsIr) -> String {
    ports
        .ports
        .iter()
        .find_map(|port| name.strip_suffix(&format!(" ({})", port.name)))
        .unwrap_or(name)
        .to_owned()
}

/// The serial settings: character time, line facts and assumed timings.
pub(super) fn serial_view(drive: &DriveIr) -> SerialView<'_> {
    SerialView {
        serial: &drive.serial,
        char_time_us: SerialSettings {
            baud: drive.serial.default_baud,
            data_bits: drive.serial.default_data_bits,
            parity: drive.serial.default_parity,
            stop_bits: drive.serial.default_stop_bits,
        }
        .char_time()
        .as_micros(),
        line_rows: drive.serial.line.as_ref().map_or_else(Vec::new, |line| {
            let mut rows = Vec::new();
            if let Some(duplex) = line.duplex {
                rows.push(("Transmission", duplex_text(duplex)));
            }
            if let Some(topology) = line.topology {
                rows.push(("Line control", topology_text(topology)));
            }
            if let Some(sync) = line.synchronisation {
                rows.push(("Synchronisation", synchronisation_text(sync)));
            }
            if let Some(order) = line.bit_order {
                rows.push(("Bit order", bit_order_text(order)));
            }
            rows
        }),
        assumed: drive
            .serial
            .assumed_timing
            .iter()
            .map(|field| match field {
                TimingField::StartupDelayMs => "startup_delay_ms",
                TimingField::FrameAbandonMs => "frame_abandon_ms",
                TimingField::ProcessingAllowanceMs => "processing_allowance_ms",
            })
            .collect(),
    }
}

/// The serial ports' table and per-port copies, when the drive has several ports.
pub(super) fn ports_view(drive: &DriveIr) -> Option<PortsView<'_>> {
    drive.ports.as_ref().map(|ports| {
        let setting_names: Vec<&str> = ports
            .ports
            .first()
            .map(|p| p.settings.iter().map(|(name, _)| name.as_str()).collect())
            .unwrap_or_default();
        PortsView {
            ports,
            rows: ports
                .ports
                .iter()
                .map(|port| {
                    (
                        port.id.clone(),
                        port.name.clone(),
                        port.name_zh.clone(),
                        setting_names
                            .iter()
                            .map(|name| {
                                port.settings
                                    .iter()
                                    .find(|(n, _)| n == name)
                                    .map_or_else(|| "—".to_owned(), |(_, code)| code.clone())
                            })
                            .collect(),
                    )
                })
                .collect(),
            setting_names,
            pairs: ports
                .registers
                .iter()
                .map(|row| {
                    let name = row
                        .first()
                        .and_then(|code| drive.registers.iter().find(|r| &r.code == code))
                        .map_or_else(String::new, |r| without_port(&r.name, ports));
                    (name, row.clone())
                })
                .collect(),
        }
    })
}
