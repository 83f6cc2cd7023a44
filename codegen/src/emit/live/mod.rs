//! The drive as run-time values: the same `vfd_runtime::DriveInfo` the generated Rust
//! holds as statics, built from the IR while a program runs, for tools that load a
//! description file when they start (`vfd --drive ./my_drive.yaml`).
//!
//! Each value mirrors what the Rust emitter (`emit/rust/`) writes for it, field for field;
//! `tests/tests/one_truth.rs` compares the two for every drive file of the repository, so
//! neither can drift. The runtime's types hold `&'static` references, so the values are
//! leaked: build a drive once per process.

mod behaviour;
mod protocols;
mod registers;
mod relations;

use crate::ir::DriveIr;
use vfd_runtime::serial::{DriveTiming, ProtocolLine, SerialSettings, SerialSpec};
use vfd_runtime::DriveInfo;

/// The drive of `ir` as the runtime's data, as the generated module's `DRIVE` static holds
/// it. Its memory lives until the process ends.
pub fn drive_info(ir: &DriveIr) -> &'static DriveInfo {
    let registers = registers::registers(ir);
    leak(DriveInfo {
        id: text(&ir.id),
        vendor: text(&ir.vendor),
        model: text(&ir.model),
        name: text(&ir.name),
        name_zh: text(&ir.name_zh),
        manual: text(&ir.manual),
        manual_title: text(&ir.manual_named()),
        serial: leak(serial(ir)),
        protocols: list(
            ir.protocols
                .iter()
                .map(|p| leak(protocols::protocol(ir, p)))
                .collect(),
        ),
        registers,
        behaviour: ir.behaviour.as_ref().map(|b| leak(behaviour::behaviour(b))),
        ports: ir.ports.as_ref().map(|p| leak(relations::ports(p))),
        conversions: list(ir.conversions.iter().map(relations::conversion).collect()),
        forbidden: list(
            ir.forbidden_combinations
                .iter()
                .map(relations::forbidden)
                .collect(),
        ),
        station_register: ir.addressing.register.as_deref().map(text),
    })
}

/// The serial settings, as the generated `SERIAL` const holds them.
fn serial(ir: &DriveIr) -> SerialSpec {
    let serial = &ir.serial;
    SerialSpec {
        baud_rates: list(serial.baud_rates.clone()),
        parities: list(serial.parities.clone()),
        default: SerialSettings {
            baud: serial.default_baud,
            data_bits: serial.default_data_bits,
            parity: serial.default_parity,
            stop_bits: serial.default_stop_bits,
        },
        data_bits: list(serial.data_bits.clone()),
        protocol_lines: list(
            serial
                .protocol_lines
                .iter()
                .map(|line| ProtocolLine {
                    protocol: text(&line.protocol),
                    data_bits: line.data_bits,
                    parity: line.parity,
                    stop_bits: line.stop_bits,
                    factory: line.factory,
                })
                .collect(),
        ),
        stop_bits_sent: serial.stop_bits_sent,
        stop_bits_received: serial.stop_bits_received,
        stop_bits: list(serial.stop_bits.clone()),
        timing: DriveTiming {
            startup_delay: std::time::Duration::from_millis(serial.startup_delay_ms),
            processing_allowance: std::time::Duration::from_millis(serial.processing_allowance_ms),
            frame_abandon: std::time::Duration::from_millis(serial.frame_abandon_ms),
        },
    }
}

/// `value` for the rest of the process.
fn leak<T>(value: T) -> &'static T {
    Box::leak(Box::new(value))
}

/// `text` for the rest of the process.
fn text(text: &str) -> &'static str {
    Box::leak(text.to_owned().into_boxed_str())
}

/// `items` for the rest of the process.
fn list<T>(items: Vec<T>) -> &'static [T] {
    Box::leak(items.into_boxed_slice())
}

/// Each of `items` for the rest of the process.
fn texts(items: &[String]) -> &'static [&'static str] {
    list(items.iter().map(|s| text(s)).collect())
}
