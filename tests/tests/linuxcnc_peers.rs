//! LinuxCNC's hand-written VFD components, unmodified, as independent masters of our
//! virtual drives: each runs under `halrun` against a virtual drive on a pseudo-terminal,
//! configured as its man page says, and its pins are driven as a machine's HAL file would.
//!
//! Needs Debian's `linuxcnc-uspace` (`.ci/run` installs it); without `halrun` these tests are
//! reported ignored with the reason, except under CI, where they fail.

use std::time::Duration;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_tests::linuxcnc::{temp_dir, Hal, VirtualPort};

/// `vfs11_vfd` (written for the Toshiba VF-S11) against the VF-AS1's virtual drive, whose
/// Modbus map shares the command registers: spindle on writes command word 1 (FA00) with
/// the run, command-priority and frequency-priority bits (C400h) and the frequency command
/// (FA01). It stops at UL (0012h), a register the VF-AS1's communication manual does not
/// describe, so only its writes are checked here; the VF-S11's own description is the
/// component's full peer.
#[test]
#[cfg_attr(
    missing_halrun,
    ignore = "LinuxCNC's halrun is not installed (apt-get install linuxcnc-uspace); .ci/run installs it"
)]
fn vfs11_vfd_runs_the_vf_as1_virtual_drive_by_its_command_word() {
    let dir = temp_dir("vfs11-vf-as1");
    let settings = SerialSettings {
        baud: 19_200,
        data_bits: 8,
        parity: Parity::Even,
        stop_bits: 1,
    };
    let drive = VirtualPort::serve(&vfd_drives::vf_as1::DRIVE, "modbus", 1, settings);
    std::fs::write(
        dir.join("vfs11.ini"),
        format!(
            "[VFS11]\nDEVICE={}\nTYPE=rtu\nBAUD=19200\nBITS=8\nPARITY=even\nSTOPBITS=1\nTARGET=1\nPOLLCYCLES=10\nRECONNECT_DELAY=1\n",
            drive.path
        ),
    )
    .expect("ini");
    let mut hal = Hal::start(&dir);
    hal.run("loadusr -Wn spindle vfs11_vfd -n spindle -I vfs11.ini");
    hal.wait_for_pin("spindle.enable", Duration::from_secs(10));
    hal.setp("spindle.enable", 1);
    hal.setp("spindle.speed-command", 1500);
    hal.setp("spindle.spindle-on", 1);
    let end = std::time::Instant::now() + Duration::from_secs(10);
    let word = loop {
        let word = drive.simulator.lock().raw("FA00").unwrap_or(0);
        if word & 0x0400 != 0 || std::time::Instant::now() > end {
            break word;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(
        word & 0xC400,
        0xC400,
        "FA00 = {word:04X}h: command and frequency priority and run\n{}",
        hal.log_text()
    );
}
