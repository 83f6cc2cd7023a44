//! Block transfers (a protocol's `kind: block` command with the drive's `protocols[].block`
//! selection), end to end on the VF-AS1's binary protocol: the manual's 4.1.3 and 8.3.1
//! exchanges come byte for byte from the virtual drive, configured as the manual says.

use std::time::Duration;
use vf_as1::registers::{CommandWord12wire, FrequencyCommand2wire, OutputFrequency, Status1};
use vfd_drives::{vf_as1, yd1000};
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::{Outcome, Simulator};
use vfd_runtime::{
    block_word, BlockSelection, CommandKind, EncodeError, Request, TransactionError,
    TransactionErrorKind,
};

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).unwrap())
        .collect()
}

/// Writes `raw` to the register `code` with the persistent write (W), as a master would set
/// up the drive before a reset.
fn set_persistent(
    master: &mut vfd_runtime::transaction::Master<
        impl vfd_runtime::transport::Transport,
        vf_as1::Drive,
    >,
    code: &str,
    raw: u32,
) {
    let info = vf_as1::DRIVE.register(code).unwrap();
    master
        .transact(&Request::for_register(
            CommandKind::WritePersistent,
            info,
            raw,
        ))
        .unwrap();
}

/// The selection the manual's example assumes: F870 = 1, F871 = 3, F875-F879 = 1-5.
fn manual_settings(register: u16) -> Option<u32> {
    match register {
        0x0870 => Some(1),
        0x0871 => Some(3),
        0x0875..=0x0879 => Some(u32::from(register - 0x0874)),
        _ => None,
    }
}

fn block_spec() -> &'static vfd_runtime::BlockSpec {
    vf_as1::protocols::BINARY.block.as_ref().unwrap()
}

#[test]
fn the_selection_resolves_through_the_code_tables_and_modes() {
    let spec = block_spec();
    assert_eq!(
        spec.default_selection(),
        BlockSelection {
            write: vec![None, None],
            read: vec![None; 5],
        }
    );
    assert_eq!(
        spec.selection(manual_settings),
        BlockSelection {
            write: vec![Some(0xFA00), Some(0xFA01)],
            read: vec![
                Some(0xFD01),
                Some(0xFD00),
                Some(0xFD03),
                Some(0xFD05),
                Some(0xFC91)
            ],
        }
    );
    let led = spec.selection(|register| match register {
        0xFA80 => Some(1),
        other => manual_settings(other),
    });
    let fa70_74: Vec<Option<u16>> = (0xFA70..=0xFA74).map(Some).collect();
    assert_eq!(led.write, fa70_74);
    assert_eq!(led.read, fa70_74);
    // F875 = 20 reads the motor speed monitor FE90; 19 the free notes F880.
    let last = spec.selection(|register| match register {
        0x0875 => Some(20),
        0x0876 => Some(19),
        _ => None,
    });
    assert_eq!(&last.read[..2], &[Some(0xFE90), Some(0x0880)]);
}

#[test]
fn the_manual_example_comes_from_the_virtual_drive() {
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut master = sim.master(&vf_as1::protocols::BINARY).with_address(None);
    let spec = block_spec();
    let writes = [0xC400, 0x1770];

    // Factory state: nothing selected, both writes fail, five words of 0000h (4.1.3,
    // "parameters not set", with the byte the manual leaves out).
    let outcome = master
        .block_transfer(&spec.default_selection(), &writes, 5)
        .unwrap();
    assert_eq!(outcome.write_status, 0x03);
    assert!(outcome.write_failed(0) && outcome.write_failed(1));
    assert_eq!(
        master.last_reply(),
        hex("2F 59 05 03 00 00 00 00 00 00 00 00 00 00 90")
    );

    // Set the selection; it takes effect only at the next reset.
    set_persistent(&mut master, "F870", 1);
    set_persistent(&mut master, "F871", 3);
    for (offset, code) in ["F875", "F876", "F877", "F878", "F879"].iter().enumerate() {
        set_persistent(&mut master, code, offset as u32 + 1);
    }
    let before_reset = master
        .block_transfer(&spec.default_selection(), &writes, 5)
        .unwrap();
    assert_eq!(
        before_reset.write_status, 0x03,
        "the selectors wait for a reset"
    );
    sim.power_cycle();
    sim.advance(vf_as1::SERIAL.timing.startup_delay);
    let selection = spec.selection(manual_settings);
    assert_eq!(
        sim.lock().block_selection(&vf_as1::protocols::BINARY),
        Some(selection.clone())
    );

    // The first transfer: the run command is written, the reads show the drive before it
    // acted (4.1.3, "parameters set", corrected).
    let first = master.block_transfer(&selection, &writes, 5).unwrap();
    assert_eq!(first.write_status, 0);
    assert_eq!(first.writes, vec![Some(0xFA00), Some(0xFA01)]);
    assert_eq!(
        master.last_reply(),
        hex("2F 59 05 00 40 00 00 00 00 00 00 00 00 00 CD")
    );

    // Running at 60 Hz. The output voltage is not modelled: set as the drive would show it.
    // The words, typed: command word 1 (priority, frequency priority, run) and 60 Hz.
    sim.advance(Duration::from_secs(30));
    assert!(sim.lock().set_raw("FD05", 0x24FD));
    let run = vf_as1::bits::CommandWord1::new()
        .with_command_priority(true)
        .with_frequency_priority(true)
        .with_run(true);
    let typed = [
        block_word::<CommandWord12wire>(&run).unwrap(),
        block_word::<FrequencyCommand2wire>(&Hertz(60.0)).unwrap(),
    ];
    assert_eq!(typed, writes);
    let running = master.block_transfer(&selection, &typed, 5).unwrap();
    assert_eq!(
        master.last_reply(),
        hex("2F 59 05 00 64 00 17 70 1A 8A 24 FD 00 00 3D")
    );
    assert_eq!(
        running.reads,
        vec![
            (Some(0xFD01), 0x6400),
            (Some(0xFD00), 0x1770),
            (Some(0xFD03), 0x1A8A),
            (Some(0xFD05), 0x24FD),
            (Some(0xFC91), 0x0000),
        ]
    );
    assert!(!running.tripped);
    assert_eq!(
        running.value::<OutputFrequency>().unwrap().unwrap(),
        Hertz(60.0)
    );
    assert!(running.value::<Status1>().unwrap().unwrap().running());
    assert!(
        running.value::<FrequencyCommand2wire>().is_none(),
        "not read"
    );
    assert_eq!(running.written::<FrequencyCommand2wire>(), Some(true));
    assert_eq!(running.written::<OutputFrequency>(), None);
}

#[test]
fn the_led_mode_writes_the_led_data_and_reads_it_before_the_change() {
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut master = sim.master(&vf_as1::protocols::BINARY).with_address(None);
    let info = vf_as1::DRIVE.register("FA80").unwrap();
    master
        .transact(&Request::for_register(CommandKind::WriteRam, info, 1))
        .unwrap();
    let selection = sim
        .lock()
        .block_selection(&vf_as1::protocols::BINARY)
        .unwrap();
    let outcome = master
        .block_transfer(&selection, &[0x30, 0x31, 0x32, 0x33, 0x03], 5)
        .unwrap();
    assert_eq!(
        master.last_reply(),
        hex("2F 59 05 00 00 64 00 41 00 74 00 41 00 00 E7")
    );
    assert_eq!(outcome.write_status, 0);
    let shown: Vec<Option<u32>> = ["FA70", "FA71", "FA72", "FA73", "FA74"]
        .iter()
        .map(|code| sim.lock().raw(code))
        .collect();
    assert_eq!(
        shown,
        [Some(0x30), Some(0x31), Some(0x32), Some(0x33), Some(0x03)]
    );
}

#[test]
fn requests_the_drive_cannot_take_are_answered_as_the_manual_says() {
    let sim = Simulator::new(&vf_as1::DRIVE);
    let protocol = vf_as1::protocols::BINARY.protocol();
    let mut drive = sim.lock();
    // A bad sum: the checksum error reply (4.1.3 2)).
    assert_eq!(
        drive.respond(protocol, &hex("2F 58 02 05 C4 00 17 70 D8")),
        Outcome::Reply(hex("2F 4E 00 04 81"))
    );
    // Three words to write where the selection has two: a format error, no reply.
    let three = hex("2F 58 03 00 00 01 00 02 00 03 90");
    assert!(matches!(
        drive.respond(protocol, &three),
        Outcome::Silent(_)
    ));
    // Six words asked back: answered with none (4.1.3 5.).
    assert_eq!(
        drive.respond(protocol, &hex("2F 58 00 06 8D")),
        Outcome::Reply(hex("2F 59 00 00 88"))
    );
}

#[test]
fn a_refused_write_sets_its_status_bit() {
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut master = sim.master(&vf_as1::protocols::BINARY);
    for (code, raw) in [("F870", 1), ("F871", 3), ("F875", 2)] {
        set_persistent(&mut master, code, raw);
    }
    sim.power_cycle();
    sim.advance(vf_as1::SERIAL.timing.startup_delay);
    let selection = sim
        .lock()
        .block_selection(&vf_as1::protocols::BINARY)
        .unwrap();
    // FA01 above FH (80 Hz) is refused; FA00 takes its word.
    let outcome = master
        .block_transfer(&selection, &[0x0000, 0xFFFF], 1)
        .unwrap();
    assert_eq!(outcome.write_status, 0x02);
    assert!(!outcome.write_failed(0) && outcome.write_failed(1));
    assert_eq!(outcome.reads, vec![(Some(0xFD00), 0)]);
}

#[test]
fn more_words_than_the_selection_has_are_refused_before_sending() {
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut master = sim.master(&vf_as1::protocols::BINARY);
    let selection = block_spec().default_selection();
    for (writes, reads) in [(&[1u16, 2, 3][..], 0u8), (&[][..], 6)] {
        let error: TransactionError = master
            .block_transfer(&selection, writes, reads)
            .unwrap_err();
        assert!(
            matches!(
                error.kind,
                TransactionErrorKind::Encode(EncodeError::BlockTooLong { .. })
            ),
            "{error}"
        );
    }
    assert_eq!(sim.lock().requests(), 0, "nothing was sent");
}

#[test]
fn a_drive_without_a_block_selection_has_no_block_command() {
    assert!(yd1000::protocols::BINARY.block_command().is_none());
    assert!(yd1000::protocols::BINARY.block.is_none());
    assert!(vf_as1::protocols::BINARY.block_command().is_some());
    assert!(vf_as1::protocols::ASCII.block_command().is_none());
    let sim = Simulator::new(&yd1000::DRIVE);
    let protocol = yd1000::protocols::BINARY.protocol();
    assert!(matches!(
        sim.lock()
            .respond(protocol, &hex("2F 58 02 05 C4 00 17 70 D9")),
        Outcome::Silent(_)
    ));
    let mut master = sim.master(&yd1000::protocols::BINARY);
    let error = master
        .block_transfer(&BlockSelection::default(), &[], 0)
        .unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Encode(EncodeError::UnsupportedCommand { .. })
        ),
        "{error}"
    );
}

#[test]
fn a_tripped_drive_answers_with_a_lower_case_y() {
    let sim = Simulator::new(&vf_as1::DRIVE);
    let mut master = sim.master(&vf_as1::protocols::BINARY).with_address(None);
    sim.inject_trip(0x18);
    let outcome = master
        .block_transfer(&block_spec().default_selection(), &[], 0)
        .unwrap();
    assert!(outcome.tripped);
    assert!(outcome.reads.is_empty());
    // 2Fh + 79h ('y') + count 0 + status 0.
    assert_eq!(master.last_reply(), hex("2F 79 00 00 A8"));
}
