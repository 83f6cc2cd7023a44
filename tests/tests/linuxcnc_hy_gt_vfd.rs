//! LinuxCNC's `hy_gt_vfd` (written for the Huanyang GT series), unmodified under `halrun`,
//! as the independent Modbus master of the GT's virtual drive (drives/hy-gt.yaml): loaded
//! as its man page says (38400 bps 8N1 RTU at station 1: PC.01 = 5, PC.02 = 0, PC.00 = 1;
//! P0.01 = 2 and P0.07 = 7 for commands and frequency from the port; PC.03 = 1 ms; `-S`
//! and `-F` matching P2.03 and P0.03), its pins driven as a machine's HAL file would, and
//! what it does checked on the virtual drive, through our own master and on its pins.
//!
//! `hy_gt_vfd` waits 16 ms for a whole reply (libmodbus response time-out, no byte
//! time-out): the virtual drive answers after the frame gap and PC.03's 1 ms.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` the test is
//! reported ignored with the reason, except under CI, where it fails.

use std::time::Duration;
use vfd_drives::hy_gt;
use vfd_runtime::prelude::*;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_tests::linuxcnc::{temp_dir, wait_on_drive, Hal, VirtualPort};

/// The registers a failed wait shows.
const SHOWN: &[&str] = &["1000H", "2000H", "1001H", "3000H", "3005H", "5000H"];

/// The component's pin `name`.
fn pin(name: &str) -> String {
    format!("hy_gt_vfd.{name}")
}

/// CRC-16/Modbus of `frame`, appended low byte first.
fn with_crc(frame: &[u8]) -> Vec<u8> {
    let mut crc: u16 = 0xFFFF;
    for byte in frame {
        crc ^= u16::from(*byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    let mut out = frame.to_vec();
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// No Modbus exchange of the component failed so far.
fn no_errors(hal: &Hal) {
    assert_eq!(
        hal.number(&pin("modbus-errors")),
        0.0,
        "hy_gt_vfd counted failed exchanges\nhalrun's log:\n{}",
        hal.log_text()
    );
}

/// `hy_gt_vfd -S 24000 -F 400 -f 10`: a 24000 rpm spindle at 400 Hz (P2.03 = 24000 at
/// P2.02 = 400.00 Hz, P0.03 = P0.04 = 400.00 Hz). A speed of 12000 rpm is 200 Hz, which it
/// writes to 2000H as 200 / 400 x 10000 = 5000 (50.00 % of P0.03).
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn hy_gt_vfd_runs_stops_and_sees_a_trip_on_the_gt_virtual_drive() {
    let dir = temp_dir("hy_gt");
    let settings = SerialSettings {
        baud: 38_400,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&hy_gt::DRIVE, "modbus", 1, settings);
    {
        // Set on the panel as hy_gt_vfd(1) asks.
        let mut sim = drive.simulator.lock();
        for (code, raw) in [
            ("P0.01", 2),
            ("P0.03", 40_000),
            ("P0.04", 40_000),
            ("P0.05", 1_000),
            ("P0.07", 7),
            ("P2.02", 40_000),
            ("P2.03", 24_000),
            ("PC.01", 5),
            ("PC.02", 0),
            ("PC.03", 1),
        ] {
            assert!(sim.preset(code, raw), "{code} takes {raw}");
        }
    }
    let mut hal = Hal::start(&dir);
    hal.run(&format!(
        "loadusr -Wn hy_gt_vfd hy_gt_vfd -d {} -r 38400 -p none -t 1 -S 24000 -F 400 -f 10",
        drive.path
    ));
    hal.wait_for_pin(&pin("spindle-on"), Duration::from_secs(10));
    // Its start-up reads of every monitor went through; off, it writes 5 (stop) each cycle.
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "commanded to stop",
        Duration::from_secs(10),
        |sim| sim.raw("1000H") == Some(5),
    );
    no_errors(&hal);

    // Spindle on forward at 12000 rpm: 1000H = 1, 2000H = 5000 (50.00 % of 400.00 Hz).
    hal.setp(&pin("speed-cmd"), 12_000);
    hal.setp(&pin("spindle-on"), 1);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running forward at 200.00 Hz",
        Duration::from_secs(20),
        |sim| sim.is_running() && sim.raw("3000H") == Some(20_000) && sim.raw("1001H") == Some(1),
    );
    assert_eq!(drive.simulator.lock().raw("2000H"), Some(5_000));
    assert_eq!(drive.simulator.lock().raw("1000H"), Some(1));
    // Our own master reads the same from the drive.
    let mut master = drive.simulator.master(&hy_gt::protocols::MODBUS);
    use hy_gt::registers::{
        CommunicationSetting, InverterStatus, OperationFrequency, RotationSpeed, SettingFrequency,
    };
    assert_eq!(master.read::<OperationFrequency>().unwrap(), Hertz(200.0));
    assert_eq!(master.read::<SettingFrequency>().unwrap(), Hertz(200.0));
    assert_eq!(
        master.read::<CommunicationSetting>().unwrap(),
        Percent(50.0)
    );
    assert_eq!(master.read::<RotationSpeed>().unwrap(), Rpm(12_000.0));
    assert_eq!(
        master.read::<InverterStatus>().unwrap().value,
        hy_gt::codes::InverterStatus::ForwardRunning
    );
    // The component's pins agree: the frequency it commands and reads back, the speed
    // (3005H) and at-speed (speed within 2 % of its command).
    hal.wait_for(&pin("at-speed"), Duration::from_secs(10), |v| v == "TRUE");
    assert_eq!(hal.number(&pin("freq-cmd")), 200.0);
    hal.wait_for(&pin("freq-fb"), Duration::from_secs(5), |v| {
        v.parse::<f64>().is_ok_and(|hz| (hz - 200.0).abs() < 0.005)
    });
    // speed-fb (3005H) is read after freq-fb (3000H) in the component's cycle.
    hal.wait_for(&pin("speed-fb"), Duration::from_secs(5), |v| v == "12000");
    no_errors(&hal);

    // hy_gt_vfd has no direction: it writes 1 (forward run) every cycle. A reverse run
    // written by another master (1000H = 2, taken here with the drive held so that no
    // frame of the component comes between) turns the drive; the component's next cycle
    // runs it forward again.
    {
        let mut sim = drive.simulator.lock();
        let protocol = hy_gt::DRIVE
            .protocols
            .iter()
            .copied()
            .find(|p| p.id == "modbus")
            .expect("the GT speaks Modbus RTU");
        let reverse = with_crc(&[0x01, 0x06, 0x10, 0x00, 0x00, 0x02]);
        sim.respond(protocol, &reverse);
        assert_eq!(sim.raw("1000H"), Some(2));
        assert_eq!(sim.raw("1001H"), Some(2), "1001H reads reverse running");
    }
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "running forward again at 200.00 Hz",
        Duration::from_secs(20),
        |sim| {
            sim.raw("1000H") == Some(1)
                && sim.raw("1001H") == Some(1)
                && sim.raw("3000H") == Some(20_000)
        },
    );
    hal.wait_for(&pin("at-speed"), Duration::from_secs(10), |v| v == "TRUE");

    // Off: 1000H = 5, the drive ramps down and stands by.
    hal.setp(&pin("spindle-on"), 0);
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "stopped",
        Duration::from_secs(20),
        |sim| !sim.is_running() && sim.raw("3000H") == Some(0) && sim.raw("1001H") == Some(3),
    );
    assert_eq!(drive.simulator.lock().raw("1000H"), Some(5));
    assert!(!hal.bit(&pin("at-speed")));
    assert_eq!(hal.number(&pin("freq-cmd")), 0.0);
    hal.wait_for(&pin("speed-fb"), Duration::from_secs(5), |v| v == "0");

    // A trip: its code shows in 5000H and on the component's fault-info pin (and
    // fault-info-code, from LinuxCNC 2.10); 1001H reads 4. The component has no reset: our
    // master resets it (1000H = 7), and the pin returns to 0.
    drive.simulator.inject_trip(0x0B);
    hal.wait_for(&pin("fault-info"), Duration::from_secs(5), |v| v == "11");
    if hal.has_pin(&pin("fault-info-code")) {
        hal.wait_for(&pin("fault-info-code"), Duration::from_secs(5), |v| {
            v == "11"
        });
    }
    assert_eq!(drive.simulator.lock().raw("1001H"), Some(4));
    assert_eq!(drive.simulator.lock().raw("5000H"), Some(0x0B));
    assert_eq!(
        master.read::<InverterStatus>().unwrap().value,
        hy_gt::codes::InverterStatus::Fault
    );
    use hy_gt::registers::ControlCommand;
    master
        .write_ram::<ControlCommand>(hy_gt::codes::ControlCommand::FaultReset)
        .unwrap();
    wait_on_drive(
        &hal,
        &drive,
        SHOWN,
        "reset",
        Duration::from_secs(10),
        |sim| sim.trip().is_none() && sim.raw("5000H") == Some(0) && sim.raw("1001H") == Some(3),
    );
    hal.wait_for(&pin("fault-info"), Duration::from_secs(5), |v| v == "0");

    // No exchange failed over the whole run.
    no_errors(&hal);
}
