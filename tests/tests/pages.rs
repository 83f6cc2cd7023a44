//! Parameter pages and the master's follow-up, on the DV1's Eaton protocol: one typed call
//! produces the manual's whole exchange (page switch, acknowledgement, read, reply, the
//! master's C), the page is switched only when it changes and forgotten after an error or
//! a reset, and a garbled reply is asked for again with F.

use vfd_drives::dv1;
use vfd_drives::dv1::codes::InverterResetCode;
use vfd_drives::dv1::registers::{
    AllowedErrorCount, CommunicationErrorHandling, InverterReset, OutputFrequency, Parameter0215,
};
use vfd_runtime::prelude::*;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{Direction, Recording};
use vfd_runtime::virtual_drive::{Fault, SimLink, Simulator};
use vfd_runtime::{Request, TransactionErrorKind};

type Traced = Master<Recording<SimLink>, dv1::Drive>;

/// A virtual DV1 at station 0 (as in the manual's examples) and a master that logs the line.
fn eaton() -> (Simulator, Traced) {
    let sim = Simulator::new(&dv1::DRIVE);
    sim.lock().set_address(0);
    let protocol = &dv1::protocols::EATON;
    let master = Master::new(
        Recording::new(sim.link(protocol)),
        protocol,
        dv1::DRIVE.serial.default,
        dv1::DRIVE.serial.timing,
    )
    .with_address(Some(0));
    (sim, master)
}

/// The line so far, each entry shown as text with its direction, then cleared.
fn take_log(master: &mut Traced) -> Vec<(Direction, String)> {
    let transport = master.transport_mut();
    let log = transport
        .log()
        .iter()
        .map(|(direction, bytes)| (*direction, String::from_utf8_lossy(bytes).into_owned()))
        .collect();
    transport.clear();
    log
}

fn sent(text: &str) -> (Direction, String) {
    (Direction::Sent, text.to_owned())
}

fn received(text: &str) -> (Direction, String) {
    (Direction::Received, text.to_owned())
}

#[test]
fn reading_p195_is_the_manuals_example_three_with_the_masters_acknowledgement() {
    let (_sim, mut master) = eaton();
    let value = master.read::<Parameter0215>().unwrap();
    assert_eq!(value.into_value(), Hertz(60.0));
    assert_eq!(
        take_log(&mut master),
        vec![
            // 例三 step 1: switch to page 1 (HFF, data H0001); step 2: format C.
            sent("\x0500FF00001DD\r"),
            received("\x0600\r"),
            // Step 3: read code H5F (195 - 100 = 95); step 4: format E, H1770, unit 2.
            sent("\x05005F00B\r"),
            received("\x020017702\x0361\r"),
            // ⑤: the master's C (format table, l. 174-179; not printed in 例三).
            sent("\x0600\r"),
        ]
    );
    assert_eq!(master.known_page(Some(0)), Some(1));
}

#[test]
fn writing_50_hz_to_p195_is_example_four() {
    let (sim, mut master) = eaton();
    // 07-11 at its factory setting 0: a write over the link goes to RAM and EEPROM, which
    // is what 例四 does; told so, the master sends the write alone.
    master.assume_persistence_selector(0);
    master
        .write_persistent::<Parameter0215>(Hertz(50.0))
        .unwrap();
    assert_eq!(
        take_log(&mut master),
        vec![
            // 例四 steps 1-2 (略: the same as 例三's), then steps 3-4.
            sent("\x0500FF00001DD\r"),
            received("\x0600\r"),
            sent("\x0500DF01388EE\r"),
            received("\x0600\r"),
        ]
    );
    assert_eq!(sim.lock().raw("02-15"), Some(0x1388));
}

#[test]
fn a_ram_write_sets_07_11_on_page_0_then_writes_on_page_1() {
    let (sim, mut master) = eaton();
    master.write_ram::<Parameter0215>(Hertz(50.0)).unwrap();
    assert_eq!(
        take_log(&mut master),
        vec![
            // 07-11 (P.34) is offset 34 = 22h of page 0: written 1 (RAM only) with HA2.
            sent("\x0500FF00000DC\r"),
            received("\x0600\r"),
            sent("\x0500A200001C4\r"),
            received("\x0600\r"),
            // Then P.195 on page 1, as in 例四.
            sent("\x0500FF00001DD\r"),
            received("\x0600\r"),
            sent("\x0500DF01388EE\r"),
            received("\x0600\r"),
        ]
    );
    assert_eq!(sim.lock().raw("07-11"), Some(1));
    assert_eq!(master.known_page(Some(0)), Some(1));
}

#[test]
fn the_page_is_switched_only_when_it_changes() {
    let (_sim, mut master) = eaton();
    master.read::<Parameter0215>().unwrap();
    take_log(&mut master);
    // P.153 (07-10) is on page 1 too: no switch.
    master.read::<CommunicationErrorHandling>().unwrap();
    let log = take_log(&mut master);
    assert_eq!(log.len(), 3, "read, reply, C: {log:?}");
    // P.153 - 100 = 53 = 35h.
    assert_eq!(log[0], sent("\x0500350F8\r"), "{log:?}");
    // P.52 (07-08) is on page 0: switch, then read offset 52 = 34h.
    master.read::<AllowedErrorCount>().unwrap();
    let log = take_log(&mut master);
    assert_eq!(log[0], sent("\x0500FF00000DC\r"));
    assert_eq!(master.known_page(Some(0)), Some(0));
    // A register with its own command code is not paged: no switch, page kept.
    master.read::<OutputFrequency>().unwrap();
    let log = take_log(&mut master);
    assert_eq!(log[0], sent("\x05006F00C\r"), "{log:?}");
    assert_eq!(master.known_page(Some(0)), Some(0));
}

#[test]
fn after_a_refusal_the_page_is_switched_again() {
    let (_sim, mut master) = eaton();
    master.read::<Parameter0215>().unwrap();
    take_log(&mut master);
    // 例五: 500 (HC350) is out of range; sent raw, as the typed API refuses it first.
    master.assume_persistence_selector(0);
    let request = Request::for_register(
        vfd_runtime::CommandKind::WritePersistent,
        <Parameter0215 as vfd_runtime::register::Register>::INFO,
        0xC350,
    );
    let error = master.transact(&request).unwrap_err();
    match error.kind {
        TransactionErrorKind::Rejected { code, info, .. } => {
            assert_eq!(code, 0x0C);
            assert_eq!(info.map(|i| i.id.as_ref()), Some("data_range_error"));
        }
        other => panic!("expected H0C, got {other:?}"),
    }
    assert_eq!(
        take_log(&mut master),
        vec![sent("\x0500DF0C350F5\r"), received("\x1500C\r")]
    );
    assert_eq!(master.known_page(Some(0)), None);
    master.read::<Parameter0215>().unwrap();
    assert_eq!(take_log(&mut master)[0], sent("\x0500FF00001DD\r"));
}

#[test]
fn a_reset_forgets_the_page_on_both_sides() {
    let (sim, mut master) = eaton();
    master.read::<Parameter0215>().unwrap();
    assert_eq!(sim.lock().page(&dv1::protocols::EATON), Some(1));
    master
        .write_ram::<InverterReset>(InverterResetCode::Reset)
        .unwrap();
    assert_eq!(master.known_page(Some(0)), None);
    assert_eq!(sim.lock().page(&dv1::protocols::EATON), Some(0));
    take_log(&mut master);
    master.read::<Parameter0215>().unwrap();
    assert_eq!(take_log(&mut master)[0], sent("\x0500FF00001DD\r"));
}

#[test]
fn a_garbled_reply_is_asked_for_again_with_f() {
    let (sim, mut master) = eaton();
    let mut master = {
        master.read::<Parameter0215>().unwrap();
        take_log(&mut master);
        master.with_retries(1)
    };
    sim.inject(Fault::CorruptChecksum);
    let value = master.read::<Parameter0215>().unwrap();
    assert_eq!(value.into_value(), Hertz(60.0));
    let log = take_log(&mut master);
    assert_eq!(log.len(), 5, "{log:?}");
    assert_eq!(log[0], sent("\x05005F00B\r"));
    assert_ne!(
        log[1],
        received("\x020017702\x0361\r"),
        "the first reply is garbled"
    );
    // F: NAK, station, CR; the drive sends the same reply again, and the master says C.
    assert_eq!(log[2], sent("\x1500\r"));
    assert_eq!(log[3], received("\x020017702\x0361\r"));
    assert_eq!(log[4], sent("\x0600\r"));
}

#[test]
fn the_virtual_drive_refuses_a_page_that_does_not_exist() {
    let sim = Simulator::new(&dv1::DRIVE);
    sim.lock().set_address(0);
    let protocol = &dv1::protocols::EATON;
    // Page 5 (P mode ends at page 4) and page 109 (no group 09): H0C, data range error,
    // and the drive stays on its page.
    for (frame, page) in [("\x0500FF00005E1\r", 5), ("\x0500FF0006DF6\r", 109)] {
        let outcome = sim.lock().respond(protocol, frame.as_bytes());
        assert_eq!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Reply(b"\x1500C\r".to_vec()),
            "page {page}"
        );
        assert_eq!(sim.lock().page(protocol), Some(0), "page {page} refused");
    }
    // Page 4 (the last of P mode) and group-mode page 102 (02-xx) exist: acknowledged.
    for (frame, page) in [("\x0500FF00004E0\r", 4), ("\x0500FF00066E8\r", 102)] {
        let outcome = sim.lock().respond(protocol, frame.as_bytes());
        assert_eq!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Reply(b"\x0600\r".to_vec()),
            "page {page}"
        );
        assert_eq!(sim.lock().page(protocol), Some(page));
    }
    // The page reads back with H7F: 0066h, unit digit 0 (30h+30h+30h+30h+36h+36h+30h = 15Ch).
    let outcome = sim.lock().respond(protocol, b"\x05007F00D\r");
    assert_eq!(
        outcome,
        vfd_runtime::virtual_drive::Outcome::Reply(b"\x020000660\x035C\r".to_vec())
    );
}

#[test]
fn pages_locate_registers_in_both_numberings() {
    let paging = dv1::protocols::EATON.paging.as_ref().unwrap();
    assert_eq!(paging.locate(0xC3), Some((1, 0x5F)));
    assert_eq!(paging.register(1, 0x5F), Some(0xC3));
    assert_eq!(paging.locate(99), Some((0, 99)));
    assert_eq!(paging.locate(100), Some((1, 0)));
    assert_eq!(paging.locate(499), Some((4, 99)));
    assert_eq!(paging.locate(500), None, "P mode ends at P.499");
    assert_eq!(paging.locate(10215), Some((102, 15)));
    assert_eq!(paging.locate(10915), None, "no page for group 09");
    assert_eq!(paging.register(102, 15), Some(10215));
    assert_eq!(paging.register(5, 0), None);
    assert_eq!(paging.register(109, 0), None);
    // Every paged register of the description maps there and back.
    for info in dv1::DRIVE.registers {
        if let Some((page, offset)) = dv1::protocols::EATON.page_of(info.address) {
            assert_eq!(
                paging.register(page, offset),
                Some(info.address),
                "{}",
                info.code
            );
        }
    }
}

#[test]
fn a_refusal_gets_no_follow_up_and_an_f_then_repeats_nothing() {
    let sim = Simulator::new(&dv1::DRIVE);
    sim.lock().set_address(0);
    let protocol = &dv1::protocols::EATON;
    let page = sim.lock().respond(protocol, b"\x0500FF00001DD\r");
    assert_eq!(
        page,
        vfd_runtime::virtual_drive::Outcome::Reply(b"\x0600\r".to_vec())
    );
    // A read of P.190 (offset 90 = 5Ah on page 1), which the description does not have:
    // D, H0B (command code error).
    let refused = sim.lock().respond(protocol, b"\x05005A006\r");
    assert_eq!(
        refused,
        vfd_runtime::virtual_drive::Outcome::Reply(b"\x1500B\r".to_vec())
    );
    let again = sim.lock().respond(protocol, b"\x1500\r");
    assert!(
        matches!(again, vfd_runtime::virtual_drive::Outcome::Silent(_)),
        "{again:?}"
    );
    // A sound read reply is repeated on F.
    let read = sim.lock().respond(protocol, b"\x05005F00B\r");
    let again = sim.lock().respond(protocol, b"\x1500\r");
    assert_eq!(read, again);
}

#[test]
fn in_cr_lf_the_whole_exchange_ends_its_frames_in_cr_lf_the_follow_up_too() {
    let (sim, master) = eaton();
    let cr_lf = dv1::protocols::EATON.variant("cr_lf").unwrap();
    assert!(sim.lock().select_variant(cr_lf.protocol()));
    let mut master = master.with_variant("cr_lf").unwrap();
    let value = master.read::<Parameter0215>().unwrap();
    assert_eq!(value.into_value(), Hertz(60.0));
    assert_eq!(
        take_log(&mut master),
        vec![
            sent("\x0500FF00001DD\r\n"),
            received("\x0600\r\n"),
            sent("\x05005F00B\r\n"),
            received("\x020017702\x0361\r\n"),
            sent("\x0600\r\n"),
        ]
    );
}
