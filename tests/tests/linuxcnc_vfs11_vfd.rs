//! LinuxCNC's `vfs11_vfd` (written for the Toshiba VF-S11), unmodified, as the independent
//! Modbus master of the VF-S11's virtual drive (drives/vf-s11.yaml): configured by an INI
//! file as its man page says, its pins driven as a machine's HAL file would, and what it
//! does checked on the virtual drive, through our own master and on its output pins.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::vf_s11;
use vfd_runtime::prelude::*;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_tests::linuxcnc::{temp_dir, wait_on_drive, Hal, VirtualPort};

/// The registers a failed wait shows.
const SHOWN: &[&str] = &["FA00", "FA01", "FD00", "FD01"];

fn near(pin: f64, hz: f64) -> bool {
    (pin - hz).abs() < 0.005
}

/// Spindle on forward at 1200 rpm, reverse, off, a trip and its reset, as LinuxCNC drives
/// them: the virtual drive runs at the frequency `vfs11_vfd` computes (1200 rpm x 50 Hz /
/// 1410 rpm = 42.55 Hz), its at-speed, frequency and status pins follow the drive, the
/// frequency limit it reads at start-up is the drive's UL (0012h, 50 Hz), a trip shows on
/// its trip-code pin, its err-reset clears it (FA00 bit 13), and no exchange fails.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn vfs11_vfd_drives_the_vf_s11_virtual_drive() {
    let dir = temp_dir("vfs11-vf-s11");
    // The drive's factory line (9600 bps, even parity; E6581222 section 2), with Modbus RTU
    // chosen (F829 = 1) and station 1, as the component's documentation has the drive set up.
    let settings = SerialSettings {
        baud: 9_600,
        data_bits: 8,
        parity: Parity::Even,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&vf_s11::DRIVE, "modbus", 1, settings);
    {
        let mut sim = drive.simulator.lock();
        assert!(sim.preset("F829", 1));
        assert!(sim.preset("F802", 1));
        // Ramps of 1 s (ACC and DEC in 0.1 s), so that the run takes seconds, not tens.
        assert!(sim.preset("ACC", 10));
        assert!(sim.preset("DEC", 10));
    }
    std::fs::write(
        dir.join("vfs11.ini"),
        format!(
            "[VFS11]\nDEVICE={}\nTYPE=rtu\nBAUD=9600\nBITS=8\nPARITY=even\nSTOPBITS=1\nTARGET=1\nPOLLCYCLES=10\nRECONNECT_DELAY=1\n",
            drive.path
        ),
    )
    .expect("ini");
    let mut hal = Hal::start(&dir);
    hal.run("loadusr -Wn spindle vfs11_vfd -n spindle -I vfs11.ini");
    hal.wait_for_pin("spindle.enable", Duration::from_secs(10));

    // At start-up it reads UL (0012h): 50 Hz, the factory value the description gives.
    hal.wait_for("spindle.frequency-limit", Duration::from_secs(10), |v| {
        v.parse::<f64>().is_ok_and(|hz| near(hz, 50.0))
    });
    // max-rpm = UL x nameplate-RPM / nameplate-HZ = 50 x 1410 / 50.
    assert!(
        (hal.number("spindle.max-rpm") - 1410.0).abs() < 0.01,
        "max-rpm {}",
        hal.getp("spindle.max-rpm")
    );

    // Spindle on, forward, 1200 rpm.
    hal.setp("spindle.enable", 1);
    hal.setp("spindle.speed-command", 1200);
    hal.setp("spindle.spindle-on", 1);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running forward at 42.55 Hz",
        Duration::from_secs(15),
        |sim| sim.is_running() && sim.raw("FD00") == Some(4255),
    );
    // Command and frequency priority, run, forward. Bit 6 (acceleration pattern 2) is left
    // out of the comparison: Debian's vfs11_vfd (2.9.0~pre1) sets it whatever its
    // acceleration-pattern pin says (it tests the pin's pointer, not its value; LinuxCNC's
    // later getter/setter rewrite reads the value).
    let word = drive.simulator.lock().raw("FA00").unwrap_or(0);
    assert_eq!(
        word & !0x0040,
        0xC400,
        "FA00 = {word:04X}h: command and frequency priority, run, forward"
    );
    // Our own master reads the same from the drive.
    let mut master = drive.simulator.master(&vf_s11::protocols::MODBUS);
    use vf_s11::registers::{FrequencyCommand, OutputFrequency, Status};
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(42.55));
    assert_eq!(master.read::<FrequencyCommand>().unwrap(), Hertz(42.55));
    let status = master.read::<Status>().unwrap();
    assert!(status.running() && !status.reverse() && !status.tripped());
    // The component's pins agree.
    hal.wait_for("spindle.at-speed", Duration::from_secs(10), |v| v == "TRUE");
    // at-speed means within 1 % of the command (vfs11_vfd's speed-tolerance), so the cycle
    // that set it may have read the drive a step short of 42.55 Hz: the pin is waited on.
    hal.wait_for("spindle.frequency-out", Duration::from_secs(5), |v| {
        v.parse::<f64>().is_ok_and(|hz| near(hz, 42.55))
    });
    assert!(near(hal.number("spindle.frequency-command"), 42.55));
    assert!(!hal.bit("spindle.is-stopped"));
    hal.wait_for("spindle.status", Duration::from_secs(5), |v| {
        v.parse::<i64>()
            .is_ok_and(|s| s & 0x0400 != 0 && s & 0x0200 == 0)
    });

    // Reverse: spindle-fwd off (the component derives spindle-rev from it). FD00 is a
    // magnitude that read 42.55 Hz before the reversal too, and FD01's reverse bit follows
    // the command while the output still ramps through zero: the output itself is waited on.
    hal.setp("spindle.spindle-fwd", 0);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running in reverse at 42.55 Hz",
        Duration::from_secs(15),
        |sim| {
            sim.raw("FA00").is_some_and(|w| w & !0x0040 == 0xC600)
                && (sim.output() + 42.55).abs() < 1e-6
                && sim.raw("FD00") == Some(4255)
                && sim.raw("FD01").is_some_and(|s| s & 0x0600 == 0x0600)
        },
    );
    assert!(master.read::<Status>().unwrap().reverse());
    hal.wait_for("spindle.status", Duration::from_secs(5), |v| {
        v.parse::<i64>().is_ok_and(|s| s & 0x0600 == 0x0600)
    });
    hal.wait_for("spindle.at-speed", Duration::from_secs(10), |v| v == "TRUE");
    assert!(hal.bit("spindle.spindle-rev"));

    // Off: the drive ramps down and stops.
    hal.setp("spindle.spindle-on", 0);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "stopped",
        Duration::from_secs(15),
        |sim| !sim.is_running() && sim.raw("FD00") == Some(0),
    );
    assert_eq!(drive.simulator.lock().raw("FA00").unwrap_or(0) & 0x0400, 0);
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
    hal.wait_for("spindle.is-stopped", Duration::from_secs(5), |v| {
        v == "TRUE"
    });
    assert!(!hal.bit("spindle.at-speed"));

    // A trip on the drive shows on the trip-code pin; err-reset clears it.
    drive.simulator.inject_trip(0x18);
    hal.wait_for("spindle.trip-code", Duration::from_secs(5), |v| v == "24");
    hal.wait_for("spindle.status", Duration::from_secs(5), |v| {
        v.parse::<i64>().is_ok_and(|s| s & 0x0002 != 0)
    });
    hal.setp("spindle.err-reset", 1);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "reset",
        Duration::from_secs(10),
        |sim| sim.raw("FC90") == Some(0) && sim.raw("FD01").is_some_and(|s| s & 0x0002 == 0),
    );
    hal.wait_for("spindle.trip-code", Duration::from_secs(5), |v| v == "0");
    assert_eq!(drive.simulator.lock().raw("FE10"), Some(0x18));

    // No exchange failed over the whole run.
    assert_eq!(
        hal.getp("spindle.error-count"),
        "0",
        "halrun's log:\n{}",
        hal.log_text()
    );
    assert!(hal.bit("spindle.modbus-ok"));
}
