//! LinuxCNC's `hy_vfd` (Huanyang HY series, Huanyang's own function codes 01-05), unmodified
//! under `halrun`, as an independent master of the HY's virtual drive: configured as its man
//! page says (PD001 = PD002 = 2, station 1, 19200 b/s 8N1 RTU), it writes PD005 and PD144
//! from `-F`/`-S` and reads the setup parameters (01, 02), writes the frequency (05) and the
//! control byte (03, whose reply carries the status byte) and reads the eight status values
//! (04) every cycle; its pins must agree with the virtual drive.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` this test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::hy::{self, registers::*};
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_tests::linuxcnc::{temp_dir, Hal, VirtualPort};

const LIMIT: Duration = Duration::from_secs(30);

/// Waits until the virtual drive's raw register `name` satisfies `ready`; its value then.
fn wait_raw(port: &VirtualPort, hal: &Hal, name: &str, ready: impl Fn(u32) -> bool) -> u32 {
    let end = std::time::Instant::now() + LIMIT;
    loop {
        let value = port.simulator.lock().raw(name).unwrap_or(0);
        if ready(value) {
            return value;
        }
        assert!(
            std::time::Instant::now() < end,
            "{name} is still {value:#06X} after {LIMIT:?}\nhalrun's log:\n{}",
            hal.log_text()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// `hy_vfd -F 400 -S 24000`: 24000 rpm at 400 Hz, so PD144 (the speed at 50 Hz) = 3000 and a
/// speed of 12000 rpm is 200 Hz. The component adds 1 rpm forward and subtracts 1 in reverse
/// before scaling (hy_vfd.c write_data): it writes 20001 (200.01 Hz) forward, 19998 in
/// reverse.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn hy_vfd_runs_reverses_stops_and_sees_a_trip_on_the_hy_virtual_drive() {
    let dir = temp_dir("hy_vfd");
    let settings = SerialSettings {
        baud: 19_200,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    };
    let port = VirtualPort::serve(&hy::DRIVE, "rtu", 1, settings);
    {
        // Set on the panel, as the man page asks: run commands and frequency from the port,
        // RTU 8N1 at 19200 b/s; short ramps (PD014, PD015: 2.0 s over PD005) keep the run short.
        let mut drive = port.simulator.lock();
        for (code, raw) in [
            ("PD001", 2),
            ("PD002", 2),
            ("PD164", 2),
            ("PD165", 3),
            ("PD014", 20),
            ("PD015", 20),
        ] {
            assert!(drive.set_raw(code, raw), "{code} takes {raw}");
        }
    }
    let mut hal = Hal::start(&dir);
    hal.run(&format!(
        "loadusr -Wn spindle hy_vfd -n spindle -d {} -r 19200 -p none -t 1 -F 400 -S 24000",
        port.path
    ));
    hal.wait_for_pin("spindle.enable", Duration::from_secs(10));
    hal.setp("spindle.enable", 1);
    // Its setup: PD005 and PD144 written with 02, read back with 01.
    wait_raw(&port, &hal, "PD144", |raw| raw == 3000);
    assert_eq!(port.simulator.lock().raw("PD005"), Some(40_000));
    hal.wait_for("spindle.max-freq", LIMIT, |v| v == "400");
    hal.wait_for("spindle.rated-motor-rev", LIMIT, |v| v == "24000");

    // Forward at 12000 rpm: 05 writes 200.01 Hz, 03 writes 01h (run).
    hal.setp("spindle.speed-command", 12000);
    hal.setp("spindle.spindle-forward", 1);
    hal.setp("spindle.spindle-on", 1);
    hal.wait_for("spindle.spindle-at-speed", LIMIT, |v| v == "TRUE");
    assert_eq!(port.simulator.lock().raw("FREQ"), Some(20_001));
    assert_eq!(port.simulator.lock().raw("CNTR"), Some(0x01));
    assert!(port.simulator.lock().is_running());
    // at-speed means within 2 % of the command (hy_vfd's spindle-at-speed-tolerance): the
    // drive may still ramp through the last 4 Hz, and the pins show the cycle that saw it.
    // The drive's output is waited on, then the pins of a cycle that read it.
    wait_raw(&port, &hal, "OutF", |raw| raw == 20_001);
    // Our own master reads the same over the same protocol.
    let mut master = port.simulator.master(&hy::protocols::RTU);
    let output = master.read::<OutputFrequency>().expect("Out F");
    assert!((output.0 - 200.01).abs() < 1e-6, "Out F = {output:?}");
    hal.wait_for("spindle.OutF", LIMIT, |v| {
        v.parse::<f64>().is_ok_and(|f| (f - 200.01).abs() < 1e-6)
    });
    assert!((hal.number("spindle.SetF") - 200.01).abs() < 1e-6);
    // spindle-speed-fb follows OutF in the same cycle (hy_vfd.c read_data).
    hal.wait_for("spindle.spindle-speed-fb", LIMIT, |v| {
        v.parse::<f64>().is_ok_and(|f| (f - 12_000.6).abs() < 0.01)
    });
    assert_eq!(hal.number("spindle.frequency-command"), 20_001.0);
    assert!(hal.bit("spindle.CNST-run"));
    assert!(hal.bit("spindle.CNST-running"));
    assert!(!hal.bit("spindle.CNST-command-rf"));
    assert!(!hal.bit("spindle.CNST-running-rf"));

    // Reverse: 11h (run + r/f), 199.98 Hz; the status byte's r/f bits follow.
    hal.setp("spindle.spindle-forward", 0);
    hal.setp("spindle.spindle-reverse", 1);
    hal.wait_for("spindle.CNST-running-rf", LIMIT, |v| v == "TRUE");
    // at-speed was already true going forward: the drive's own output is waited on first.
    wait_raw(&port, &hal, "OutF", |raw| raw == 19_998);
    hal.wait_for("spindle.OutF", LIMIT, |v| {
        v.parse::<f64>().is_ok_and(|f| (f - 199.98).abs() < 1e-6)
    });
    hal.wait_for("spindle.spindle-at-speed", LIMIT, |v| v == "TRUE");
    assert_eq!(port.simulator.lock().raw("CNTR"), Some(0x11));
    assert_eq!(port.simulator.lock().raw("FREQ"), Some(19_998));
    assert!(hal.bit("spindle.CNST-command-rf"));

    // Off: 08h (stop); the drive ramps down and the status byte shows it stopped.
    hal.setp("spindle.spindle-on", 0);
    wait_raw(&port, &hal, "OutF", |raw| raw == 0);
    hal.wait_for("spindle.CNST-run", LIMIT, |v| v == "FALSE");
    hal.wait_for("spindle.OutF", LIMIT, |v| v == "0");
    assert_eq!(port.simulator.lock().raw("CNTR"), Some(0x08));
    assert!(!port.simulator.lock().is_running());
    assert!(!hal.bit("spindle.spindle-at-speed"));

    // A trip while running forward: the HY names no trip over the link and hy_vfd has no
    // fault pin; the trip shows as the drive stopping under a run command (CNST run and
    // running clear, at-speed false) while the component keeps writing 01h.
    hal.setp("spindle.spindle-reverse", 0);
    hal.setp("spindle.spindle-forward", 1);
    hal.setp("spindle.spindle-on", 1);
    hal.wait_for("spindle.spindle-at-speed", LIMIT, |v| v == "TRUE");
    port.simulator.inject_trip(1);
    hal.wait_for("spindle.CNST-running", LIMIT, |v| v == "FALSE");
    hal.wait_for("spindle.spindle-at-speed", LIMIT, |v| v == "FALSE");
    assert!(!hal.bit("spindle.CNST-run"));
    assert_eq!(port.simulator.lock().raw("CNTR"), Some(0x01));
    assert_eq!(port.simulator.lock().trip(), Some(1));

    // No exchange failed over the run, and the component says its link is good.
    assert_eq!(hal.number("spindle.error-count"), 0.0, "{}", hal.log_text());
    assert!(hal.bit("spindle.hycomm-ok"));
}
