//! LinuxCNC's `vfdb_vfd` (hal/user_comps/vfdb_vfd/vfdb_vfd.c), unmodified, as an independent
//! master of the Delta VFD-B's virtual drive built from drives/vfd-b.yaml: every cycle it
//! writes the command word 2000H (run or stop, forward or reverse) and the frequency command
//! 2001H, and reads 2100H (error code), 2101H (status) and 2103H (output frequency); it reads
//! 01-00 (0100H) once at start-up.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::vfd_b::registers::{Command, FrequencyCommand, OutputFrequency};
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::units::Hertz;
use vfd_tests::linuxcnc::{temp_dir, wait_on_drive, Hal, VirtualPort};

const LIMIT: Duration = Duration::from_secs(20);

/// Spindle on forward at 1200 rpm (40 Hz with a 60 Hz, 1800 rpm motor), reverse (a negative
/// speed command), off, and a trip shown on the error-code pin.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn vfdb_vfd_runs_reverses_stops_and_sees_a_trip_of_the_vfd_b_virtual_drive() {
    let dir = temp_dir("vfdb");
    let settings = SerialSettings {
        baud: 19_200,
        data_bits: 8,
        parity: Parity::Even,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&vfd_drives::vfd_b::DRIVE, "modbus", 1, settings);
    let sim = &drive.simulator;
    // One-second ramps over 60 Hz, as a spindle set-up would set 01-09 and 01-10.
    let mut master = sim.master(&vfd_drives::vfd_b::protocols::MODBUS);
    master.write_words(0x0109, &[10]).expect("01-09 = 1.0 s");
    master.write_words(0x010A, &[10]).expect("01-10 = 1.0 s");
    std::fs::write(
        dir.join("vfdb.ini"),
        format!(
            "[VFD-B]\nDEVICE={}\nTYPE=rtu\nBAUD=19200\nBITS=8\nPARITY=even\nSTOPBITS=1\nTARGET=1\nPOLLCYCLES=10\nRECONNECT_DELAY=1\nMOTOR_HZ=60\nMOTOR_RPM=1800\n",
            drive.path
        ),
    )
    .expect("ini");
    let mut hal = Hal::start(&dir);
    hal.run("loadusr -Wn spindle vfdb_vfd -n spindle -I vfdb.ini");
    hal.wait_for_pin("spindle.enable", LIMIT);
    hal.wait_for("spindle.frequency-limit", LIMIT, |v| v.parse() == Ok(60.0));
    hal.setp("spindle.enable", 1);
    hal.setp("spindle.speed-command", 1200);
    hal.setp("spindle.spindle-on", 1);
    hal.wait_for("spindle.frequency-out", LIMIT, |v| v.parse() == Ok(40.0));
    // The pin shows 2103H in 0.01 Hz: it reads 40.00 from 39.995 Hz on, while the drive
    // may still be a step short of 40 Hz; the drive itself is waited on.
    wait_on_drive(
        &hal,
        &drive,
        &["2000H", "2103H"],
        "forward at 40 Hz",
        LIMIT,
        |d| (d.output() - 40.0).abs() < 1e-9,
    );
    {
        let d = sim.lock();
        assert!(d.is_running());
        assert!(
            (d.output() - 40.0).abs() < 1e-9,
            "forward at 40 Hz: {}",
            d.output()
        );
        assert_eq!(d.raw("2000H"), Some(0x0012), "run, forward");
        assert_eq!(d.raw("2001H"), Some(4000));
    }
    assert_eq!(master.read::<FrequencyCommand>().unwrap(), Hertz(40.0));
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(40.0));
    assert!(master.read::<Command>().unwrap().run());
    assert_eq!(hal.number("spindle.frequency-command"), 40.0);
    assert!(!hal.bit("spindle.is-stopped"));
    assert_eq!(
        hal.number("spindle.status") as u32 & 0x1F,
        0b00011,
        "run, forward"
    );

    // Reverse: a negative speed command sets REV (bits 5-4 = 10).
    hal.setp("spindle.speed-command", -1200);
    hal.wait_for("spindle.status", LIMIT, |v| {
        v.parse::<u32>().is_ok_and(|s| s & 0x1F == 0b11011)
    });
    // The status bits say reverse as soon as the command does, while the output still ramps
    // through zero; frequency-out is a magnitude and read 40 before the reversal too, so
    // the drive itself is waited on.
    wait_on_drive(
        &hal,
        &drive,
        &["2000H", "2103H"],
        "reverse at 40 Hz",
        LIMIT,
        |d| (d.output() + 40.0).abs() < 1e-9,
    );
    assert_eq!(sim.lock().raw("2000H"), Some(0x0022), "run, reverse");
    hal.wait_for("spindle.frequency-out", LIMIT, |v| v.parse() == Ok(40.0));

    // Off: stop (bits 1-0 = 01); the drive ramps down.
    hal.setp("spindle.spindle-on", 0);
    hal.wait_for("spindle.is-stopped", LIMIT, |v| v == "TRUE");
    // is-stopped is 2103H reading 0, from under 0.005 Hz on; the drive is waited on to stop.
    wait_on_drive(&hal, &drive, &["2000H", "2103H"], "stopped", LIMIT, |d| {
        !d.is_running()
    });
    assert_eq!(sim.lock().raw("2000H"), Some(0x0021), "stop, reverse");

    // A trip shows as its code on error-code; vfdb_vfd has no reset (its source leaves it
    // as a TODO), so our master resets it by 2002H bit 1.
    sim.inject_trip(6);
    hal.wait_for("spindle.error-code", LIMIT, |v| v == "6");
    master.write_words(0x2002, &[0b10]).expect("reset");
    hal.wait_for("spindle.error-code", LIMIT, |v| v == "0");

    assert_eq!(
        hal.getp("spindle.error-count"),
        "0",
        "no failed exchange\n{}",
        hal.log_text()
    );
}
