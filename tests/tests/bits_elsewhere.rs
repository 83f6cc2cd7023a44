//! Behaviour bits held by registers of their own (drives/README.md, "A bit need not be in
//! its role's word"): the made-up `fixtures/bits-elsewhere/finch_f3.yaml` takes its run,
//! direction and fault-reset commands in three registers and shows its states in a status
//! word and in two coils, as the GS2 and the WJ200 do. Its virtual drive is driven over
//! Modbus by a master writing each register on its own.

use std::time::Duration;
use vfd_runtime::virtual_drive::Simulator;

vfd_macros::include_drive!(
    "fixtures/bits-elsewhere/finch_f3.yaml",
    protocols = "../drives/protocols"
);

const ON: u32 = 0xFF00;

#[test]
fn a_direction_register_reverses_a_drive_run_by_its_run_register() {
    let sim = Simulator::new(&finch_f3::DRIVE);
    let mut master = sim.master(&finch_f3::protocols::MODBUS);
    master.write_words(0x0203, &[400]).expect("40.0 Hz");
    master.write_words(0x0200, &[1]).expect("run");
    sim.advance(Duration::from_secs(2));
    {
        let drive = sim.lock();
        assert!(drive.is_running());
        assert_eq!(drive.raw("S01"), Some(400), "40.0 Hz forward");
        assert_eq!(drive.raw("S00"), Some(0b11), "state 11: run");
        assert_eq!(
            drive.raw("C0F"),
            Some(ON),
            "the operation-status coil is on"
        );
        assert_eq!(drive.raw("C10"), Some(0), "forward");
    }
    // The direction register alone reverses the running drive.
    master.write_words(0x0201, &[1]).expect("reverse");
    sim.advance(Duration::from_secs(5));
    {
        let drive = sim.lock();
        assert!(drive.is_running());
        assert_eq!(drive.raw("S01"), Some(400), "40.0 Hz in reverse");
        assert_eq!(
            drive.raw("C10"),
            Some(ON),
            "the rotation-direction coil is on"
        );
    }
    master.write_words(0x0200, &[0]).expect("stop");
    sim.advance(Duration::from_secs(5));
    let drive = sim.lock();
    assert!(!drive.is_running());
    assert_eq!(drive.raw("S00"), Some(0));
    assert_eq!(
        drive.raw("C0F"),
        Some(0),
        "the operation-status coil is off"
    );
}

#[test]
fn a_reset_register_clears_a_trip_on_its_rising_edge() {
    let sim = Simulator::new(&finch_f3::DRIVE);
    let mut master = sim.master(&finch_f3::protocols::MODBUS);
    sim.lock().inject_trip(7);
    assert_eq!(sim.lock().raw("S00"), Some(0b100), "fault");
    assert_eq!(sim.lock().raw("S02"), Some(7));
    master.write_words(0x0202, &[1]).expect("reset");
    assert_eq!(sim.lock().trip(), None, "the rising edge resets");
    assert_eq!(sim.lock().raw("S02"), Some(0));
    // Still 1: no edge, so a second trip stays until the register falls and rises again.
    sim.lock().inject_trip(9);
    master.write_words(0x0202, &[1]).expect("still 1");
    assert_eq!(sim.lock().trip(), Some(9));
    master.write_words(0x0202, &[0]).expect("back to 0");
    master.write_words(0x0202, &[1]).expect("reset again");
    assert_eq!(sim.lock().trip(), None);
}

/// A Modbus frame with its CRC appended.
fn frame(body: &[u8]) -> Vec<u8> {
    let crc = vfd_runtime::checksum::compute(vfd_runtime::ChecksumAlgorithm::Crc16Modbus, body);
    let mut bytes = body.to_vec();
    bytes.extend_from_slice(&(crc as u16).to_le_bytes());
    bytes
}

#[test]
fn a_read_of_status_coils_answers_one_bit_per_coil() {
    use vfd_runtime::virtual_drive::{Outcome, VirtualDrive};
    let mut drive = VirtualDrive::new(&finch_f3::DRIVE);
    drive.set_address(1);
    let modbus = &finch_f3::protocols::MODBUS;
    // Run in reverse: both status coils (0Fh operation, 10h direction) are on.
    drive.respond(modbus, &frame(&[1, 0x06, 0x02, 0x03, 0x01, 0x90]));
    drive.respond(modbus, &frame(&[1, 0x06, 0x02, 0x01, 0x00, 0x01]));
    drive.respond(modbus, &frame(&[1, 0x06, 0x02, 0x00, 0x00, 0x01]));
    drive.advance(Duration::from_secs(5));
    // Function 01, two coils from 000Fh: one data byte, bits 0 and 1.
    assert_eq!(
        drive.respond(modbus, &frame(&[1, 0x01, 0x00, 0x0F, 0x00, 0x02])),
        Outcome::Reply(frame(&[1, 0x01, 0x01, 0b11])),
    );
    // One coil: one byte, bit 0.
    assert_eq!(
        drive.respond(modbus, &frame(&[1, 0x01, 0x00, 0x10, 0x00, 0x01])),
        Outcome::Reply(frame(&[1, 0x01, 0x01, 0b1])),
    );
    // A coil the drive lacks in the range: illegal data address.
    assert_eq!(
        drive.respond(modbus, &frame(&[1, 0x01, 0x00, 0x0F, 0x00, 0x03])),
        Outcome::Reply(frame(&[1, 0x81, 0x02])),
    );
}
