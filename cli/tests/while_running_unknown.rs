//! `writable_while_running: unknown` (the VF-AS1's section 7 table has no such column) as
//! the command line treats it: `vfd info` says the manual does not state it, and `vfd
//! restore` writes such a value while the motor runs instead of refusing, reporting the
//! drive's answer.

mod common;

use common::{text, Sim};
use std::process::Command;

fn vfd(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs");
    assert!(output.status.success(), "{}", text(&output));
    text(&output)
}

#[test]
fn info_says_when_the_manual_does_not_state_the_while_running_flag() {
    let f803 = vfd(&["info", "vf-as1", "F803"]);
    assert!(
        f803.contains("while run   not stated by the manual (a write while running is attempted; a refusal is reported)"),
        "{f803}"
    );
    let fh = vfd(&["info", "vf-as1", "FH"]);
    assert!(
        fh.contains("while run   not writable while the motor runs"),
        "{fh}"
    );
}

#[test]
fn the_yd1000_registers_without_a_run_time_column_are_unknown() {
    // Not in the 11.x tables with their 运行中修改 column: known from examples or section 6.
    for code in ["F260", "F501", "F800", "F801", "F802", "F803"] {
        let info = vfd(&["info", "yd1000", code]);
        assert!(
            info.contains("while run   not stated by the manual"),
            "{code}: {info}"
        );
    }
}

#[test]
fn restore_writes_an_unknown_value_while_running_and_reports_the_answer() {
    let dir =
        std::env::temp_dir().join(format!("vfd-while-running-unknown-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("vf-as1.yaml");
    let file_arg = file.to_str().unwrap();
    let sim = Sim::start("vf-as1", "binary");
    let saved = sim.vfd("vf-as1", "binary", &["backup", "--to", file_arg]);
    assert!(saved.status.success(), "{}", text(&saved));
    // F803 (no while-running column) changes, then the motor runs.
    for (code, value) in [
        ("F803", "5"),
        ("FA01", "20"),
        ("FA00", "command_priority,frequency_priority,run"),
    ] {
        let wrote = sim.vfd("vf-as1", "binary", &["write", code, value]);
        assert!(wrote.status.success(), "{}", text(&wrote));
    }
    let status = sim.vfd("vf-as1", "binary", &["read", "FD01"]);
    assert!(text(&status).contains("running"), "{}", text(&status));
    let restored = sim.vfd("vf-as1", "binary", &["restore", "--from", file_arg]);
    let message = text(&restored);
    assert!(restored.status.success(), "{message}");
    assert!(!message.contains("the drive is running"), "{message}");
    let back = sim.vfd("vf-as1", "binary", &["read", "F803"]);
    assert!(text(&back).contains("0 s"), "{}", text(&back));
    let _ = std::fs::remove_dir_all(&dir);
}
