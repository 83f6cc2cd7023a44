//! LinuxCNC's `mitsub_vfd` (written for the Mitsubishi A500/F500/E500/D700/E700/F700
//! inverters), unmodified, as the independent computer-link master of the FR-E700's virtual
//! drive (drives/fr-e700.yaml): loaded as its man page says (`--port`, `--baud 9600`,
//! `spindle=01`), with the inverter set as its help text asks (Pr. 117 = 1, Pr. 118 = 96,
//! Pr. 119 = 1, Pr. 120 = 0: 9600 bps 8N2; Pr. 124 = 0: frames without CR/LF), its pins
//! driven as a machine's HAL file would, and what it does checked on the virtual drive,
//! through our own master and on its output pins.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::fr_e700;
use vfd_runtime::prelude::*;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_tests::linuxcnc::{temp_dir, wait_on_drive, Hal, VirtualPort};

/// The registers a failed wait shows.
const SHOWN: &[&str] = &["H6D-HED", "H6F", "H7A", "H74"];

/// Spindle on forward at 30 Hz, reverse, off, a trip and an emergency stop, as LinuxCNC
/// drives them: the virtual drive runs at the frequency `mitsub_vfd` writes with HED
/// (0.01 Hz), in the direction of HFA's 02 / 04, the component's up-to-speed and
/// motor-fb pins follow H7A bit 3 and H6F, a trip shows on its alarm pin (H7A bit 7), and
/// no exchange raises an error in the component. Its reset after an emergency stop is
/// HFD without data, which the drive refuses (HB): the trip stays.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn mitsub_vfd_drives_the_fr_e700_virtual_drive() {
    let dir = temp_dir("mitsub");
    let settings = SerialSettings {
        baud: 9_600,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 2,
    };
    let drive = VirtualPort::serve(&fr_e700::DRIVE, "link", 1, settings);
    for (parameter, value) in [
        ("Pr.117", 1),
        ("Pr.118", 96),
        ("Pr.119", 1),
        ("Pr.120", 0),
        ("Pr.124", 0),
    ] {
        assert!(
            drive.simulator.lock().preset(parameter, value),
            "{parameter}"
        );
    }
    let mut hal = Hal::start(&dir);
    hal.run(&format!(
        "loadusr -Wn spindle mitsub_vfd --port {} --baud 9600 spindle=01",
        drive.path
    ));
    hal.wait_for_pin("spindle.run", Duration::from_secs(10));
    let pin = |name: &str| format!("spindle.{name}");
    hal.setp(&pin("monitor"), 1);

    // Spindle on, forward (the fwd pin's default), at 30 Hz: HED = 3000, HFA = 02.
    hal.setp(&pin("motor-cmd"), 30);
    hal.setp(&pin("run"), 1);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running forward at 30.00 Hz",
        Duration::from_secs(20),
        |sim| sim.is_running() && sim.raw("H6F") == Some(3000) && sim.raw("H7A") == Some(0x0B),
    );
    assert_eq!(drive.simulator.lock().raw("H6D-HED"), Some(3000));
    // Our own master, set for frames without CR/LF as Pr. 124 = 0 says, reads the same.
    let link: &'static _ = Box::leak(Box::new(
        fr_e700::protocols::LINK
            .variant("none")
            .expect("variant none"),
    ));
    let mut master = drive.simulator.master(link);
    use fr_e700::registers::{InverterStatus, OutputFrequency, SetFrequencyRam};
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(30.0));
    assert_eq!(master.read::<SetFrequencyRam>().unwrap(), Hertz(30.0));
    let status = master.read::<InverterStatus>().unwrap();
    assert!(status.running() && status.forward() && status.up_to_frequency());
    // The component's pins agree: up to speed, 30 Hz fed back, no alarm.
    hal.wait_for(&pin("up-to-speed"), Duration::from_secs(10), |v| {
        v == "TRUE"
    });
    hal.wait_for(&pin("motor-fb"), Duration::from_secs(10), |v| {
        v.parse::<f64>().is_ok_and(|hz| (hz - 30.0).abs() < 0.005)
    });
    assert!(!hal.bit(&pin("alarm")));

    // Reverse: HFA = 04. H7A reads 0Dh (running, reverse, up to frequency) as soon as the
    // command says reverse, the output still at +30 Hz, and H6F is a magnitude: the output
    // itself is waited on.
    hal.setp(&pin("fwd"), 0);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running in reverse at 30.00 Hz",
        Duration::from_secs(20),
        |sim| {
            sim.raw("H7A") == Some(0x0D)
                && (sim.output() + 30.0).abs() < 1e-6
                && sim.raw("H6F") == Some(3000)
        },
    );
    hal.wait_for(&pin("stat-bit-2"), Duration::from_secs(10), |v| v == "TRUE");
    hal.wait_for(&pin("up-to-speed"), Duration::from_secs(10), |v| {
        v == "TRUE"
    });
    assert!(!hal.bit(&pin("stat-bit-1")));

    // Off: HFA = 00, the drive ramps down and stops.
    hal.setp(&pin("run"), 0);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "stopped",
        Duration::from_secs(20),
        |sim| !sim.is_running() && sim.raw("H6F") == Some(0) && sim.raw("H7A") == Some(0),
    );
    hal.wait_for(&pin("motor-fb"), Duration::from_secs(10), |v| {
        v.parse::<f64>().is_ok_and(|hz| hz == 0.0)
    });
    assert!(!hal.bit(&pin("up-to-speed")));

    // A trip: H7A bit 7 shows on the alarm pin, the code in H74's low byte.
    drive.simulator.inject_trip(0x10);
    hal.wait_for(&pin("alarm"), Duration::from_secs(10), |v| v == "TRUE");
    assert_eq!(
        drive.simulator.lock().raw("H74").map(|w| w & 0xFF),
        Some(0x10)
    );

    // The emergency stop cycle: the estop pin's rise makes mitsub_vfd send its reset, HFD
    // without the data H9696: the drive refuses it (a read of no instruction, HB) and stays
    // tripped; its fall sends HFA = 00. The component looks at the pin once a cycle (five
    // monitor exchanges of at least 50 ms each): each edge is waited on in what it prints
    // once it has sent its frame, not slept through.
    hal.setp(&pin("estop"), 1);
    hal.wait_for_log("Estop cleared", Duration::from_secs(10));
    hal.setp(&pin("estop"), 0);
    hal.wait_for_log("stopped due to Estop Signal", Duration::from_secs(10));
    // A new speed goes out with HED after both frames, and the drive takes frames in order:
    // once it holds the speed, it has taken the HFD.
    hal.setp(&pin("motor-cmd"), 20);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "HED 20.00 Hz, sent after the emergency stop cycle",
        Duration::from_secs(10),
        |sim| sim.raw("H6D-HED") == Some(2000),
    );
    assert!(drive.simulator.lock().trip().is_some());
    hal.wait_for(&pin("alarm"), Duration::from_secs(10), |v| v == "TRUE");

    // No exchange raised an error in the component (it prints "error" and its names when
    // one does; it has no error counter).
    let log = hal.log_text();
    assert!(!log.contains("error ["), "halrun's log:\n{log}");
}
