//! Errors a new user hit give a hint: the read-only refusal names the manual and `vfd
//! info`, `encode` without a station address names `--address`.

mod common;

use common::text;

/// What a new user hit: the read-only refusal and `encode` without a station address give
/// a hint.
#[test]
fn read_only_and_missing_address_errors_give_a_hint() {
    let run = |args: &[&str]| {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(args)
            .output()
            .expect("vfd runs");
        assert!(!output.status.success());
        text(&output)
    };
    let encode = run(&["encode", "fc51", "modbus", "read", "201"]);
    assert!(
        encode.contains("needs a station address")
            && encode.contains("hint:")
            && encode.contains("--address"),
        "{encode}"
    );
    let read_only = run(&[
        "write",
        "--drive",
        "yd1000",
        "--port",
        "/dev/null",
        "FE01",
        "1",
    ]);
    assert!(
        read_only.contains("is read-only")
            && read_only.contains("hint: the manual lists it as read-only"),
        "{read_only}"
    );
}

/// A frame no protocol of the DV1 decodes: each reason is given once, although the Eaton
/// protocol's two line-ending variants fail alike.
#[test]
fn decode_errors_give_each_reason_once() {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["decode", "--drive", "dv1", ":01XYZ\\r"])
        .output()
        .expect("vfd runs");
    assert!(!output.status.success());
    let message = text(&output);
    let lines: Vec<&str> = message.lines().filter(|l| l.contains(": ")).collect();
    assert!(lines.iter().any(|l| l.contains("eaton")), "{message}");
    let unique: std::collections::HashSet<&&str> = lines.iter().collect();
    assert_eq!(unique.len(), lines.len(), "a line printed twice: {message}");
}

/// A RAM write of a parameter a persistence selector governs says that the selector was
/// set (the description's selector, DV1 07-11); a persistent write does not.
#[test]
fn a_ram_write_says_it_set_the_persistence_selector() {
    let sim = common::Sim::start("dv1", "modbus");
    let ram = sim.vfd("dv1", "modbus", &["write", "02-15", "30Hz"]);
    assert!(ram.status.success(), "{}", text(&ram));
    let said = text(&ram);
    assert!(
        said.contains("note: a RAM write sets the persistence selector 07-11"),
        "{said}"
    );
    let persistent = sim.vfd("dv1", "modbus", &["write", "02-15", "30Hz", "--persist"]);
    assert!(persistent.status.success(), "{}", text(&persistent));
    assert!(
        !text(&persistent).contains("persistence selector"),
        "{}",
        text(&persistent)
    );
}

/// A parameter write the drive refuses at the step before it (the persistence selector,
/// because the motor runs) names the register asked for, then the step and why it is sent,
/// with the drive's code and meaning.
#[test]
fn a_refused_step_names_the_register_asked_for_and_the_step() {
    let sim = common::Sim::start("dv1", "modbus");
    let run = sim.vfd("dv1", "modbus", &["write", "HFA", "forward"]);
    assert!(run.status.success(), "{}", text(&run));
    let refused = sim.vfd("dv1", "modbus", &["write", "02-15", "30Hz"]);
    assert!(!refused.status.success(), "{}", text(&refused));
    let message = text(&refused);
    assert!(
        message.starts_with("vfd: cannot write register 00C3 02-15"),
        "{message}"
    );
    assert!(
        message.contains("the step before it was refused: setting the persistence selector")
            && message.contains("07-11")
            && message.contains("error H03 Illegal data value"),
        "{message}"
    );
    assert!(
        message.contains("hint: the manual allows 02-15 to change only while the motor is stopped"),
        "{message}"
    );
}
