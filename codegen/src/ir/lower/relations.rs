//! Lowers what relates registers to one another, each register named by its code: the
//! serial ports and their copies of registers, forbidden combinations of values and the
//! manual's formulas.

use super::code_of;
use crate::ir::types::*;
use crate::naming::const_name;
use crate::parse::model::{DriveFile, RegisterModel};
use crate::validate::ranges;
use vfd_runtime::units::Unit;

/// The register's copies on each port, when it is in a row of `ports.registers`.
pub(super) fn per_port(
    model: &DriveFile,
    index: &ranges::RegisterIndex<'_>,
    register: &RegisterModel,
) -> Vec<(String, String)> {
    let Some(ports) = &model.ports else {
        return Vec::new();
    };
    let row = ports.registers.iter().find(|row| {
        row.values()
            .any(|name| index.find(name).is_some_and(|r| r.id == register.id))
    });
    let Some(row) = row else {
        return Vec::new();
    };
    ports
        .list
        .iter()
        .filter_map(|port| {
            let name = row.get(&port.id)?;
            Some((port.id.clone(), code_of(index, name)))
        })
        .collect()
}

/// The ports, resolved to register codes.
pub(super) fn lower_ports(model: &DriveFile, index: &ranges::RegisterIndex<'_>) -> Option<PortsIr> {
    let ports = model.ports.as_ref()?;
    Some(PortsIr {
        source: ports.source.clone(),
        note: ports.note.trim().to_owned(),
        ports: ports
            .list
            .iter()
            .map(|port| PortIr {
                id: port.id.clone(),
                const_name: const_name(&port.id),
                name: port.name.clone(),
                name_zh: port.name_zh.clone(),
                settings: port
                    .settings
                    .iter()
                    .map(|(what, name)| (what.clone(), code_of(index, name)))
                    .collect(),
            })
            .collect(),
        shared: ports.shared.iter().map(|n| code_of(index, n)).collect(),
        registers: ports
            .registers
            .iter()
            .map(|row| {
                ports
                    .list
                    .iter()
                    .filter_map(|port| row.get(&port.id).map(|n| code_of(index, n)))
                    .collect()
            })
            .collect(),
    })
}

/// The forbidden combinations, each condition's register resolved to its code and its
/// values to raw words (validation has checked both).
pub(super) fn lower_forbidden(
    model: &DriveFile,
    index: &ranges::RegisterIndex<'_>,
) -> Vec<ForbiddenCombinationIr> {
    model
        .forbidden_combinations
        .iter()
        .map(|combination| ForbiddenCombinationIr {
            id: combination.id.clone(),
            rule: combination.rule.trim().to_owned(),
            meaning: combination.meaning.trim().to_owned(),
            source: combination.source.clone(),
            when: combination
                .when
                .iter()
                .filter_map(|condition| {
                    let register = index.find(&condition.register)?;
                    let scale = ranges::scale_of(register);
                    let raw = condition
                        .values
                        .iter()
                        .map(|v| (v / scale).round() as u32)
                        .collect();
                    Some((register.code.clone(), raw))
                })
                .collect(),
        })
        .collect()
}

/// The conversions, their formulas parsed (validation has checked they parse).
pub(super) fn lower_conversions(
    model: &DriveFile,
    index: &ranges::RegisterIndex<'_>,
) -> Vec<ConversionIr> {
    model
        .conversions
        .iter()
        .filter_map(|conversion| {
            let names: Vec<&str> = conversion.inputs.iter().map(|i| i.name.as_str()).collect();
            let program = crate::validate::formula::parse(&conversion.formula, &names).ok()?;
            Some(ConversionIr {
                id: conversion.id.clone(),
                name: conversion.name.clone(),
                source: conversion.source.clone(),
                formula: conversion.formula.clone(),
                program,
                inputs: conversion
                    .inputs
                    .iter()
                    .map(|input| ConversionInputIr {
                        name: input.name.clone(),
                        register: input.register.as_ref().map(|n| code_of(index, n)),
                        times: input.times.unwrap_or(1.0),
                        description: input.description.clone(),
                    })
                    .collect(),
                unit: conversion
                    .unit
                    .as_deref()
                    .and_then(Unit::from_symbol)
                    .unwrap_or(Unit::None),
                result: conversion.result.as_ref().map(|n| code_of(index, n)),
                truncate: conversion.rounding.is_some(),
                when: conversion.when.as_ref().map(|when| {
                    let value = match &when.value {
                        crate::parse::model::ConditionValueModel::Value(value) => Some(*value),
                        crate::parse::model::ConditionValueModel::Word(_) => None,
                    };
                    (code_of(index, &when.register), value)
                }),
                note: conversion.note.trim().to_owned(),
                examples: conversion
                    .examples
                    .iter()
                    .map(|example| {
                        let inputs = conversion
                            .inputs
                            .iter()
                            .map(|input| example.inputs.get(&input.name).copied().unwrap_or(0.0))
                            .collect();
                        (inputs, example.result, example.source.clone())
                    })
                    .collect(),
            })
        })
        .collect()
}
