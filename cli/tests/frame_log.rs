//! Frames as `vfd sim -v`, `--trace` and `vfd decode` show them: each frame decoded by the
//! station it is for on a line of mixed models; a request no station answers (an inverter
//! reset) on its own line; the master's acknowledgement (Eaton C) and the page switch as
//! the protocol steps they are; error codes in the manual's notation (the DV1's H0C).

mod common;

use common::text;
use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Command, Output, Stdio};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs")
}

/// `vfd sim -v ARGS`, its device and its log so far (read when it is stopped).
struct VerboseSim {
    child: Child,
    port: String,
}

impl VerboseSim {
    fn start(args: &[&str]) -> VerboseSim {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg("sim")
            .arg("-v")
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("vfd sim starts");
        let mut port = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut port)
            .expect("the device");
        VerboseSim {
            child,
            port: port.trim().to_owned(),
        }
    }

    /// Stops it and returns its log.
    fn log(mut self) -> String {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let mut log = String::new();
        let _ = self
            .child
            .stderr
            .take()
            .expect("piped")
            .read_to_string(&mut log);
        log
    }
}

#[test]
fn a_mixed_line_logs_each_frame_with_the_station_it_is_for() {
    let sim = VerboseSim::start(&["--station", "dv1:modbus@1", "--station", "fc51:modbus@2"]);
    let port = sim.port.clone();
    // Function 01 (coils): the FC 51's, which the DV1 (the first station) lacks.
    let coils = vfd(&[
        "read",
        "--drive",
        "fc51",
        "-p",
        "modbus",
        "--address",
        "2",
        "--port",
        &port,
        "STW",
    ]);
    assert!(coils.status.success(), "{}", text(&coils));
    // A reset is never answered; the next request is.
    let reset = vfd(&[
        "write",
        "--drive",
        "dv1",
        "--address",
        "1",
        "--port",
        &port,
        "HFD",
        "reset",
    ]);
    assert!(reset.status.success(), "{}", text(&reset));
    let status = vfd(&[
        "read",
        "--drive",
        "dv1",
        "--address",
        "1",
        "--port",
        &port,
        "H7A",
    ]);
    assert!(status.status.success(), "{}", text(&status));
    let log = sim.log();
    let line = |needle: &str| {
        log.lines()
            .find(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("no {needle:?} in:\n{log}"))
            .to_owned()
    };
    let coil_request = line("02 01 00 20 00 10");
    assert!(
        coil_request.contains("request [2]") && coil_request.contains("STW Status word"),
        "{coil_request}"
    );
    assert!(line("02 01 02 07 00").contains("reply   [2]"), "{log}");
    let reset = line("01 06 11 01 96 96 32 F8");
    assert!(
        reset.contains("request [1]") && reset.ends_with("never answered"),
        "the reset on a line of its own: {reset}"
    );
    assert!(!log.contains("not a whole"), "{log}");
}

#[test]
fn the_trace_shows_the_acknowledgement_and_the_page_switch_as_such() {
    let sim = common::Sim::start("dv1", "eaton");
    let read = sim.vfd("dv1", "eaton", &["read", "--trace", "02-15"]);
    let trace = text(&read);
    assert!(read.status.success(), "{trace}");
    assert!(
        trace.contains(
            "-> 05 30 31 46 46 30 30 30 30 31 44 45 0D  [station 1, page switch to page 1]"
        ),
        "{trace}"
    );
    assert!(
        trace.contains("-> 06 30 31 0D  [follow-up: the master acknowledges the reply, station 1]"),
        "{trace}"
    );
    assert!(!trace.contains("not a whole"), "{trace}");
}

#[test]
fn error_codes_are_shown_as_the_manual_prints_them() {
    let eaton = vfd(&[
        "decode",
        "--drive",
        "dv1",
        "-p",
        "eaton",
        "--reply",
        "\\x1500C\\r",
    ]);
    assert!(
        text(&eaton).contains("error:    H0C (Data range error"),
        "{}",
        text(&eaton)
    );
    // The FC 51 prints its Errornum in decimal: 01 83 11 (17, cannot change while running).
    let fc51 = vfd(&[
        "decode",
        "--drive",
        "fc51",
        "-p",
        "modbus",
        "--reply",
        "01 83 11 81 3C",
    ]);
    assert!(
        text(&fc51).contains("error:    17 (Cannot change"),
        "{}",
        text(&fc51)
    );
}

#[test]
fn decode_shows_the_page_switch_as_a_step_not_a_register() {
    let decoded = text(&vfd(&[
        "decode",
        "--drive",
        "dv1",
        "-p",
        "eaton",
        "\\x0500FF00001DD\\r",
    ]));
    assert!(
        decoded.contains("step:     page switch (wire number 00FFh)")
            && decoded.contains("page:     1\n")
            && !decoded.contains("register:"),
        "{decoded}"
    );
}
