//! DV1 parameters that choose how other registers are written and read, through the typed
//! API and the virtual drive: 07-11 (P.34) chooses where parameter writes go (RAM and
//! EEPROM, or RAM only: the description's `persistence:`), 00-08 chooses one or two
//! decimals for the frequencies at 1002h, 1003h and 1009h (`scale_by` with `otherwise`),
//! which an Eaton read reply's unit digit states.

use std::time::Duration;
use vfd_drives::dv1;
use vfd_runtime::prelude::*;
use vfd_runtime::transport::memory_pair;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, DriveProtocol, Request, TransactionErrorKind};
use vfd_tests::outcomes::refused;
use vfd_tests::scripted_peer::answer;

use dv1::bits::RunCommand as Word;
use dv1::codes::EepromWriteSelection as Selection;
use dv1::registers::*;

const PROTOCOLS: [&DriveProtocol<dv1::Drive>; 3] = [
    &dv1::protocols::MODBUS,
    &dv1::protocols::MODBUS_ASCII,
    &dv1::protocols::EATON,
];

/// 07-08 (P.52, 0034h): a parameter every protocol reaches (on the Eaton protocol at offset
/// 52 of page 0, as 07-11 at offset 34), factory setting 1.
const PARAMETER: &str = "07-08";
const SELECTOR: &str = "07-11";

/// The page switches a new master makes before its first access to page 0 (07-08 and 07-11
/// share it): one on a protocol with pages.
fn switches(protocol: &DriveProtocol<dv1::Drive>) -> u64 {
    u64::from(protocol.paging.is_some())
}

/// (RAM, EEPROM) of the register `name` in the virtual drive.
fn stored(sim: &Simulator, name: &str) -> (u32, u32) {
    let drive = sim.lock();
    (drive.raw(name).unwrap(), drive.eeprom_raw(name).unwrap())
}

#[test]
fn a_ram_write_sets_07_11_to_1_first_and_leaves_the_parameters_eeprom_copy() {
    for protocol in PROTOCOLS {
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(protocol);
        assert_eq!(master.persistence_selector(), None, "unknown at first");
        // Factory state: 07-11 = 0, every parameter write over the link would reach the
        // EEPROM.
        assert_eq!(stored(&sim, SELECTOR), (0, 0));
        master.write_ram::<AllowedErrorCount>(5).unwrap();
        assert_eq!(stored(&sim, PARAMETER), (5, 1), "{}: RAM only", protocol.id);
        // Two frames: 07-11 = 1, then the value. Writing 1 while 0 was in force stored it
        // in the EEPROM too (the documented price of a RAM-only write).
        assert_eq!(sim.requests(), 2 + switches(protocol), "{}", protocol.id);
        assert_eq!(stored(&sim, SELECTOR), (1, 1));
        assert_eq!(master.persistence_selector(), Some(1));
        // Known now: the next RAM write is one frame.
        master.write_ram::<AllowedErrorCount>(6).unwrap();
        assert_eq!(sim.requests(), 3 + switches(protocol));
        assert_eq!(stored(&sim, PARAMETER), (6, 1));
        // RAM-only registers are not governed: the run command and the RAM frequency go
        // as they are.
        master
            .write_ram::<FrequencyCommandRam>(Hertz(10.0))
            .unwrap();
        master.write_ram::<RunCommand>(Word::new()).unwrap();
        assert_eq!(sim.requests(), 5 + switches(protocol));
        // A power cycle brings back what the EEPROM holds.
        sim.power_cycle();
        sim.advance(Duration::from_secs(2));
        assert_eq!(stored(&sim, PARAMETER), (1, 1));
        assert_eq!(master.read::<AllowedErrorCount>().unwrap(), 1);
        assert_eq!(
            master.read::<EepromWriteSelection>().unwrap(),
            Selection::RamOnly
        );
    }
}

#[test]
fn a_persistent_write_reaches_the_eeprom_and_leaves_07_11_as_it_was() {
    for protocol in PROTOCOLS {
        // 07-11 = 1 (RAM only) in RAM and EEPROM, as a first RAM write leaves it.
        let sim = Simulator::new(&dv1::DRIVE);
        sim.master(protocol)
            .write_ram::<AllowedErrorCount>(3)
            .unwrap();
        assert_eq!(stored(&sim, SELECTOR), (1, 1));
        let before = sim.requests();
        // A new master knows nothing: it reads 07-11 (1), writes 0 (RAM only, since 1 is
        // in force), the value (RAM and EEPROM), then 1 (stored as 1, what the EEPROM held).
        let mut master = sim.master(protocol);
        master.write_persistent::<AllowedErrorCount>(7).unwrap();
        assert_eq!(
            sim.requests() - before,
            4 + switches(protocol),
            "{}",
            protocol.id
        );
        assert_eq!(stored(&sim, PARAMETER), (7, 7), "{}", protocol.id);
        assert_eq!(stored(&sim, SELECTOR), (1, 1), "{}", protocol.id);
        assert_eq!(master.persistence_selector(), Some(1));
        // Known to hold 1: no read the second time.
        master.write_persistent::<AllowedErrorCount>(8).unwrap();
        assert_eq!(sim.requests() - before, 7 + switches(protocol));
        assert_eq!(stored(&sim, PARAMETER), (8, 8));
        assert_eq!(stored(&sim, SELECTOR), (1, 1));
        // And a RAM write after it is one frame again, leaving the EEPROM at 8.
        master.write_ram::<AllowedErrorCount>(2).unwrap();
        assert_eq!(sim.requests() - before, 8 + switches(protocol));
        assert_eq!(stored(&sim, PARAMETER), (2, 8));
        sim.power_cycle();
        sim.advance(Duration::from_secs(2));
        assert_eq!(master.read::<AllowedErrorCount>().unwrap(), 8);
    }
}

#[test]
fn with_the_factory_setting_a_persistent_write_is_the_write_alone() {
    for protocol in PROTOCOLS {
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(protocol);
        master.write_persistent::<AllowedErrorCount>(9).unwrap();
        // The read of 07-11 (0), then the value: 07-11 stays 0 in RAM and EEPROM.
        assert_eq!(sim.requests(), 2 + switches(protocol), "{}", protocol.id);
        assert_eq!(stored(&sim, PARAMETER), (9, 9));
        assert_eq!(stored(&sim, SELECTOR), (0, 0));
        assert_eq!(master.persistence_selector(), Some(0));
        // 0 remembered: read again before the next persistent write (a power cycle may
        // have brought back a 1 from the EEPROM).
        master.write_persistent::<AllowedErrorCount>(4).unwrap();
        assert_eq!(sim.requests(), 4 + switches(protocol));
        assert_eq!(stored(&sim, PARAMETER), (4, 4));
    }
}

#[test]
fn a_refused_persistent_write_still_puts_07_11_back() {
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    master.write_ram::<AllowedErrorCount>(3).unwrap();
    // 07-08 takes 0-10: 11 is refused (exception 03) after 07-11 was set to 0.
    let request = Request::for_register(CommandKind::WritePersistent, AllowedErrorCount::INFO, 11);
    assert_eq!(refused(master.transact(&request)), 3);
    assert_eq!(stored(&sim, SELECTOR), (1, 1), "written back");
    assert_eq!(stored(&sim, PARAMETER), (3, 1));
    // After a failure the master does not trust what it knew.
    assert_eq!(master.persistence_selector(), None);
    // A request by number alone goes as it is (its number need not be a parameter).
    let before = sim.requests();
    let raw = Request::raw(CommandKind::WriteRam, 0x0034, 4);
    master.transact(&raw).unwrap();
    assert_eq!(sim.requests() - before, 1);
}

#[test]
fn writes_of_07_11_itself_follow_their_kind() {
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    // A persistent 1 from the factory state: read (0), then 1 stored in RAM and EEPROM.
    master
        .write_persistent::<EepromWriteSelection>(Selection::RamOnly)
        .unwrap();
    assert_eq!(sim.requests(), 2);
    assert_eq!(stored(&sim, SELECTOR), (1, 1));
    assert_eq!(master.persistence_selector(), Some(1));
    // A RAM-only 0 while 1 is in force: RAM 0, the EEPROM keeps 1.
    master
        .write_ram::<EepromWriteSelection>(Selection::RamAndEeprom)
        .unwrap();
    assert_eq!(stored(&sim, SELECTOR), (0, 1));
    assert_eq!(master.persistence_selector(), Some(0));
    // A persistent write from there: read (0), then the value, which reaches the EEPROM;
    // 07-11's EEPROM copy stays 1.
    master.write_persistent::<AllowedErrorCount>(6).unwrap();
    assert_eq!(stored(&sim, PARAMETER), (6, 6));
    assert_eq!(stored(&sim, SELECTOR), (0, 1));
    // A RAM write sets 1 again (RAM and EEPROM, the EEPROM held 1).
    master.write_ram::<AllowedErrorCount>(2).unwrap();
    assert_eq!(stored(&sim, SELECTOR), (1, 1));
    assert_eq!(stored(&sim, PARAMETER), (2, 6));
}

#[test]
fn the_eeprom_frequency_register_keeps_its_own_storage() {
    // 1002h (RAM) and 1009h (EEPROM) are not parameters: 07-11 does not govern them, and
    // the master sends no 07-11 before them.
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    master
        .write_ram::<FrequencyCommandEeprom>(Hertz(30.0))
        .unwrap();
    master
        .write_ram::<FrequencyCommandRam>(Hertz(20.0))
        .unwrap();
    assert_eq!(sim.requests(), 2);
    assert_eq!(stored(&sim, SELECTOR), (0, 0));
    assert_eq!(master.persistence_selector(), None);
}

#[test]
fn a_value_refused_before_sending_touches_nothing() {
    // 500 Hz is outside 02-15's 0-400 Hz: refused before 07-11 or the page is touched.
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::EATON);
    let error = master.write_ram::<Parameter0215>(Hertz(500.0)).unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Value(_)),
        "{error}"
    );
    assert_eq!(sim.requests(), 0);
    assert_eq!(stored(&sim, SELECTOR), (0, 0));
    assert_eq!(master.persistence_selector(), None);
}

/// Runs the drive at `hertz` with 00-08 = `selector`, the frequency written in
/// the scale 00-08 chooses, and returns the simulator once the output has reached it.
fn running_at(
    protocol: &'static DriveProtocol<dv1::Drive>,
    selector: u32,
    hertz: f64,
) -> Simulator {
    let sim = Simulator::new(&dv1::DRIVE);
    assert!(sim.lock().set_raw("00-08", selector));
    let mut master = sim.master(protocol);
    let write = FrequencyCommandRam::write_ram_scaled(Hertz(hertz), selector).unwrap();
    master.transact(&write).unwrap();
    master
        .write_ram::<RunCommand>(Word::new().with_forward(true))
        .unwrap();
    sim.advance(Duration::from_secs(10));
    sim
}

#[test]
fn over_modbus_00_08_chooses_the_scale_of_1003h() {
    for protocol in [&dv1::protocols::MODBUS, &dv1::protocols::MODBUS_ASCII] {
        for (selector, raw) in [(0, 5000), (1, 500), (3, 500)] {
            let sim = running_at(protocol, selector, 50.0);
            assert_eq!(sim.lock().raw("H6F"), Some(raw));
            let mut master = sim.master(protocol);
            // 00-08 read first, then the word in the scale it chooses.
            let chosen = master.read::<FrequencyDecimals>().unwrap().value;
            assert_eq!(u32::from(chosen), selector);
            let answer = master.transact(&OutputFrequency::read()).unwrap();
            assert_eq!(answer.data, Some(raw));
            assert_eq!(answer.decimals, None, "Modbus states no decimals");
            assert_eq!(
                OutputFrequency::value_scaled(raw, u32::from(chosen)).unwrap(),
                Hertz(50.0),
                "{} 00-08 = {selector}",
                protocol.id
            );
        }
    }
    // The typed write of 00-08 at its group-mode address 2718h.
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    master.write_ram::<FrequencyDecimals>(1).unwrap();
    assert_eq!(sim.lock().raw("00-08"), Some(1));
}

#[test]
fn over_eaton_the_unit_digit_gives_the_scale_of_1003h() {
    for (selector, frame) in [
        // Station 01, 50.00 Hz = 1388h, unit 2: 30h+31h+31h+33h+38h+38h+32h = 167h -> "67".
        (0, &b"\x020113882\x0367\r"[..]),
        // Station 01, 50.0 Hz = 01F4h, unit 1: 30h+31h+30h+31h+46h+34h+31h = 16Dh -> "6D".
        (1, &b"\x020101F41\x036D\r"[..]),
    ] {
        let sim = running_at(&dv1::protocols::EATON, selector, 50.0);
        let mut master = sim.master(&dv1::protocols::EATON);
        // No read of 00-08: the reply's unit digit says the scale (one request only).
        let before = sim.requests();
        assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(50.0));
        assert_eq!(
            sim.requests() - before,
            1,
            "00-08 = {selector}: one request"
        );
        assert_eq!(master.last_reply(), frame, "00-08 = {selector}");
        let answer = master.transact(&OutputFrequency::read()).unwrap();
        assert_eq!(answer.decimals, Some(if selector == 0 { 2 } else { 1 }));
    }
}

/// The Eaton sum check of a data reply: station, data and unit digit.
fn data_reply(body: &str) -> Vec<u8> {
    let sum = body.bytes().map(u32::from).sum::<u32>() & 0xFF;
    format!("\x02{body}\x03{sum:02X}\r").into_bytes()
}

#[test]
fn a_unit_digit_no_scale_of_the_register_has_is_a_typed_error() {
    let protocol = &dv1::protocols::EATON;
    let (near, far) = memory_pair();
    let peer = answer(
        far,
        protocol.protocol(),
        vec![
            // 1003h with three decimals: neither 0.01 nor 0.1 Hz.
            data_reply("0013883"),
            // 1004h (0.01 A, fixed) with one decimal.
            data_reply("0013881"),
            // 1004h as the description says: 50.00 A.
            data_reply("0013882"),
        ],
    );
    let mut master =
        Master::new(near, protocol, dv1::SERIAL.default, dv1::SERIAL.timing).with_address(Some(0));
    let error = master.read::<OutputFrequency>().unwrap_err();
    match &error.kind {
        TransactionErrorKind::Value(ValueError::WrongDecimals {
            register,
            expected,
            received,
        }) => {
            assert_eq!(register.code, "H6F");
            assert_eq!((*expected, *received), (2, 3));
        }
        other => panic!("not a decimals error: {other:?}"),
    }
    let text = error.to_string();
    assert!(text.contains("H6F") && text.contains('3'), "{text}");
    let error = master.read::<OutputCurrent>().unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Value(ValueError::WrongDecimals {
                expected: 2,
                received: 1,
                ..
            })
        ),
        "{error}"
    );
    assert_eq!(master.read::<OutputCurrent>().unwrap().value, Amperes(50.0));
    let requests = peer.join().unwrap();
    assert_eq!(requests[0], b"\x05006F00C\r");
}

#[test]
fn the_frames_of_a_persistent_write_with_07_11_at_1() {
    // Derived frames (the manual prints none): read 07-11 (0022h) = 1, write 0, write 07-08
    // (0034h) = 7, write 1 back. CRC-16/MODBUS, low byte first.
    let frames = [
        "01 03 00 22 00 01 24 00",
        "01 06 00 22 00 00 29 C0",
        "01 06 00 34 00 07 89 C6",
        "01 06 00 22 00 01 E8 00",
    ];
    let hex = |text: &str| {
        text.split(' ')
            .map(|byte| u8::from_str_radix(byte, 16).unwrap())
            .collect::<Vec<u8>>()
    };
    let protocol = &dv1::protocols::MODBUS;
    let (near, far) = memory_pair();
    // Replies: 07-11 = 1, then each write echoed.
    let mut replies = vec![hex("01 03 02 00 01 79 84")];
    replies.extend(frames[1..].iter().map(|frame| hex(frame)));
    let peer = answer(far, protocol.protocol(), replies);
    let mut master =
        Master::new(near, protocol, dv1::SERIAL.default, dv1::SERIAL.timing).with_address(Some(1));
    master.write_persistent::<AllowedErrorCount>(7).unwrap();
    assert_eq!(master.persistence_selector(), Some(1));
    let sent = peer.join().unwrap();
    let expected: Vec<Vec<u8>> = frames.iter().map(|frame| hex(frame)).collect();
    assert_eq!(sent, expected);
}
