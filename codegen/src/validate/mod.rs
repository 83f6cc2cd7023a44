//! Stage 4: checks a described drive and reports every problem at once.
//!
//! Each check is a pass in its own file, over the [`Context`] (the parsed drive, its
//! lowered protocols and its decoded example frames); [`check`] runs them all in order.
//! Nothing is generated from a description that has problems.

pub(crate) mod ranges;

mod bit_examples_match;
mod bit_fields_do_not_overlap;
mod code_values_are_unique;
mod defaults_are_in_range;
mod examples_decode;
mod identifiers_are_snake_case;
mod names_are_unique;
mod ranges_resolve;
mod reference_scaling_resolves;
mod references_resolve;
mod register_addresses_are_unique;
mod scales_are_positive;
mod serial_settings_are_consistent;
mod units_are_known;
mod value_examples_match;

use crate::diagnostics::Diagnostics;
use crate::frames::DecodedExample;
use crate::parse::model::{DriveFile, RegisterModel};
use crate::parse::SourceFile;
use crate::protocols::LoweredProtocol;

/// Everything the checks and the IR look at: the parsed drive, its lowered protocols and
/// its example frames, decoded once.
#[derive(Debug, Clone)]
pub(crate) struct Context {
    /// The drive file.
    pub source: SourceFile,
    /// Its parsed content.
    pub model: DriveFile,
    /// Its protocols, lowered (those with problems are left out).
    pub protocols: Vec<LoweredProtocol>,
    /// Its examples' frames, decoded, in example order.
    pub frames: Vec<DecodedExample>,
}

/// Runs every check, in a fixed order.
pub(crate) fn check(drive: &Context, out: &mut Diagnostics) {
    let checks: [fn(&Context, &mut Diagnostics); 15] = [
        identifiers_are_snake_case::identifiers_are_snake_case,
        register_addresses_are_unique::register_addresses_are_unique,
        names_are_unique::names_are_unique,
        units_are_known::units_are_known,
        scales_are_positive::scales_are_positive,
        ranges_resolve::ranges_resolve,
        defaults_are_in_range::defaults_are_in_range,
        references_resolve::references_resolve,
        bit_fields_do_not_overlap::bit_fields_do_not_overlap,
        code_values_are_unique::code_values_are_unique,
        serial_settings_are_consistent::serial_settings_are_consistent,
        examples_decode::examples_decode,
        value_examples_match::value_examples_match,
        bit_examples_match::bit_examples_match,
        reference_scaling_resolves::reference_scaling_resolves,
    ];
    for check in checks {
        check(drive, out);
    }
}

/// Decimal places a scale implies (0.01 -> 2).
pub(crate) fn decimals(scale: f64) -> usize {
    usize::from(vfd_runtime::units::decimals_of(scale))
}

/// `12.50 Hz` for a raw count of a register, without float noise.
pub(crate) fn show_raw(register: &RegisterModel, raw: i64) -> String {
    let scale = ranges::scale_of(register);
    with_unit(
        register,
        format!("{:.*}", decimals(scale), raw as f64 * scale),
    )
}

pub(crate) fn with_unit(register: &RegisterModel, number: String) -> String {
    match register.unit.as_deref() {
        Some(unit) if !unit.is_empty() => format!("{number} {unit}"),
        _ => number,
    }
}

/// Parses `bit: N` or `bits: "msb:lsb"` into (lsb, width).
pub(crate) fn bit_span(bit: Option<u8>, bits: Option<&str>) -> Result<(u8, u8), String> {
    match (bit, bits) {
        (Some(bit), None) if bit < 16 => Ok((bit, 1)),
        (Some(bit), None) => Err(format!("bit {bit} is outside a 16-bit word")),
        (None, Some(text)) => {
            let (msb, lsb) = text
                .split_once(':')
                .ok_or_else(|| format!("`bits: {text}` is not \"msb:lsb\""))?;
            let msb: u8 = msb
                .trim()
                .parse()
                .map_err(|_| format!("`{msb}` is not a bit number"))?;
            let lsb: u8 = lsb
                .trim()
                .parse()
                .map_err(|_| format!("`{lsb}` is not a bit number"))?;
            if msb < lsb || msb > 15 {
                return Err(format!("`bits: {text}` needs 15 >= msb >= lsb"));
            }
            Ok((lsb, msb - lsb + 1))
        }
        _ => Err("give exactly one of `bit` and `bits`".to_owned()),
    }
}
