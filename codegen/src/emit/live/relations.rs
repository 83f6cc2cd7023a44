//! Relations between registers as run-time values: the serial ports, the manual's
//! formulas and the forbidden combinations, as `emit/rust/relations.rs` writes them.

use super::{list, text, texts};
use crate::ir::{ConversionIr, ForbiddenCombinationIr, PortsIr};
use vfd_runtime::conversion::{Conversion, ConversionInput};
use vfd_runtime::{Condition, ForbiddenCombination, PortInfo, Ports};

/// The drive's serial ports.
pub(super) fn ports(ports: &PortsIr) -> Ports {
    Ports {
        ports: list(
            ports
                .ports
                .iter()
                .map(|port| PortInfo {
                    id: text(&port.id),
                    name: text(&port.name),
                    name_zh: text(&port.name_zh),
                    settings: list(
                        port.settings
                            .iter()
                            .map(|(what, code)| (text(what), text(code)))
                            .collect(),
                    ),
                })
                .collect(),
        ),
        shared: texts(&ports.shared),
        registers: list(ports.registers.iter().map(|row| texts(row)).collect()),
    }
}

/// One of the manual's formulas.
pub(super) fn conversion(conversion: &ConversionIr) -> Conversion {
    Conversion {
        id: text(&conversion.id),
        formula: text(&conversion.formula),
        inputs: list(
            conversion
                .inputs
                .iter()
                .map(|input| ConversionInput {
                    name: text(&input.name),
                    register: input.register.as_deref().map(text),
                    times: input.times,
                })
                .collect(),
        ),
        program: list(conversion.program.clone()),
        truncate: conversion.truncate,
        result: conversion.result.as_deref().map(text),
        when: conversion
            .when
            .as_ref()
            .map(|(code, value)| (text(code), *value)),
    }
}

/// One forbidden combination.
pub(super) fn forbidden(combination: &ForbiddenCombinationIr) -> ForbiddenCombination {
    ForbiddenCombination {
        id: text(&combination.id),
        rule: text(&combination.rule),
        meaning: text(&combination.meaning),
        source: text(&combination.source),
        when: list(
            combination
                .when
                .iter()
                .map(|(register, raw)| Condition {
                    register: text(register),
                    raw: list(raw.clone()),
                })
                .collect(),
        ),
    }
}
