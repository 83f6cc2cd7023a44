//! Stage 4: checks a described drive and reports every problem at once.
//!
//! Each check is a pass in its own file, over the [`Context`] (the parsed drive, its
//! lowered protocols and its decoded example frames); [`check`] runs them all in order.
//! Nothing is generated from a description that has problems. [`warn`] then runs the
//! warnings, one file each too: things that are valid but do not do what they seem to.

pub(crate) mod formula;
pub(crate) mod ranges;

mod behaviour_resolves;
mod bit_examples_match;
mod bit_fields_do_not_overlap;
mod bit_fields_fit_their_registers;
mod byte_registers_have_commands;
mod code_values_are_unique;
mod defaults_are_in_range;
mod example_values;
mod examples_decode;
mod examples_re_encode;
mod identifiers_are_snake_case;
mod inferred_facts_exist;
mod line_formats_resolve;
mod names_are_unique;
mod paged_examples_name_their_place;
mod ranges_resolve;
mod reference_scaling_resolves;
mod references_resolve;
mod refusal_codes_resolve;
mod register_addresses_are_unique;
mod relations_resolve;
mod replies_answer_requests;
mod rust_names_are_unique;
mod scales_are_positive;
mod sequences_replay;
mod sequences_resolve;
mod serial_settings_are_consistent;
mod silent_requests_have_no_reply;
mod station_register_resolves;
mod storage_rules_are_consistent;
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
    let checks: [fn(&Context, &mut Diagnostics); 31] = [
        identifiers_are_snake_case::identifiers_are_snake_case,
        register_addresses_are_unique::register_addresses_are_unique,
        names_are_unique::names_are_unique,
        rust_names_are_unique::rust_names_are_unique,
        units_are_known::units_are_known,
        scales_are_positive::scales_are_positive,
        inferred_facts_exist::inferred_facts_exist,
        ranges_resolve::ranges_resolve,
        defaults_are_in_range::defaults_are_in_range,
        references_resolve::references_resolve,
        bit_fields_do_not_overlap::bit_fields_do_not_overlap,
        bit_fields_fit_their_registers::bit_fields_fit_their_registers,
        code_values_are_unique::code_values_are_unique,
        serial_settings_are_consistent::serial_settings_are_consistent,
        station_register_resolves::station_register_resolves,
        examples_decode::examples_decode,
        paged_examples_name_their_place::paged_examples_name_their_place,
        replies_answer_requests::replies_answer_requests,
        silent_requests_have_no_reply::silent_requests_have_no_reply,
        examples_re_encode::examples_re_encode,
        value_examples_match::value_examples_match,
        bit_examples_match::bit_examples_match,
        reference_scaling_resolves::reference_scaling_resolves,
        behaviour_resolves::behaviour_resolves,
        refusal_codes_resolve::refusal_codes_resolve,
        relations_resolve::relations_resolve,
        sequences_resolve::sequences_resolve,
        sequences_replay::sequences_replay,
        line_formats_resolve::line_formats_resolve,
        storage_rules_are_consistent::storage_rules_are_consistent,
        byte_registers_have_commands::byte_registers_have_commands,
    ];
    for check in checks {
        check(drive, out);
    }
}

/// Declares the warning checks, one file each named after its function, and [`warn`],
/// which runs them in the order listed. Adding a warning: a file in `validate/` whose
/// `pub fn <file name>(&Context, &mut Diagnostics)` pushes `source.warning(..)`
/// diagnostics, and its name in this list.
macro_rules! warnings {
    ($($check:ident),* $(,)?) => {
        $(mod $check;)*

        /// Runs every warning check, in a fixed order.
        pub(crate) fn warn(drive: &Context, out: &mut Diagnostics) {
            $($check::$check(drive, out);)*
        }
    };
}

warnings! {
    behaviour_is_described,
    examples_are_accepted,
    settings_change_something,
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

/// Test helpers: a small valid drive, and one check run over in-memory YAML.
#[cfg(test)]
pub(crate) mod testing {
    use super::Context;
    use crate::diagnostics::{Diagnostic, Diagnostics};
    use crate::parse::SourceFile;
    use std::path::Path;

    /// The file name diagnostics of in-memory test drives carry.
    pub(crate) const FILE: &str = "test.yaml";

    /// A small drive every check accepts: three ranged registers (one bounded by another),
    /// a code-table register, a bit-field register, one protocol and one example.
    pub(crate) const VALID: &str = r#"drive:
  id: test_drive
  vendor: Test
  model: T1
  name: Test drive
  manual: none.txt

serial:
  source: "2"
  baud_rates: [4800, 9600]
  parities: [even, odd]
  data_bits: 8
  stop_bits_sent: 1
  stop_bits_received: 1
  default: { baud: 9600, parity: even, data_bits: 8, stop_bits: 1 }
  timing:
    startup_delay_ms: 1000
    frame_abandon_ms: 1000
    processing_allowance_ms: 500

addressing:
  min: 0
  max: 31

protocols:
  - { id: ascii, uses: toshiba-ascii, source: "4.1" }

error_codes:
  source: "3.2"
  codes:
    - { code: 0x0000, id: cannot_execute, name: Cannot execute, meaning: Not now. }
    - { code: 0x0001, id: data_error, name: Data error, meaning: Out of range. }

codes:
  - id: parity
    name: Parity
    source: "6"
    values:
      - { value: 0, id: no_parity, name: No parity }
      - { value: 1, id: even_parity, name: Even parity }

bitfields:
  - id: command_word
    name: Command word
    source: "7.1"
    fields:
      - { bit: 15, id: command_enabled, name: Command enabled }
      - { bits: "14:11", reserved: true }
      - { bit: 10, id: run, name: Run }
      - { bits: "9:0", reserved: true }
    examples:
      - { value: 0x8400, set: [command_enabled, run], description: Forward run, source: "7.1" }

registers:
  - { address: 0x0009, id: acceleration_time, code: Acc, name: Acceleration time, unit: s, scale: 0.1, range: { min: 0.1, max: 3600 }, default: 10.0, source: "11.1" }
  - { address: 0x0011, id: maximum_frequency, code: FH, name: Maximum frequency, unit: Hz, scale: 0.01, range: { min: 30.0, max: 320.0 }, default: 80.0, source: "11.1" }
  - { address: 0x0012, id: upper_limit_frequency, code: UL, name: Upper limit, unit: Hz, scale: 0.01, range: { min: 0.5, max: FH }, default: 80.0, source: "11.1" }
  - { address: 0x0600, id: parity_setting, code: F601, name: Parity, code_table: parity, default: 1, source: "6" }
  - { address: 0xFA00, id: command, code: FA00, name: Command, bitfield: command_word, ram_only: true, source: "7.1" }

value_examples:
  - { register: FH, value: 80.0, raw: 0x1F40, source: "11.1", description: 80 Hz }

examples:
  - id: read_maximum_frequency
    protocol: ascii
    source: "5.1"
    description: Read the maximum frequency.
    request: { ascii: "(R0011)\r", expect: { command: R, register: 0x0011 } }
    reply: { ascii: "(R00111F40)\r", expect: { command: R, register: 0x0011, data: 0x1F40 } }
    value: 80.0
"#;

    /// [`VALID`] with each `(from, to)` applied; each `from` must occur exactly once.
    pub(crate) fn valid_with(edits: &[(&str, &str)]) -> String {
        let mut yaml = VALID.to_owned();
        for (from, to) in edits {
            assert_eq!(
                yaml.matches(from).count(),
                1,
                "`{from}` must occur exactly once in the test drive"
            );
            yaml = yaml.replacen(from, to, 1);
        }
        yaml
    }

    /// The 1-based line of the only line of `yaml` containing `needle`.
    pub(crate) fn line_of(yaml: &str, needle: &str) -> usize {
        let lines: Vec<usize> = yaml
            .lines()
            .enumerate()
            .filter(|(_, line)| line.contains(needle))
            .map(|(index, _)| index + 1)
            .collect();
        assert_eq!(lines.len(), 1, "`{needle}` must be on exactly one line");
        lines[0]
    }

    /// Builds the [`Context`] the checks see, running the stages `compile_source` runs
    /// before validation. Panics when those stages already find problems: a test drive
    /// must reach validation.
    pub(crate) fn context(yaml: &str) -> Context {
        let protocols_dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../drives/protocols"));
        let source = SourceFile::from_text(Path::new(FILE), yaml.to_owned());
        let mut earlier = Diagnostics::default();
        let drive = crate::load::load(source, Some(protocols_dir), &[], &mut earlier);
        let Some(drive) = drive else {
            panic!("the test drive does not parse:\n{earlier}");
        };
        let protocols = crate::protocols::lower(&drive, &mut earlier);
        assert!(
            earlier.is_empty(),
            "the test drive has problems before validation:\n{earlier}"
        );
        let frames = crate::frames::decode_examples(&drive.model, &protocols);
        Context {
            source: drive.source,
            model: drive.model,
            protocols,
            frames,
        }
    }

    /// Runs one check over `yaml` and returns what it reports.
    pub(crate) fn check_yaml(check: fn(&Context, &mut Diagnostics), yaml: &str) -> Vec<Diagnostic> {
        let mut out = Diagnostics::default();
        check(&context(yaml), &mut out);
        out.items
    }

    /// The only diagnostic; panics showing all of them otherwise.
    #[track_caller]
    pub(crate) fn only(diagnostics: &[Diagnostic]) -> &Diagnostic {
        assert_eq!(
            diagnostics.len(),
            1,
            "expected one diagnostic, got {diagnostics:#?}"
        );
        &diagnostics[0]
    }

    /// Asserts a diagnostic's path and message, and that it points at the line of `yaml`
    /// containing `line_needle`.
    #[track_caller]
    pub(crate) fn assert_at(
        diagnostic: &Diagnostic,
        yaml: &str,
        path: &str,
        message: &str,
        line_needle: &str,
    ) {
        assert_eq!(diagnostic.message, message);
        assert_eq!(diagnostic.path, path);
        assert_eq!(diagnostic.file, Path::new(FILE));
        assert_eq!(
            diagnostic.position.line,
            line_of(yaml, line_needle),
            "line of {path}"
        );
        assert!(diagnostic.hint.is_some(), "every diagnostic has a hint");
    }

    /// Asserts that a diagnostic's column is where `text` starts on its line.
    #[track_caller]
    pub(crate) fn assert_column(diagnostic: &Diagnostic, yaml: &str, text: &str) {
        let line = yaml
            .lines()
            .nth(diagnostic.position.line - 1)
            .unwrap_or_default();
        let column = line
            .find(text)
            .unwrap_or_else(|| panic!("`{text}` is not on line {line:?}"));
        assert_eq!(diagnostic.position.column, column + 1, "column of `{text}`");
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{context, VALID};
    use super::*;

    #[test]
    fn every_check_accepts_the_test_drive() {
        let mut out = Diagnostics::default();
        check(&context(VALID), &mut out);
        assert!(out.is_empty(), "{out}");
    }

    #[test]
    fn the_test_drive_compiles() {
        let compiled = crate::compile_text(
            std::path::Path::new(testing::FILE),
            VALID.to_owned(),
            Some(std::path::Path::new(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../drives/protocols"
            ))),
        );
        assert!(compiled.is_ok(), "{}", compiled.unwrap_err());
    }

    #[test]
    fn bit_span_reads_one_bit_and_ranges() {
        assert_eq!(bit_span(Some(15), None), Ok((15, 1)));
        assert_eq!(bit_span(None, Some("13:12")), Ok((12, 2)));
        assert_eq!(bit_span(None, Some(" 7 : 0 ")), Ok((0, 8)));
        assert_eq!(
            bit_span(Some(16), None),
            Err("bit 16 is outside a 16-bit word".to_owned())
        );
        assert_eq!(
            bit_span(None, Some("3:4")),
            Err("`bits: 3:4` needs 15 >= msb >= lsb".to_owned())
        );
        assert_eq!(
            bit_span(None, Some("16:0")),
            Err("`bits: 16:0` needs 15 >= msb >= lsb".to_owned())
        );
        assert_eq!(
            bit_span(None, Some("12")),
            Err("`bits: 12` is not \"msb:lsb\"".to_owned())
        );
        assert_eq!(
            bit_span(None, Some("a:0")),
            Err("`a` is not a bit number".to_owned())
        );
        assert_eq!(
            bit_span(None, None),
            Err("give exactly one of `bit` and `bits`".to_owned())
        );
        assert_eq!(
            bit_span(Some(1), Some("2:1")),
            Err("give exactly one of `bit` and `bits`".to_owned())
        );
    }

    #[test]
    fn values_show_with_their_unit_and_decimals() {
        let drive = context(VALID);
        let frequency = &drive.model.registers[1];
        assert_eq!(show_raw(frequency, 8000), "80.00 Hz");
        assert_eq!(decimals(0.1), 1);
        assert_eq!(decimals(1.0), 0);
        let parity = &drive.model.registers[3];
        assert_eq!(show_raw(parity, 1), "1");
    }
}
