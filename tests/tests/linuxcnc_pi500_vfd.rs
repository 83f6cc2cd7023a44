//! LinuxCNC's `pi500_vfd` (written for the Powtran PI500), unmodified, as the independent
//! Modbus master of the PI500's virtual drive (drives/pi500.yaml): loaded as its man page
//! and source say (`device`, `baud`; 8N1, the drive's F9.01 = 3), its pins driven as a
//! machine's HAL file would, and what it does checked on the virtual drive, through our own
//! master and on its output pins.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::pi500;
use vfd_runtime::prelude::*;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_tests::linuxcnc::{temp_dir, wait_on_drive, Hal, VirtualPort};

/// The registers a failed wait shows.
const SHOWN: &[&str] = &["F0.01", "1001H", "3000H", "8000H"];

/// Spindle on at 30 Hz, reversed by our own master, off, a trip and its reset, as LinuxCNC
/// drives them: the virtual drive runs at the frequency `pi500_vfd` writes to F0.01 (x100,
/// F0.02 = 2), the component's running, at-speed, ready and current pins follow 3000H,
/// 1001H and 1004H, a trip shows on its alarm pin (8000H not 0) and its enable pin resets
/// it (2000H = 7), and no Modbus exchange fails.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn pi500_vfd_drives_the_pi500_virtual_drive() {
    let dir = temp_dir("pi500");
    // pi500_vfd's default line, 9600 bps 8N1: the drive's F9.00 factory value (9600 bps)
    // with F9.01 = 3 (<8,N,1>), station 1 (F9.02's factory value).
    let settings = SerialSettings {
        baud: 9_600,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&pi500::DRIVE, "modbus", 1, settings);
    assert!(drive.simulator.lock().preset("F9.01", 3));
    let mut hal = Hal::start(&dir);
    hal.run(&format!(
        "loadusr -Wn pi500_vfd pi500_vfd --device {} --baud 9600",
        drive.path
    ));
    hal.wait_for_pin("pi500-vfd.0.run", Duration::from_secs(10));
    let pin = |name: &str| format!("pi500-vfd.0.{name}");
    hal.setp(&pin("mbslaveaddr"), 1);
    hal.setp(&pin("enable"), 1);
    // Stopped and ready: 3000H = 3.
    hal.wait_for(&pin("is-ready"), Duration::from_secs(10), |v| v == "TRUE");
    assert!(!hal.bit(&pin("is-running")));

    // Spindle on at 30 Hz: 2000H = 1, F0.01 = 3000 (0.01 Hz, F0.02 = 2).
    hal.setp(&pin("commanded-frequency"), 30);
    hal.setp(&pin("run"), 1);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running forward at 30.00 Hz",
        Duration::from_secs(20),
        |sim| sim.is_running() && sim.raw("1001H") == Some(3000) && sim.raw("3000H") == Some(1),
    );
    assert_eq!(drive.simulator.lock().raw("F0.01"), Some(3000));
    // Our own master reads the same from the drive.
    let mut master = drive.simulator.master(&pi500::protocols::MODBUS);
    use pi500::registers::{FrequencySetting, InverterState, OutputCurrent, RunningFrequency};
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(30.0));
    assert_eq!(master.read::<FrequencySetting>().unwrap(), Hertz(30.0));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        pi500::codes::InverterState::ForwardRunning
    );
    // The component's pins agree: running, at speed, the current of 1004H (3.00 A at
    // 30 Hz in the model, 5.00 A at 50 Hz).
    hal.wait_for(&pin("is-at-speed"), Duration::from_secs(10), |v| {
        v == "TRUE"
    });
    assert!(hal.bit(&pin("is-running")));
    assert!(!hal.bit(&pin("is-ready")));
    assert_eq!(master.read::<OutputCurrent>().unwrap(), Amperes(3.0));
    hal.wait_for(&pin("motor-current"), Duration::from_secs(5), |v| {
        v.parse::<f64>().is_ok_and(|a| (a - 3.0).abs() < 0.005)
    });

    // pi500_vfd has no direction pin (it writes 1 or 6 only); our master reverses the
    // drive (2000H = 2): 3000H reads 2, and the component still sees it running at speed.
    // 3000H says reverse as soon as the command does and 1001H is a magnitude that read
    // 30.00 Hz before the reversal too: the output itself is waited on.
    use pi500::registers::ControlCommand;
    master
        .write_ram::<ControlCommand>(pi500::codes::ControlCommand::ReverseRun)
        .unwrap();
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running in reverse at 30.00 Hz",
        Duration::from_secs(20),
        |sim| {
            sim.raw("3000H") == Some(2)
                && (sim.output() + 30.0).abs() < 1e-6
                && sim.raw("1001H") == Some(3000)
        },
    );
    hal.wait_for(&pin("is-at-speed"), Duration::from_secs(10), |v| {
        v == "TRUE"
    });
    assert!(hal.bit(&pin("is-running")));

    // Off: 2000H = 6, the drive ramps down and stands by.
    hal.setp(&pin("run"), 0);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "stopped",
        Duration::from_secs(20),
        |sim| !sim.is_running() && sim.raw("1001H") == Some(0) && sim.raw("3000H") == Some(3),
    );
    hal.wait_for(&pin("is-ready"), Duration::from_secs(5), |v| v == "TRUE");
    assert!(!hal.bit(&pin("is-running")));
    assert!(!hal.bit(&pin("is-at-speed")));

    // A trip: with enable off the component leaves it standing (it resets a trip as soon
    // as it sees one while enabled), the alarm pin shows it; enable on resets it (2000H = 7).
    hal.setp(&pin("enable"), 0);
    drive.simulator.inject_trip(0x0E);
    hal.wait_for(&pin("is-alarm"), Duration::from_secs(5), |v| v == "TRUE");
    assert_eq!(drive.simulator.lock().raw("3000H"), Some(4));
    assert_eq!(drive.simulator.lock().raw("8000H"), Some(0x0E));
    assert!(!hal.bit(&pin("is-ready")) && !hal.bit(&pin("is-running")));
    hal.setp(&pin("enable"), 1);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "reset",
        Duration::from_secs(10),
        |sim| sim.trip().is_none() && sim.raw("8000H") == Some(0) && sim.raw("3000H") == Some(3),
    );
    hal.wait_for(&pin("is-alarm"), Duration::from_secs(5), |v| v == "FALSE");
    hal.wait_for(&pin("is-ready"), Duration::from_secs(5), |v| v == "TRUE");

    // No exchange failed over the whole run: the component has no error counter, it logs
    // each failure ("failed to get status", "... to set frequency", "... to run", "... to
    // reset"); "failed to trip" is its word for being disabled without a trip, not an
    // exchange.
    let log = hal.log_text();
    for failure in [
        "failed to get status",
        "failed to set frequency",
        "failed to run",
        "failed to reset",
    ] {
        assert!(!log.contains(failure), "{failure}: halrun's log:\n{log}");
    }
}
