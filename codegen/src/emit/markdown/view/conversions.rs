//! The manual's formulas: inputs, when each applies, and the worked examples.

use super::trimmed;
use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct ConversionView<'a> {
    #[serde(flatten)]
    conversion: &'a ConversionIr,
    inputs_display: String,
    when_display: String,
    examples_display: String,
}

/// The manual's formulas, with inputs, condition and worked examples in words.
pub(super) fn conversion_views(drive: &DriveIr) -> Vec<ConversionView<'_>> {
    drive
        .conversions
        .iter()
        .map(|conversion| ConversionView {
            conversion,
            inputs_display: conversion
                .inputs
                .iter()
                .map(|input| match &input.register {
                    Some(code) if (input.times - 1.0).abs() > f64::EPSILON => {
                        format!("`{}` = {} × {code}", input.name, input.times)
                    }
                    Some(code) => format!("`{}` = {code}", input.name),
                    None => format!("`{}`: {}", input.name, input.description),
                })
                .collect::<Vec<_>>()
                .join("; "),
            when_display: match &conversion.when {
                Some((code, Some(value))) => format!("{code} = {value}"),
                Some((code, None)) => format!("{code} ≠ 0"),
                None => "always".to_owned(),
            },
            examples_display: conversion
                .examples
                .iter()
                .map(|(inputs, result, source)| {
                    // An input read from a register is given as the register's
                    // value; scaled first, the formula's own input follows, so
                    // the example computes as written.
                    let args: Vec<String> = conversion
                        .inputs
                        .iter()
                        .zip(inputs)
                        .map(|(input, value)| match &input.register {
                            Some(code) if (input.times - 1.0).abs() > f64::EPSILON => {
                                format!(
                                    "{code} = {value}, so `{}` = {}",
                                    input.name,
                                    trimmed(value * input.times)
                                )
                            }
                            Some(code) => format!("{code} = {value}"),
                            None => format!("`{}` = {value}", input.name),
                        })
                        .collect();
                    format!("{} → {result} ({source})", args.join(", "))
                })
                .collect::<Vec<_>>()
                .join("; "),
        })
        .collect()
}
