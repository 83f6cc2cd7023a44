//! The virtual drive's answers to faulty requests of the computer-link family, as the
//! descriptions say them: a bad sum check gets the drive's sum-check refusal naming its own
//! station (a read as well as a write), and nothing for another station; data of another
//! width than the register's is a malformed frame, never acted on. Played to the DV1 on
//! its Eaton protocol (`refusals: { eaton: { bad_checksum: 0x02 } }`) and to the made-up
//! Heron HL-7 (tests/fixtures/computer-link), whose byte registers take two data digits
//! and word registers four.

use std::path::Path;
use vfd_drives::dv1;
use vfd_runtime::virtual_drive::{Outcome, VirtualDrive};
use vfd_runtime::{DriveInfo, Protocol};

/// ENQ, `body`, the sum check over it, CR: a computer-link request.
fn request(body: &str) -> Vec<u8> {
    let sum = body.bytes().map(u32::from).sum::<u32>() & 0xFF;
    format!("\x05{body}{sum:02X}\r").into_bytes()
}

/// ENQ, `body`, a sum check of 00 (wrong for every body below), CR.
fn bad_sum(body: &str) -> Vec<u8> {
    format!("\x05{body}00\r").into_bytes()
}

/// What the drive at `station` answers to `frame`, handed over whole and as bytes on the
/// line (the two must agree).
fn answers(drive: &'static DriveInfo, protocol: &Protocol, station: u8, frame: &[u8]) -> Outcome {
    let mut whole = VirtualDrive::new(drive);
    whole.set_address(station);
    let outcome = whole.respond(protocol, frame);
    let mut on_line = VirtualDrive::new(drive);
    on_line.set_address(station);
    let mut input = frame.to_vec();
    let sent: Vec<Vec<u8>> = on_line
        .receive_before_silence(protocol, &mut input)
        .into_iter()
        .map(|t| t.bytes)
        .collect();
    match &outcome {
        Outcome::Reply(bytes) => assert_eq!(sent, vec![bytes.clone()], "{frame:?} on the line"),
        Outcome::Silent(_) => assert!(sent.is_empty(), "{frame:?} on the line: {sent:?}"),
    }
    outcome
}

#[test]
fn a_bad_sum_check_is_refused_naming_the_drives_own_station() {
    let protocol = dv1::protocols::EATON.protocol();
    // A write of 60.00 Hz to the frequency command (EDh) and a read of monitor 5Fh, at
    // station 03: NAK, station 03, error H02 (sum check error), CR.
    for body in ["03ED01770", "035F0"] {
        assert_eq!(
            answers(&dv1::DRIVE, protocol, 3, &bad_sum(body)),
            Outcome::Reply(b"\x15032\r".to_vec()),
            "{body}"
        );
    }
}

#[test]
fn a_bad_sum_check_for_another_station_gets_no_answer() {
    let protocol = dv1::protocols::EATON.protocol();
    for body in ["00ED01770", "005F0"] {
        assert!(
            matches!(
                answers(&dv1::DRIVE, protocol, 3, &bad_sum(body)),
                Outcome::Silent(_)
            ),
            "{body}"
        );
    }
}

#[test]
fn a_bad_sum_check_leaves_the_drive_as_it_was() {
    let protocol = dv1::protocols::EATON.protocol();
    let mut drive = VirtualDrive::new(&dv1::DRIVE);
    drive.set_address(3);
    let before = drive.raw("frequency_command_ram");
    drive.respond(protocol, &bad_sum("03ED01770"));
    assert_eq!(drive.raw("frequency_command_ram"), before);
}

/// The Heron HL-7 fixture, compiled from its file.
fn heron() -> &'static DriveInfo {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/computer-link/heron_hl7.yaml");
    let ir = vfd_codegen::compile(&file, None).expect("the fixture is valid");
    vfd_codegen::drive_info(&ir)
}

#[test]
fn data_of_another_width_than_the_registers_is_never_acted_on() {
    let drive = heron();
    let protocol = drive.protocols[0];
    // (request body, register, raw value it would set): F-30 (motor poles, a byte) with
    // four digits, F-01 (frequency command, a word) with two.
    for (body, register) in [("01F000008", "F-30"), ("01C1011", "F-01")] {
        let mut sim = VirtualDrive::new(drive);
        sim.set_address(1);
        let before = sim.raw(register);
        let outcome = sim.respond(protocol, &request(body));
        assert!(matches!(outcome, Outcome::Silent(_)), "{body}: {outcome:?}");
        assert_eq!(sim.raw(register), before, "{body} changed {register}");
        assert!(matches!(
            answers(drive, protocol, 1, &request(body)),
            Outcome::Silent(_)
        ));
    }
    // The page register is a byte too: a page switch with four digits does not switch.
    let mut sim = VirtualDrive::new(drive);
    sim.set_address(1);
    let outcome = sim.respond(protocol, &request("01FF00001"));
    assert!(matches!(outcome, Outcome::Silent(_)), "{outcome:?}");
    assert_eq!(sim.page(protocol), Some(0));
}

#[test]
fn data_of_the_registers_width_is_taken() {
    let drive = heron();
    let protocol = drive.protocols[0];
    let mut sim = VirtualDrive::new(drive);
    sim.set_address(1);
    for (body, register, raw) in [("01F0007", "F-30", 7), ("01C101194", "F-01", 0x1194)] {
        assert_eq!(
            sim.respond(protocol, &request(body)),
            Outcome::Reply(b"\x0601\r".to_vec()),
            "{body}"
        );
        assert_eq!(sim.raw(register), Some(raw));
    }
    sim.respond(protocol, &request("01FF001"));
    assert_eq!(sim.page(protocol), Some(1));
}
