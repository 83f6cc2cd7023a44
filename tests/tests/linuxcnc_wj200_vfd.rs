//! LinuxCNC's `wj200_vfd` (hal/user_comps/wj200_vfd/wj200_vfd.comp), unmodified, as an
//! independent master of the Hitachi WJ200's virtual drive built from drives/wj200.yaml: it
//! commands the drive by coils (operation 0001h, direction 0002h, external trip 0003h, trip
//! reset 0004h, function 05), writes the frequency to 0002h (function 10h) and reads the
//! status coils 000Fh-0019h (function 01) and registers (function 03).
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::wj200::registers::{FrequencySource, OutputFrequency};
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::units::Hertz;
use vfd_tests::linuxcnc::{temp_dir, Hal, VirtualPort};

const LIMIT: Duration = Duration::from_secs(20);
const ON: u32 = 0xFF00;

/// Run forward at 40 Hz, reverse, stop, and a trip shown on is-alarm and reset through the
/// trip-reset coil when the component is enabled again.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn wj200_vfd_runs_reverses_stops_and_resets_the_wj200_virtual_drive() {
    let dir = temp_dir("wj200");
    let settings = SerialSettings {
        baud: 19_200,
        data_bits: 8,
        parity: Parity::Even,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&vfd_drives::wj200::DRIVE, "modbus", 1, settings);
    let sim = &drive.simulator;
    // One-second ramps over the maximum frequency, as a spindle set-up would set F002/F003.
    let mut master = sim.master(&vfd_drives::wj200::protocols::MODBUS);
    master.write_words(0x1104, &[100]).expect("F002 = 1.00 s");
    master.write_words(0x1106, &[100]).expect("F003 = 1.00 s");
    let mut hal = Hal::start(&dir);
    hal.run(&format!(
        "loadusr -Wn wj200_vfd wj200_vfd --device {} --baud 19200 --parity e",
        drive.path
    ));
    hal.wait_for_pin("wj200-vfd.0.run", LIMIT);
    hal.setp("wj200-vfd.0.enable", 1);
    hal.setp("wj200-vfd.0.commanded-frequency", 40);
    hal.setp("wj200-vfd.0.reverse", 0);
    hal.setp("wj200-vfd.0.mbslaveaddr", 1);
    hal.wait_for("wj200-vfd.0.is-ready", LIMIT, |v| v == "TRUE");

    hal.setp("wj200-vfd.0.run", 1);
    hal.wait_for("wj200-vfd.0.is-at-speed", LIMIT, |v| v == "TRUE");
    assert!(hal.bit("wj200-vfd.0.is-running"));
    {
        let d = sim.lock();
        assert!(d.is_running());
        assert!(
            (d.output() - 40.0).abs() < 1e-9,
            "forward at 40 Hz: {}",
            d.output()
        );
        assert_eq!(d.raw("C0001"), Some(ON));
        assert_eq!(d.raw("C000F"), Some(ON), "operation status");
        assert_eq!(d.raw("C0010"), Some(0), "forward");
    }
    assert_eq!(master.read::<FrequencySource>().unwrap(), Hertz(40.0));
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(40.0));

    // Reverse: the direction coil; the drive ramps through 0 to 40 Hz the other way.
    hal.setp("wj200-vfd.0.reverse", 1);
    let end = std::time::Instant::now() + LIMIT;
    while (sim.lock().output() + 40.0).abs() > 1e-9 {
        assert!(
            std::time::Instant::now() < end,
            "never reached 40 Hz in reverse"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(sim.lock().raw("C0002"), Some(ON));
    assert_eq!(
        sim.lock().raw("C0010"),
        Some(ON),
        "rotation direction: reverse"
    );
    hal.wait_for("wj200-vfd.0.is-at-speed", LIMIT, |v| v == "TRUE");

    // Stop.
    hal.setp("wj200-vfd.0.run", 0);
    hal.wait_for("wj200-vfd.0.is-running", LIMIT, |v| v == "FALSE");
    assert!(!sim.lock().is_running());
    assert_eq!(sim.lock().raw("C0001"), Some(0));

    // Disabled, the component does not reset an alarm (it writes the external-trip coil,
    // which the model does not act on): a trip stays on is-alarm until it is enabled, and
    // then it writes the trip-reset coil.
    hal.setp("wj200-vfd.0.enable", 0);
    let end = std::time::Instant::now() + LIMIT;
    while sim.lock().raw("C0003") != Some(ON) {
        assert!(std::time::Instant::now() < end, "no external-trip write");
        std::thread::sleep(Duration::from_millis(20));
    }
    sim.inject_trip(12);
    hal.wait_for("wj200-vfd.0.is-alarm", LIMIT, |v| v == "TRUE");
    assert_eq!(sim.lock().raw("C0018"), Some(ON), "AL");
    hal.setp("wj200-vfd.0.enable", 1);
    hal.wait_for("wj200-vfd.0.is-alarm", LIMIT, |v| v == "FALSE");
    assert_eq!(sim.lock().trip(), None);
    assert_eq!(
        sim.lock().raw("C0004"),
        Some(ON),
        "reset by the trip-reset coil"
    );

    let log = hal.log_text();
    assert!(!log.contains("failed"), "no failed exchange:\n{log}");
}
