//! `vfd --port-kind` against `vfd sim --port-kind` for the VF-AS1's two serial ports,
//! registers whose scale another register chooses (ACC by FA09) and values taken besides
//! the range (the DV1's 99999 as FFFFh), read and written through the command line.

mod common;

use common::{text, Sim};
use std::process::Command;
use std::time::{Duration, Instant};

#[test]
fn a_port_named_once_points_the_2_wire_registers_at_the_4_wire_copies() {
    let sim = Sim::spawn(&[
        "--drive",
        "vf-as1",
        "--protocol",
        "binary",
        "--port-kind",
        "four_wire",
    ]);
    let write = sim.vfd(
        "vf-as1",
        "binary",
        &["write", "--port-kind", "four_wire", "FA01", "30Hz"],
    );
    assert!(write.status.success(), "{}", text(&write));
    assert!(text(&write).contains("wrote FA05"), "{}", text(&write));
    let copy = sim.vfd("vf-as1", "binary", &["read", "FA05", "FA01"]);
    assert!(
        text(&copy).contains("FA05") && text(&copy).contains("30.00 Hz"),
        "{}",
        text(&copy)
    );
    assert!(
        text(&copy).contains("0.00 Hz"),
        "FA01 is untouched: {}",
        text(&copy)
    );
    let run = sim.vfd(
        "vf-as1",
        "binary",
        &[
            "write",
            "--port-kind",
            "four_wire",
            "FA00",
            "command_priority,frequency_priority,run",
        ],
    );
    assert!(run.status.success(), "{}", text(&run));
    assert!(text(&run).contains("wrote FA04"), "{}", text(&run));
    // The virtual drive serves the 4-wire port: FA04 runs it (ACC has no factory value,
    // so the output steps to the command at once, on the simulator's wall clock).
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let output = sim.vfd("vf-as1", "binary", &["read", "FD00"]);
        if text(&output).contains("30.00 Hz") {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the drive does not run: {}",
            text(&output)
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let read = sim.vfd(
        "vf-as1",
        "binary",
        &["read", "--port-kind", "four_wire", "FA00"],
    );
    assert!(
        text(&read).contains("FA04") && text(&read).contains("C400h"),
        "{}",
        text(&read)
    );
}

#[test]
fn a_port_the_drive_does_not_have_is_refused_with_the_ports_it_has() {
    let sim = Sim::spawn(&["--drive", "vf-as1", "--protocol", "binary"]);
    let wrong = sim.vfd("vf-as1", "binary", &["read", "--port-kind", "usb", "FA01"]);
    assert!(!wrong.status.success());
    assert!(
        text(&wrong).contains("drive vf-as1 has no port `usb`"),
        "{}",
        text(&wrong)
    );
    assert!(
        text(&wrong).contains("two_wire, four_wire"),
        "{}",
        text(&wrong)
    );
    let one = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["sim", "--drive", "yd1000", "--port-kind", "two_wire"])
        .output()
        .expect("vfd runs");
    assert!(!one.status.success());
    assert!(
        text(&one).contains("drive yd1000 has one serial port"),
        "{}",
        text(&one)
    );
}

#[test]
fn acc_is_shown_and_written_in_the_step_fa09_chooses() {
    let sim = Sim::spawn(&["--drive", "vf-as1", "--protocol", "binary"]);
    // FA09 = 1 (0.1 s steps): 10 s is 0064h.
    let write = sim.vfd("vf-as1", "binary", &["write", "ACC", "10"]);
    assert!(write.status.success(), "{}", text(&write));
    assert!(text(&write).contains("10.0 s"), "{}", text(&write));
    // FA09 = 0 (0.01 s steps): the same word reads 1.00 s, and 10 s is written as 03E8h.
    let unit = sim.vfd("vf-as1", "binary", &["write", "FA09", "centiseconds"]);
    assert!(unit.status.success(), "{}", text(&unit));
    let read = sim.vfd("vf-as1", "binary", &["read", "ACC"]);
    assert!(text(&read).contains("1.00 s"), "{}", text(&read));
    let write = sim.vfd("vf-as1", "binary", &["write", "ACC", "10"]);
    assert!(text(&write).contains("10.00 s"), "{}", text(&write));
    let read = sim.vfd("vf-as1", "binary", &["read", "ACC"]);
    assert!(text(&read).contains("10.00 s"), "{}", text(&read));
    let watch = sim.vfd("vf-as1", "binary", &["watch", "--count", "1", "ACC"]);
    assert!(watch.status.success(), "{}", text(&watch));
    assert!(text(&watch).contains("10.00 s"), "{}", text(&watch));
    // 700 s is beyond 600 s in 0.01 s steps: refused, nothing written.
    let beyond = sim.vfd("vf-as1", "binary", &["write", "ACC", "700"]);
    assert!(!beyond.status.success());
    assert!(text(&beyond).contains("0.01 to 600 s"), "{}", text(&beyond));
}

#[test]
fn dv1_shows_and_takes_99999_by_number_or_name() {
    let sim = Sim::spawn(&["--drive", "dv1", "--protocol", "modbus"]);
    let read = sim.vfd("dv1", "modbus", &["read", "07-09"]);
    assert!(read.status.success(), "{}", text(&read));
    assert!(
        text(&read).contains("99999 (no_check: No time-out check)"),
        "{}",
        text(&read)
    );
    let write = sim.vfd("dv1", "modbus", &["write", "07-09", "2.5"]);
    assert!(write.status.success(), "{}", text(&write));
    let back = sim.vfd("dv1", "modbus", &["read", "07-09"]);
    assert!(text(&back).contains("2.5 s"), "{}", text(&back));
    for value in ["no_check", "99999"] {
        let write = sim.vfd("dv1", "modbus", &["write", "07-09", value]);
        assert!(write.status.success(), "{value}: {}", text(&write));
        let back = sim.vfd("dv1", "modbus", &["read", "07-09"]);
        assert!(
            text(&back).contains("99999 (no_check"),
            "{value}: {}",
            text(&back)
        );
    }
    let beyond = sim.vfd("dv1", "modbus", &["write", "07-09", "1000"]);
    assert!(!beyond.status.success(), "{}", text(&beyond));
}

#[test]
fn dv1_frequencies_over_eaton_take_their_scale_from_the_unit_digit() {
    // 00-08 chooses two or one decimals for 1002h; it has no Eaton code, so the command
    // line reads 1002h itself and takes the scale from the reply's unit digit.
    let sim = Sim::spawn(&["--drive", "dv1", "--protocol", "eaton"]);
    let write = sim.vfd("dv1", "eaton", &["write", "H6D-HED", "50"]);
    assert!(write.status.success(), "{}", text(&write));
    let read = sim.vfd("dv1", "eaton", &["read", "H6D-HED"]);
    assert!(read.status.success(), "{}", text(&read));
    assert!(text(&read).contains("50.00 Hz"), "{}", text(&read));
}

#[test]
fn dv1_writes_with_persist_over_the_07_11_selector() {
    // The DV1's protocols have one plain write; 07-11 chooses RAM or RAM + EEPROM, and the
    // command line's master sets it (drives/README.md, "Persistence chosen by a register").
    let sim = Sim::spawn(&["--drive", "dv1", "--protocol", "modbus"]);
    let write = sim.vfd("dv1", "modbus", &["write", "--persist", "07-08", "5"]);
    assert!(write.status.success(), "{}", text(&write));
    assert!(text(&write).contains("RAM and EEPROM"), "{}", text(&write));
    let ram = sim.vfd("dv1", "modbus", &["write", "07-08", "6"]);
    assert!(ram.status.success(), "{}", text(&ram));
    let selector = sim.vfd("dv1", "modbus", &["read", "07-11"]);
    assert!(
        text(&selector).contains("ram_only") || text(&selector).contains("RAM only"),
        "{}",
        text(&selector)
    );
}
