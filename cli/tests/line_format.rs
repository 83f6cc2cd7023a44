//! The character format each command opens a line with: the drive's factory format for the
//! protocol spoken (the DV1 speaks Modbus RTU at 8E1, its 07-07 factory setting, and Eaton
//! at 8N1), changed by `--data-bits`, `--parity` and `--stop-bits` on every command that
//! opens a line, within what the drive can be set to.

mod common;

use common::{text, Sim};
use std::io::{BufRead, BufReader};
use std::process::{Command, Output, Stdio};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs")
}

/// `vfd sim ARGS`'s banner line on standard error.
fn sim_banner(args: &[&str]) -> String {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .arg("sim")
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("vfd sim starts");
    let mut banner = String::new();
    BufReader::new(child.stderr.take().expect("piped"))
        .read_line(&mut banner)
        .expect("the banner");
    let _ = child.kill();
    let _ = child.wait();
    banner
}

#[test]
fn each_protocol_starts_from_its_own_factory_format() {
    for (protocol, format) in [("modbus", "8E1"), ("modbus_ascii", "7N2"), ("eaton", "8N1")] {
        let banner = sim_banner(&["--drive", "dv1", "--protocol", protocol]);
        assert!(
            banner.contains(&format!("9600 baud {format};")),
            "{protocol}: {banner}"
        );
    }
    let listed = text(&vfd(&["list"]));
    assert!(
        listed.contains("modbus     Modbus RTU (stations 0-254, 8E1)"),
        "{listed}"
    );
    // Given on the command line.
    let banner = sim_banner(&[
        "--drive",
        "dv1",
        "--protocol",
        "modbus",
        "--parity",
        "none",
        "--stop-bits",
        "2",
    ]);
    assert!(banner.contains("9600 baud 8N2;"), "{banner}");
}

#[test]
fn every_command_that_opens_a_line_takes_data_and_stop_bits() {
    for command in [
        "read", "write", "watch", "backup", "restore", "block", "sim",
    ] {
        let help = text(&vfd(&[command, "--help"]));
        assert!(
            help.contains("--data-bits") && help.contains("--stop-bits"),
            "{command}: {help}"
        );
    }
}

#[test]
fn a_format_the_drive_cannot_use_is_refused_before_the_port_is_opened() {
    let port = "/dev/nonexistent-vfd-port";
    let seven = vfd(&[
        "read",
        "--drive",
        "yd1000",
        "--port",
        port,
        "--data-bits",
        "7",
        "FH",
    ]);
    assert!(!seven.status.success());
    assert!(
        text(&seven).contains("yd1000 cannot use 7 data bits: its description gives 8"),
        "{}",
        text(&seven)
    );
    // The DV1 takes 7 or 8 data bits, but Modbus RTU only as 07-07 offers it.
    let rtu = vfd(&[
        "read",
        "--drive",
        "dv1",
        "--port",
        port,
        "--data-bits",
        "7",
        "07-01",
    ]);
    assert!(
        text(&rtu).contains("dv1 cannot speak modbus at 7E1: its setting offers 8N2, 8E1, 8O1"),
        "{}",
        text(&rtu)
    );
    let range = vfd(&[
        "read",
        "--drive",
        "dv1",
        "--port",
        port,
        "--stop-bits",
        "3",
        "07-01",
    ]);
    assert!(!range.status.success());
    assert!(text(&range).contains("--stop-bits"), "{}", text(&range));
}

#[test]
fn a_read_at_a_format_the_drive_offers_goes_through() {
    let sim = Sim::start("dv1", "modbus");
    let read = sim.vfd(
        "dv1",
        "modbus",
        &[
            "read",
            "--parity",
            "odd",
            "--data-bits",
            "8",
            "--stop-bits",
            "1",
            "07-01",
        ],
    );
    assert!(read.status.success(), "{}", text(&read));
}
