//! The behaviour model check's tests: each kind of name a `behaviour:` section can get
//! wrong, and the ones it must accept.

use super::behaviour_resolves as check;
use crate::validate::testing::{check_yaml, only, VALID};

const BEHAVIOUR: &str = r#"
behaviour:
  source: "7"
  command: { register: FA00, require: [command_enabled], run: run }
  frequency: { command: FH, acceleration: Acc, deceleration: 10.0, span: FH }
  status: { registers: [FA00], running: [run] }
  refusals:
    ascii: { out_of_range: 1 }
"#;

fn with_behaviour(edit: (&str, &str)) -> String {
    format!("{VALID}{}", BEHAVIOUR.replace(edit.0, edit.1))
}

#[test]
fn accepts_a_model_naming_what_exists() {
    assert!(check_yaml(check, VALID).is_empty());
    let found = check_yaml(check, &with_behaviour(("", "")));
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn leaves_a_word_whose_bit_field_is_undefined_to_references_resolve() {
    let yaml = format!("{VALID}{BEHAVIOUR}").replace(
        "bitfield: command_word, ram_only",
        "bitfield: command_wordx, ram_only",
    );
    let found = check_yaml(check, &yaml);
    assert!(found.is_empty(), "{found:#?}");
}

#[test]
fn a_status_role_set_by_a_level_needs_the_level() {
    let roles = "status: { registers: [FA00], running: [run], overload: [run], frequency_detected: [command_enabled] }";
    let yaml = format!(
        "{VALID}{}",
        BEHAVIOUR.replace("status: { registers: [FA00], running: [run] }", roles)
    );
    let found = check_yaml(check, &yaml);
    let messages: Vec<&str> = found.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(
        messages,
        [
            "`overload` bits are set by a level the model does not give",
            "`frequency_detected` bits are set by a level the model does not give"
        ]
    );
    let given = yaml
        .replace("span: FH }", "span: FH, detection: UL }")
        .replace(
            "refusals:",
            "current: { registers: [Acc], at_zero: 0, at_span: 10, overload: 8.0 }\n  refusals:",
        );
    let found = check_yaml(check, &given);
    assert!(found.is_empty(), "{found:#?}");
    let found = check_yaml(check, &given.replace("detection: UL", "detection: UX"));
    assert_eq!(only(&found).message, "register `UX` is not defined");
    assert_eq!(only(&found).path, "behaviour.frequency.detection");
}

#[test]
fn a_percentage_command_is_in_percent_of_a_frequency() {
    // FH is in Hz: as the command it is no percentage.
    let found = check_yaml(
        check,
        &with_behaviour(("span: FH }", "span: FH, percent_of: UL }")),
    );
    assert_eq!(
        only(&found).message,
        "`percent_of` reads the frequency command `FH` as a percentage, but it is in Hz"
    );
    assert_eq!(only(&found).path, "behaviour.frequency.percent_of");
    // A command in % of FH checks; one in % of a percentage does not.
    let percent = "  - { address: 0x0020, id: reference, code: REF, name: Reference, unit: \"%\", scale: 0.01, source: \"7\" }\n";
    let yaml = format!(
        "{}{}",
        VALID.replace("\nvalue_examples:", &format!("{percent}\nvalue_examples:")),
        BEHAVIOUR.replace(
            "frequency: { command: FH,",
            "frequency: { command: REF, percent_of: FH,"
        )
    );
    let found = check_yaml(check, &yaml);
    assert!(found.is_empty(), "{found:#?}");
    let found = check_yaml(check, &yaml.replace("percent_of: FH", "percent_of: REF"));
    assert_eq!(
        only(&found).message,
        "`REF` is a percentage itself, not the frequency 100 % stands for"
    );
    let found = check_yaml(check, &yaml.replace("percent_of: FH", "percent_of: FX"));
    assert_eq!(only(&found).message, "register `FX` is not defined");
}

#[test]
fn a_command_register_has_a_run_bit_or_codes() {
    let found = check_yaml(check, &with_behaviour(("run: run }", "}")));
    assert_eq!(
        only(&found).message,
        "the command register has neither a run bit (`run`) nor command codes (`codes`)"
    );
    let both = with_behaviour(("run: run }", "run: run, codes: { run: [1] } }"));
    let found = check_yaml(check, &both);
    assert_eq!(only(&found).path, "behaviour.command.codes");
    let codes = with_behaviour((
        "require: [command_enabled], run: run }",
        "codes: { run: [1], stop: [0x10000] } }",
    ));
    let found = check_yaml(check, &codes);
    assert_eq!(only(&found).message, "0x10000 does not fit a 16-bit word");
}

#[test]
fn reports_an_unknown_register() {
    let found = check_yaml(
        check,
        &with_behaviour(("acceleration: Acc", "acceleration: ACC2")),
    );
    let problem = only(&found);
    assert_eq!(problem.message, "register `ACC2` is not defined");
    assert_eq!(problem.path, "behaviour.frequency.acceleration");
}

#[test]
fn reports_an_unknown_bit_and_a_word_without_bit_field() {
    let found = check_yaml(check, &with_behaviour(("run: run", "run: start")));
    assert_eq!(
        only(&found).message,
        "bit `start` is not a field of `command_word`"
    );
    let found = check_yaml(
        check,
        &with_behaviour(("registers: [FA00]", "registers: [FH]")),
    );
    assert_eq!(
        only(&found).message,
        "register `FH` is not a bit-field word"
    );
}

#[test]
fn checks_the_reverse_run_bit_the_forward_bits_and_the_reset_write() {
    let found = check_yaml(
        check,
        &with_behaviour((
            "run: run }",
            "run: run, run_reverse: run, reset_by_write: { register: F601, value: 1 } }",
        )),
    );
    assert!(found.is_empty(), "{found:#?}");
    let found = check_yaml(
        check,
        &with_behaviour(("run: run }", "run: run, run_reverse: backwards }")),
    );
    let problem = only(&found);
    assert_eq!(problem.path, "behaviour.command.run_reverse");
    assert_eq!(
        problem.message,
        "bit `backwards` is not a field of `command_word`"
    );
    let found = check_yaml(
        check,
        &with_behaviour(("running: [run]", "running: [run], forward: [ahead]")),
    );
    assert_eq!(only(&found).path, "behaviour.status.forward[0]");
    // The reset value must be one of the register's codes.
    let found = check_yaml(
        check,
        &with_behaviour((
            "run: run }",
            "run: run, reset_by_write: { register: F601, value: 0x9696 } }",
        )),
    );
    let problem = only(&found);
    assert_eq!(problem.path, "behaviour.command.reset_by_write.value");
    assert_eq!(
        problem.message,
        "0x9696 is not a value of `F601`'s code table `parity`"
    );
    let found = check_yaml(
        check,
        &with_behaviour((
            "run: run }",
            "run: run, reset_by_write: { register: RST, value: 1 } }",
        )),
    );
    let problem = only(&found);
    assert_eq!(problem.path, "behaviour.command.reset_by_write.register");
    assert_eq!(problem.message, "register `RST` is not defined");
}

#[test]
fn a_trip_history_names_registers_or_their_bit_fields() {
    let history = "trip: { history: [FA00.run, FA00.command_enabled, Acc] }\n  refusals:";
    let found = check_yaml(check, &with_behaviour(("refusals:", history)));
    assert!(found.is_empty(), "{found:#?}");
    let history = "trip: { history: [FA00.stop, Acc.low, ACC2], clear_by_write: { register: FA00, value: 0x10000 } }\n  refusals:";
    let found = check_yaml(check, &with_behaviour(("refusals:", history)));
    let messages: Vec<(&str, &str)> = found
        .iter()
        .map(|d| (d.path.as_str(), d.message.as_str()))
        .collect();
    assert_eq!(
        messages,
        [
            (
                "behaviour.trip.clear_by_write.value",
                "0x10000 does not fit a 16-bit word"
            ),
            (
                "behaviour.trip.history[0]",
                "`stop` is not a field of `command_word`"
            ),
            (
                "behaviour.trip.history[1]",
                "register `acceleration_time` is not a bit-field word, so `Acc.low` names no field"
            ),
            (
                "behaviour.trip.history[2]",
                "register `ACC2` is not defined"
            ),
        ]
    );
}

#[test]
fn reports_refusals_for_a_protocol_the_drive_lacks() {
    let found = check_yaml(check, &with_behaviour(("ascii: {", "modbus: {")));
    assert_eq!(found.len(), 2, "{found:?}");
    let problem = &found[0];
    assert_eq!(
        problem.message,
        "protocol `modbus` is not one of the drive's"
    );
    assert_eq!(
        problem.hint.as_deref(),
        Some("the drive's protocols are: ascii")
    );
    assert_eq!(
            found[1].message,
            "protocol `ascii` has no refusals: the virtual drive would not answer a refused request over it"
        );
}
