//! `vfd check`: errors, then warnings, each with file:line:column and a hint; warnings do
//! not fail the check unless `--deny-warnings` is given.

use std::process::{Command, Output};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("vfd runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

const WARNED: &str = "tests/fixtures/warnings/no_behaviour.yaml";

#[test]
fn warnings_are_printed_with_a_location_and_a_hint_and_do_not_fail() {
    let output = vfd(&["check", "--protocols", "drives/protocols", WARNED]);
    let text = stdout(&output);
    assert!(output.status.success(), "{text}");
    assert!(
        text.contains("no_behaviour.yaml: ok (5 registers, 1 examples, 1 warning)"),
        "{text}"
    );
    assert!(
        text.contains("warning: the drive has no `behaviour:` section"),
        "{text}"
    );
    assert!(
        text.contains("--> tests/fixtures/warnings/no_behaviour.yaml:3:1"),
        "{text}"
    );
    assert!(
        text.contains("= hint: without it the virtual drive"),
        "{text}"
    );
}

#[test]
fn deny_warnings_fails_on_a_warning_and_passes_without_one() {
    let output = vfd(&[
        "check",
        "--deny-warnings",
        "--protocols",
        "drives/protocols",
        WARNED,
    ]);
    assert!(!output.status.success(), "{}", stdout(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("--deny-warnings"), "{stderr}");
    let clean = vfd(&["check", "--deny-warnings", "drives/yd1000.yaml"]);
    assert!(clean.status.success(), "{}", stdout(&clean));
}

#[test]
fn errors_come_before_warnings() {
    let output = vfd(&[
        "check",
        "--protocols",
        "drives/protocols",
        "tests/fixtures/broken/example_not_simulated.yaml",
    ]);
    let text = stdout(&output);
    assert!(!output.status.success(), "{text}");
    let error = text
        .find("error: the virtual drive gives this example's reply")
        .expect("the error");
    let warning = text
        .find("warning: the drive has no `behaviour:`")
        .expect("the warning");
    assert!(error < warning, "{text}");
    assert!(text.contains("examples[0].not_simulated"), "{text}");
}
