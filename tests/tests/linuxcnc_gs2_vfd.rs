//! LinuxCNC's `gs2_vfd` (hal/user_comps/gs2_vfd.c), unmodified, as an independent master of
//! the AutomationDirect GS2's virtual drive built from drives/gs2.yaml: it writes the speed
//! reference P9.26, RUN P9.27, direction P9.28 and fault reset P9.30 one register at a time,
//! and reads the status addresses 2100h-210Ch in one request.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::gs2::registers::{OutputFrequency, RunCommand, SpeedReference};
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::units::Hertz;
use vfd_tests::linuxcnc::{temp_dir, wait_on_drive, Hal, VirtualPort};

const LIMIT: Duration = Duration::from_secs(20);

/// Waits until the virtual drive holds `raw` in `register`.
fn wait_raw(sim: &vfd_runtime::virtual_drive::Simulator, register: &str, raw: u32) {
    let end = std::time::Instant::now() + LIMIT;
    while sim.lock().raw(register) != Some(raw) {
        assert!(
            std::time::Instant::now() < end,
            "{register} never became {raw}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Spindle on forward at 1200 rpm (40 Hz with a 60 Hz, 1800 rpm motor), reverse, off, a trip
/// and its reset, as a machine's HAL file drives the component's pins.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn gs2_vfd_runs_reverses_stops_and_resets_the_gs2_virtual_drive() {
    let dir = temp_dir("gs2");
    let settings = SerialSettings {
        baud: 19_200,
        data_bits: 8,
        parity: Parity::Even,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&vfd_drives::gs2::DRIVE, "modbus", 1, settings);
    let sim = &drive.simulator;
    let mut hal = Hal::start(&dir);
    // As gs2_vfd(1) says: device, rate, parity, target; one-second ramps (-A, -D).
    hal.run(&format!(
        "loadusr -Wn spindle gs2_vfd -n spindle -d {} -r 19200 -p even -t 1 -A 1 -D 1",
        drive.path
    ));
    hal.wait_for_pin("spindle.speed-command", LIMIT);
    let log = |hal: &Hal| hal.log_text();
    // The start-up writes: acceleration and deceleration 1.0 s, ramp to stop.
    hal.wait_for("spindle.initialized", LIMIT, |v| v == "TRUE");
    assert_eq!(sim.lock().raw("P1.01"), Some(10), "{}", log(&hal));
    assert_eq!(sim.lock().raw("P1.02"), Some(10));
    assert_eq!(sim.lock().raw("P1.00"), Some(0), "ramp to stop");

    hal.setp("spindle.nameplate-HZ", 60);
    hal.setp("spindle.nameplate-RPM", 1800);
    hal.setp("spindle.spindle-fwd", 1);
    // gs2_vfd writes RUN only when spindle-on changes, and starts from "changed to on" (its
    // old_run = -1, true as a HAL bit): a first cycle must see the spindle off, as a
    // machine's does at start-up. The speed reference, written first in every cycle, shows
    // when a second cycle (after one with the spindle off) has begun.
    hal.setp("spindle.speed-command", 1203);
    wait_raw(sim, "P9.26", 401);
    hal.setp("spindle.speed-command", 1206);
    wait_raw(sim, "P9.26", 402);
    hal.setp("spindle.speed-command", 1200);
    hal.setp("spindle.spindle-on", 1);
    hal.wait_for("spindle.frequency-out", LIMIT, |v| v.parse() == Ok(40.0));
    // The pin shows 2103h in 0.1 Hz: it reads 40.0 from 39.95 Hz on, while the drive may
    // still be a step short of 40 Hz; the drive itself is waited on.
    wait_on_drive(
        &hal,
        &drive,
        &["P9.27", "2103h"],
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
        assert_eq!(d.raw("P9.26"), Some(400));
        assert_eq!(d.raw("P9.27"), Some(1));
        assert_eq!(d.raw("P9.28"), Some(0));
    }
    // Our own master reads what the component wrote and what the drive shows.
    let mut master = sim.master(&vfd_drives::gs2::protocols::MODBUS);
    assert_eq!(master.read::<SpeedReference>().unwrap(), Hertz(40.0));
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(40.0));
    assert!(master.read::<RunCommand>().unwrap().run());
    hal.wait_for("spindle.at-speed", LIMIT, |v| v == "TRUE");
    assert_eq!(hal.number("spindle.frequency-command"), 40.0);
    assert!(!hal.bit("spindle.is-stopped"));
    assert_eq!(
        hal.number("spindle.status-2") as u32 & 0x1F,
        0b00011,
        "run, forward"
    );

    // Reverse: P9.28 = 1; the drive ramps through 0 to 40 Hz the other way.
    hal.setp("spindle.spindle-fwd", 0);
    hal.wait_for("spindle.status-2", LIMIT, |v| {
        v.parse::<u32>().is_ok_and(|s| s & 0x1F == 0b11011)
    });
    // The status says reverse as soon as the command does, while the output still ramps
    // through zero; frequency-out is a magnitude and read 40 before the reversal too, so
    // the drive itself is waited on.
    wait_on_drive(
        &hal,
        &drive,
        &["P9.28", "2103h"],
        "reverse at 40 Hz",
        LIMIT,
        |d| (d.output() + 40.0).abs() < 1e-9,
    );
    assert_eq!(sim.lock().raw("P9.28"), Some(1));
    hal.wait_for("spindle.frequency-out", LIMIT, |v| v.parse() == Ok(40.0));
    assert!(
        hal.bit("spindle.spindle-rev"),
        "the component's own reverse pin"
    );

    // Off: P9.27 = 0; the drive ramps down and stops.
    hal.setp("spindle.spindle-on", 0);
    hal.wait_for("spindle.is-stopped", LIMIT, |v| v == "TRUE");
    // is-stopped is 2103h reading 0, from under 0.05 Hz on; the drive is waited on to stop.
    wait_on_drive(&hal, &drive, &["P9.27", "2103h"], "stopped", LIMIT, |d| {
        !d.is_running()
    });
    assert_eq!(sim.lock().raw("P9.27"), Some(0));
    assert!(!hal.bit("spindle.at-speed"));

    // A trip shows as its code in status monitor 1; err-reset clears it through P9.30.
    sim.inject_trip(6);
    hal.wait_for("spindle.status-1", LIMIT, |v| v == "6");
    hal.setp("spindle.err-reset", 1);
    hal.wait_for("spindle.status-1", LIMIT, |v| v == "0");
    assert_eq!(sim.lock().trip(), None);
    hal.setp("spindle.err-reset", 0);

    assert_eq!(
        hal.getp("spindle.error-count"),
        "0",
        "no failed exchange\n{}",
        log(&hal)
    );
}
