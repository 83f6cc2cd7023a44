//! The vocabulary an outside integrator lacked when describing a drive of the computer-link
//! family (issue 30), as behaviour: the DV1's station register (07-01) and its Eaton
//! refusals of frames it cannot read; and a made-up drive of the family,
//! `fixtures/link-vocabulary/kestrel_k7.yaml`, that uses every new key (registers known by
//! their wire numbers or their page only, storage chosen by the instruction code, separate
//! baud-rate and parity registers, the station register, the refusals of unreadable frames
//! with their retries limit, the status roles overload and frequency detected, and paged
//! examples), compiled by the proc-macro and driven through its virtual drive.

use vfd_drives::dv1;
use vfd_runtime::virtual_drive::{Outcome, Simulator, VirtualDrive};
use vfd_runtime::Protocol;

/// `text` with the Eaton sum check (the low byte of the sum of the characters after ENQ)
/// and CR appended: `"\x0500FA00002"` -> `"\x0500FA00002D9\r"`.
fn eaton_frame(text: &str) -> Vec<u8> {
    let sum: u32 = text.bytes().skip(1).map(u32::from).sum();
    format!("{text}{:02X}\r", sum & 0xFF).into_bytes()
}

#[track_caller]
fn answers(drive: &mut VirtualDrive, protocol: &Protocol, request: &[u8], reply: &[u8]) {
    match drive.respond(protocol, request) {
        Outcome::Reply(bytes) => assert_eq!(
            bytes.escape_ascii().to_string(),
            reply.escape_ascii().to_string(),
            "the reply to {}",
            request.escape_ascii()
        ),
        Outcome::Silent(why) => panic!("silent to {}: {why}", request.escape_ascii()),
    }
}

#[track_caller]
fn silent(drive: &mut VirtualDrive, protocol: &Protocol, request: &[u8]) {
    if let Outcome::Reply(bytes) = drive.respond(protocol, request) {
        panic!(
            "{} answered with {}",
            request.escape_ascii(),
            bytes.escape_ascii()
        );
    }
}

mod dv1_station_register {
    use super::*;
    use dv1::registers::StationNumber;

    #[test]
    fn the_virtual_drive_answers_at_the_station_07_01_holds_after_a_reset() {
        let eaton = dv1::protocols::EATON.protocol();
        let mut drive = VirtualDrive::new(&dv1::DRIVE);
        // Its first protocol is Modbus, which takes no station 0: station 1, 07-01 = 1.
        assert_eq!(drive.address(), 1);
        assert_eq!(drive.raw("07-01"), Some(1));
        drive.set_address(0);
        assert_eq!(
            drive.raw("07-01"),
            Some(0),
            "setting the station sets 07-01"
        );
        // 07-01 = 5 over the link (page 0, offset 24h = P.36, write code A4h): acknowledged
        // at station 0; it takes effect after a reset, so the drive stays at station 0.
        answers(
            &mut drive,
            eaton,
            &eaton_frame("\x0500FF00000"),
            b"\x0600\r",
        );
        answers(
            &mut drive,
            eaton,
            &eaton_frame("\x0500A400005"),
            b"\x0600\r",
        );
        assert_eq!(drive.raw("07-01"), Some(5));
        assert_eq!(drive.address(), 0);
        drive.reset();
        assert_eq!(
            drive.address(),
            5,
            "the station 07-01 holds, after the reset"
        );
        silent(&mut drive, eaton, &eaton_frame("\x05007A0"));
        answers(
            &mut drive,
            eaton,
            &eaton_frame("\x05057A0"),
            b"\x020500000\x0355\r",
        );
    }

    #[test]
    fn a_master_reaches_the_moved_station_after_the_reset() {
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(&dv1::protocols::MODBUS);
        master.write_ram::<StationNumber>(7).unwrap();
        sim.lock().reset();
        assert_eq!(sim.lock().address(), 7);
        let mut moved = sim.master(&dv1::protocols::MODBUS);
        assert_eq!(moved.read::<StationNumber>().unwrap(), 7);
    }
}

mod dv1_unreadable_frames {
    use super::*;

    fn at_station_0() -> VirtualDrive {
        let mut drive = VirtualDrive::new(&dv1::DRIVE);
        drive.set_address(0);
        drive
    }

    #[test]
    fn a_frame_with_a_syntax_error_gets_h03_at_its_station() {
        let eaton = dv1::protocols::EATON.protocol();
        let mut drive = at_station_0();
        // Three data digits where four belong (例一 with one digit short).
        answers(
            &mut drive,
            eaton,
            &eaton_frame("\x0500FA0000"),
            b"\x15003\r",
        );
        // A character the frames never carry: the DV1 has no character error, so the
        // syntax error's code.
        answers(
            &mut drive,
            eaton,
            &eaton_frame("\x0500FA000G2"),
            b"\x15003\r",
        );
        // A wrong sum check: H02, at the station the frame names.
        answers(&mut drive, eaton, b"\x0500FA00002D8\r", b"\x15002\r");
        // Another station's garbled frame, and one whose station is garbled: no reply.
        silent(&mut drive, eaton, &eaton_frame("\x0501FA0000"));
        silent(&mut drive, eaton, &eaton_frame("\x050*FA00002"));
        // The frame it can read is still carried out.
        answers(&mut drive, eaton, b"\x0500FA00002D9\r", b"\x0600\r");
    }

    #[test]
    fn the_error_reply_is_the_manuals_protocol_error_to_a_master() {
        let eaton = dv1::protocols::EATON.protocol();
        let mut drive = at_station_0();
        let Outcome::Reply(bytes) = drive.respond(eaton, &eaton_frame("\x0500FA0000")) else {
            panic!("silent");
        };
        let Ok(vfd_runtime::protocol::Found::Frame {
            frame: vfd_runtime::Reply::Error { error, .. },
            ..
        }) = eaton.decode_reply(None, &bytes)
        else {
            panic!("not an error reply: {}", bytes.escape_ascii());
        };
        let info = eaton.error_code(error).expect("in the manual's table");
        assert_eq!(info.id, "protocol_error");
        assert!(info.meaning.contains("syntax error"), "{}", info.meaning);
    }
}

mod dv1_storage_by_instruction {
    use super::*;
    use dv1::registers::{FrequencyCommandEeprom, FrequencyCommandRam};
    use vfd_runtime::prelude::*;
    use vfd_runtime::{EncodeError, TransactionErrorKind};

    fn eaton() -> (
        Simulator,
        vfd_runtime::transaction::Master<vfd_runtime::virtual_drive::SimLink, dv1::Drive>,
    ) {
        let sim = Simulator::new(&dv1::DRIVE);
        sim.lock().set_address(0);
        let master = sim.master(&dv1::protocols::EATON);
        (sim, master)
    }

    #[test]
    fn hee_stores_in_eeprom_and_hed_in_ram() {
        let (sim, mut master) = eaton();
        // 1009h (HEE): a persistent write goes out with the plain write, and the drive
        // keeps it over a power cycle.
        master
            .write_persistent::<FrequencyCommandEeprom>(Hertz(45.0))
            .unwrap();
        assert_eq!(sim.lock().eeprom_raw("H73-HEE"), Some(4500));
        // 1002h (HED): RAM only.
        master
            .write_ram::<FrequencyCommandRam>(Hertz(30.0))
            .unwrap();
        assert_eq!(sim.lock().raw("H6D-HED"), Some(3000));
        assert_eq!(sim.lock().eeprom_raw("H6D-HED"), Some(0));
        sim.power_cycle();
        assert_eq!(sim.lock().raw("H73-HEE"), Some(4500));
        assert_eq!(sim.lock().raw("H6D-HED"), Some(0));
    }

    #[test]
    fn a_ram_write_of_the_eeprom_instruction_is_refused_before_sending() {
        let (sim, mut master) = eaton();
        let error = master
            .write_ram::<FrequencyCommandEeprom>(Hertz(45.0))
            .unwrap_err();
        assert!(
            matches!(
                error.kind,
                TransactionErrorKind::Encode(EncodeError::StoredInEeprom {
                    register: 0x1009,
                    ..
                })
            ),
            "{error}"
        );
        assert_eq!(sim.lock().tally().addressed, 0, "nothing was sent");
        // The frame the persistent write sends is the HEE write the manual lists.
        let request = FrequencyCommandEeprom::write_persistent(Hertz(50.0)).unwrap();
        let mut frame = [0u8; 16];
        let len = dv1::protocols::EATON
            .encode_request(&request, Some(0), &mut frame)
            .unwrap();
        assert_eq!(&frame[..len], eaton_frame("\x0500EE01388").as_slice());
    }
}

vfd_macros::include_drive!(
    "fixtures/link-vocabulary/kestrel_k7.yaml",
    protocols = "../drives/protocols"
);

mod kestrel {
    use super::*;
    use kestrel_k7::registers::*;
    use std::time::Duration;
    use vfd_runtime::prelude::*;
    use vfd_runtime::{EncodeError, Space, TransactionErrorKind};

    fn link() -> &'static Protocol {
        kestrel_k7::protocols::LINK.protocol()
    }

    #[test]
    fn registers_known_by_their_wire_numbers_are_read_and_found_by_code() {
        let status = kestrel_k7::DRIVE.register("H7A").unwrap();
        assert!(!status.has_address, "no address of its own");
        assert_eq!(status.label(), "register H7A (Inverter status)");
        // Reached by its instruction code on the link, and by nothing else.
        let own = link()
            .wire_numbers
            .iter()
            .find(|w| w.register == status.address)
            .unwrap();
        assert_eq!((own.read, own.write), (Some(0x7A), None));
        let sim = Simulator::new(&kestrel_k7::DRIVE);
        let mut master = sim.master(&kestrel_k7::protocols::LINK);
        assert!(!master
            .read::<InverterStatus>()
            .unwrap()
            .into_value()
            .running());
        // Its number is no register number a frame carries: a paged read of it is none.
        assert_eq!(link().page_of(status.address), None);
    }

    #[test]
    fn a_parameter_known_by_its_page_and_number_takes_its_number_from_the_pages() {
        let detection = kestrel_k7::DRIVE.register("Pr.42").unwrap();
        assert!(detection.has_address);
        assert_eq!(detection.address, 42);
        assert_eq!(link().page_of(42), Some((0, 0x2A)));
        assert_eq!(
            kestrel_k7::DRIVE
                .register_at(Space::Parameter, 117)
                .map(|r| r.code),
            Some("Pr.117")
        );
        let sim = Simulator::new(&kestrel_k7::DRIVE);
        let mut master = sim.master(&kestrel_k7::protocols::LINK);
        assert_eq!(
            master.read::<FrequencyDetection>().unwrap().into_value(),
            Hertz(6.0)
        );
    }

    #[test]
    fn the_instruction_decides_where_a_write_goes() {
        let sim = Simulator::new(&kestrel_k7::DRIVE);
        let mut master = sim.master(&kestrel_k7::protocols::LINK);
        master
            .write_persistent::<FrequencyEeprom>(Hertz(50.0))
            .unwrap();
        master.write_ram::<FrequencyRam>(Hertz(20.0)).unwrap();
        // A parameter's plain write is an EEPROM one: persistent writes only.
        master
            .write_persistent::<AccelerationTime>(Seconds(7.5))
            .unwrap();
        let error = master
            .write_ram::<AccelerationTime>(Seconds(7.5))
            .unwrap_err();
        assert!(
            matches!(
                error.kind,
                TransactionErrorKind::Encode(EncodeError::StoredInEeprom { register: 7, .. })
            ),
            "{error}"
        );
        let drive = sim.lock();
        assert_eq!(drive.eeprom_raw("H6E-HEE"), Some(5000));
        assert_eq!(drive.eeprom_raw("Pr.7"), Some(75));
        assert_eq!(drive.raw("H6D-HED"), Some(2000));
        assert_eq!(drive.eeprom_raw("H6D-HED"), Some(0));
    }

    #[test]
    fn the_drive_answers_at_the_station_its_register_holds() {
        let mut drive = VirtualDrive::new(&kestrel_k7::DRIVE);
        assert_eq!(drive.address(), 1, "Pr.117's factory value");
        // Pr.117 = 4 (page 1, number 11h): the drive stays at 1 until a reset.
        answers(
            &mut drive,
            link(),
            &eaton_frame("\x0501FF00001"),
            b"\x0601\r",
        );
        answers(
            &mut drive,
            link(),
            &eaton_frame("\x05019100004"),
            b"\x0601\r",
        );
        assert_eq!(drive.address(), 1);
        drive.reset();
        assert_eq!(drive.address(), 4);
        drive.set_address(9);
        assert_eq!(
            drive.raw("Pr.117"),
            Some(9),
            "setting the station sets Pr.117"
        );
    }

    #[test]
    fn unreadable_frames_get_the_manuals_errors_then_the_nak_error() {
        let mut drive = VirtualDrive::new(&kestrel_k7::DRIVE);
        // A character error (a `G` among the data's hex digits), then a second unreadable
        // frame in a row: more than Pr.121 = 1 allows, the NAK error (H0).
        answers(
            &mut drive,
            link(),
            &eaton_frame("\x0501ED0G388"),
            b"\x15017\r",
        );
        answers(
            &mut drive,
            link(),
            &eaton_frame("\x0501ED0138"),
            b"\x15010\r",
        );
        // A frame it reads starts the count again: a syntax error is H3 once more.
        answers(
            &mut drive,
            link(),
            &eaton_frame("\x05017A0"),
            b"\x020100000\x0351\r",
        );
        answers(
            &mut drive,
            link(),
            &eaton_frame("\x0501ED0138"),
            b"\x15013\r",
        );
        answers(&mut drive, link(), b"\x0501ED0138800\r", b"\x15010\r");
        let Ok(vfd_runtime::protocol::Found::Frame {
            frame: vfd_runtime::Reply::Error { info, .. },
            ..
        }) = link().decode_reply(None, b"\x15010\r")
        else {
            panic!("an error reply");
        };
        assert_eq!(info.map(|i| i.id.as_ref()), Some("nak_error"));
    }

    #[test]
    fn overload_and_frequency_detected_follow_their_levels() {
        let sim = Simulator::new(&kestrel_k7::DRIVE);
        let mut master = sim.master(&kestrel_k7::protocols::LINK);
        master.write_ram::<FrequencyRam>(Hertz(60.0)).unwrap();
        master
            .write_ram::<RunCommand>(kestrel_k7::bits::RunCommand::new().with_forward(true))
            .unwrap();
        let status = |master: &mut vfd_runtime::transaction::Master<
            vfd_runtime::virtual_drive::SimLink,
            kestrel_k7::Drive,
        >| master.read::<InverterStatus>().unwrap().into_value();
        // Pr.7 = 5 s for 60 Hz: 0.4 s gives 4.8 Hz (below Pr.42 = 6 Hz), 1 s 12 Hz.
        sim.advance(Duration::from_millis(400));
        let early = status(&mut master);
        assert!(early.running() && !early.frequency_detected() && !early.overload());
        sim.advance(Duration::from_millis(600));
        let later = status(&mut master);
        assert!(later.frequency_detected() && !later.overload());
        // 8 A at 46.7 Hz: overloaded at 60 Hz (10 A).
        sim.advance(Duration::from_secs(5));
        let full = status(&mut master);
        assert!(full.up_to_frequency() && full.frequency_detected() && full.overload());
        assert_eq!(
            master.read::<OutputCurrent>().unwrap().into_value(),
            Amperes(10.0)
        );
    }
}

/// The reference page of the made-up drive shows each new fact.
#[test]
fn the_page_shows_the_new_vocabulary() {
    let ir = vfd_codegen::compile(
        std::path::Path::new("fixtures/link-vocabulary/kestrel_k7.yaml"),
        Some(std::path::Path::new("../drives/protocols")),
    )
    .expect("the fixture compiles");
    let page =
        vfd_codegen::markdown_page(&ir, &vfd_codegen::OutputNames::default()).expect("renders");
    // Paragraphs on one line each, as the assertions read them.
    let page = vfd_codegen::unwrap_markdown(&page);
    for shown in [
        "| `none: wire numbers only` | H7A |",
        "| `002A, link page 0 offset 2Ah` | Pr.42 |",
        "set by Pr.117 (the virtual drive answers at the station it holds)",
        "| 0001h | 9600 bps — line: 9600 bps |",
        "| 0002h | Even parity — line: even parity |",
        "storage by instruction: a RAM-only register's write goes to RAM",
        "Status levels: overload while the output current is at or above 8; frequency detected while running at or above Pr.42.",
        "Bad character | Malformed frame | Retries exceeded",
        "once more than Pr.121 unreadable frames",
        "On page 0, where the request's offset is Pr.42.",
    ] {
        assert!(page.contains(shown), "the page lacks {shown:?}:\n{page}");
    }
}
