//! Hints that point the right way (an outside integrator's findings): a write whose first
//! step gets no reply is told to check the line, not to stop the motor; a drive of one
//! protocol is never told to try `--protocol`; a protocol that writes only persistently is
//! told `--persist`; `write`, `info` and `restore` say the same of where a value is stored;
//! a drive named by its path is named by it in the backup header and the hints, and
//! `info --drive FILE` works as every other command's `--drive` does.

mod common;

use common::{text, Sim};
use std::process::{Command, Output};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs")
}

/// The computer-link fixture drive: one protocol (`link`), writes only persistent, F-01
/// kept in RAM whatever the command.
fn heron() -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/computer-link/heron_hl7.yaml")
        .canonicalize()
        .expect("the fixture")
        .display()
        .to_string()
}

#[test]
fn a_write_whose_first_step_gets_no_reply_is_told_to_check_the_line() {
    // Station 2 is not on the line: the coil-65 step before the write of 303 times out.
    let sim = Sim::spawn(&["--station", "fc51:modbus@1"]);
    let write = sim.vfd(
        "fc51",
        "modbus",
        &["write", "--address", "2", "--timeout", "50", "303", "40"],
    );
    let message = text(&write);
    assert!(!write.status.success(), "{message}");
    assert!(message.contains("the step before it failed"), "{message}");
    assert!(message.contains("no reply"), "{message}");
    assert!(message.contains("hint: check baud rate"), "{message}");
    assert!(!message.contains("motor is stopped"), "{message}");
}

#[test]
fn a_drive_of_one_protocol_is_pointed_at_persist_not_at_another_protocol() {
    let drive = heron();
    let sim = Sim::spawn(&["--drive", &drive]);
    let ram = sim.vfd(&drive, "link", &["write", "F-02", "20"]);
    let message = text(&ram);
    assert!(!ram.status.success(), "{message}");
    assert!(message.contains("give --persist"), "{message}");
    assert!(!message.contains("--protocol"), "{message}");
    let silent = sim.vfd(
        &drive,
        "link",
        &["read", "--address", "7", "--timeout", "50", "F-02"],
    );
    let message = text(&silent);
    assert!(message.contains("hint: check baud rate"), "{message}");
    assert!(!message.contains("--protocol"), "{message}");
}

#[test]
fn write_and_info_agree_on_where_a_value_is_stored() {
    let drive = heron();
    let sim = Sim::spawn(&["--drive", &drive]);
    let kept = sim.vfd(&drive, "link", &["write", "--persist", "F-01", "20"]);
    assert!(kept.status.success(), "{}", text(&kept));
    assert!(
        text(&kept).contains("(RAM only: the drive keeps a persistent write of it in RAM)"),
        "{}",
        text(&kept)
    );
    let info = text(&vfd(&["info", "--drive", &drive, "F-01", "F-02"]));
    assert!(
        info.contains("storage     RAM only (a persistent write is accepted, kept in RAM)"),
        "{info}"
    );
    assert!(
        info.contains("storage     RAM and EEPROM: its protocols write it only persistently"),
        "{info}"
    );
}

#[test]
fn restore_names_the_drive_file_and_points_at_persist() {
    let drive = heron();
    let dir = std::env::temp_dir().join(format!("vfd-hint-direction-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("heron.yaml");
    let file_arg = file.to_str().unwrap();
    let sim = Sim::spawn(&["--drive", &drive]);
    let saved = sim.vfd(&drive, "link", &["backup", "--to", file_arg]);
    assert!(saved.status.success(), "{}", text(&saved));
    let backup = std::fs::read_to_string(&file).unwrap();
    let header = backup.lines().next().unwrap();
    assert!(
        header.contains(&format!("`vfd restore --drive {drive} --from FILE`")),
        "{header}"
    );
    // A changed value: the link writes only persistently.
    std::fs::write(&file, backup.replace("10.0 s", "12.0 s")).unwrap();
    let ram = sim.vfd(&drive, "link", &["restore", "--from", file_arg]);
    let message = text(&ram);
    assert!(!ram.status.success(), "{message}");
    assert!(message.contains("nothing written"), "{message}");
    assert!(message.contains("restore with --persist"), "{message}");
    let persistent = sim.vfd(
        &drive,
        "link",
        &["restore", "--persist", "--from", file_arg],
    );
    assert!(persistent.status.success(), "{}", text(&persistent));
    // Onto another model: pointed at the model it was taken from.
    let wrong = vfd(&[
        "restore", "--drive", "dv1", "--port", &sim.port, "--from", file_arg,
    ]);
    assert!(
        text(&wrong).contains("restore it onto a heron_hl7 with --drive heron_hl7"),
        "{}",
        text(&wrong)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
