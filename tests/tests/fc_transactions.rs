//! The FC drive through both of its protocols: the same typed calls over FC telegrams and
//! Modbus RTU, array parameters, persistent writes, text, process data and error replies.

use std::time::Duration;
use vfd_drives::fc51::{self, bits, protocols, registers};
use vfd_runtime::serial::DriveTiming;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{memory_pair, MemoryTransport};
use vfd_runtime::units::Percent;
use vfd_runtime::{DecodeErrorKind, TransactionErrorKind};
use vfd_tests::scripted_peer::answer;

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("hex"))
        .collect()
}

fn master(
    protocol: &'static vfd_runtime::DriveProtocol<fc51::Drive>,
    replies: &[&str],
) -> (
    Master<MemoryTransport, fc51::Drive>,
    std::thread::JoinHandle<Vec<Vec<u8>>>,
) {
    let (ours, theirs) = memory_pair();
    let peer = answer(theirs, protocol, replies.iter().map(|r| hex(r)).collect());
    let timing = DriveTiming {
        processing_allowance: Duration::from_millis(50),
        ..fc51::SERIAL.timing
    };
    (
        Master::new(ours, protocol, fc51::SERIAL.default, timing).with_address(Some(1)),
        peer,
    )
}

fn shown(frames: &[Vec<u8>]) -> Vec<String> {
    frames.iter().map(|f| vfd_runtime::error::hex(f)).collect()
}

#[test]
fn parameter_303_reads_the_same_through_both_protocols() {
    // FC telegram: AK 1 read of 303; the drive answers AK 2 (double word) 60000.
    let (mut fc, fc_peer) = master(
        &protocols::FC,
        &["02 0E 01 21 2F 00 00 00 00 EA 60 00 03 00 00 8A"],
    );
    let via_fc = fc.read::<registers::MaximumReference>().unwrap();
    // Modbus RTU: function 03 at 303 x 10 - 1 = 0BD5h, two registers (the manual's frames).
    let (mut modbus, modbus_peer) = master(&protocols::MODBUS, &["01 03 04 00 00 EA 60 B5 7B"]);
    let via_modbus = modbus.read::<registers::MaximumReference>().unwrap();
    assert_eq!(via_fc, 60.0);
    assert_eq!(via_fc, via_modbus);
    assert_eq!(
        shown(&fc_peer.join().unwrap()),
        ["02 0E 01 11 2F 00 00 00 00 00 00 00 00 00 00 33"]
    );
    assert_eq!(
        shown(&modbus_peer.join().unwrap()),
        ["01 03 0B D5 00 02 D7 D7"]
    );
}

#[test]
fn array_parameters_select_the_index_first_on_modbus() {
    let (mut modbus, peer) = master(
        &protocols::MODBUS,
        &["01 06 00 08 00 02 89 C9", "01 03 02 00 00 B8 44"],
    );
    assert_eq!(modbus.read_at::<registers::PresetReference>(2).unwrap(), 0);
    // Exactly the manual's two frames (with the CRC it leaves out).
    assert_eq!(
        shown(&peer.join().unwrap()),
        ["01 06 00 08 00 02 89 C9", "01 03 0C 1B 00 01 F7 5D"]
    );
}

#[test]
fn array_parameters_carry_the_index_in_fc_telegrams() {
    let (mut fc, peer) = master(
        &protocols::FC,
        &["02 0E 01 11 36 00 02 00 00 00 00 00 03 00 00 2B"],
    );
    assert_eq!(fc.read_at::<registers::PresetReference>(2).unwrap(), 0);
    let sent = peer.join().unwrap();
    assert_eq!(
        &sent[0][3..7],
        [0x11, 0x36, 0x00, 0x02],
        "PKE 1136h, IND 0002h"
    );
    let error = fc.read_at::<registers::PresetReference>(4).unwrap_err();
    assert!(
        error.to_string().contains("outside the array of 4"),
        "{error}"
    );
}

/// A Modbus RTU frame from its bytes without the CRC, with the CRC appended.
fn with_crc(text: &str) -> String {
    let mut bytes = hex(text);
    let crc = vfd_runtime::checksum::crc16_modbus(&bytes);
    bytes.extend(crc.to_le_bytes());
    vfd_runtime::error::hex(&bytes)
}

#[test]
fn array_elements_are_written_after_selecting_the_index() {
    // The drive echoes each 05 and 06 request.
    let select_index = with_crc("01 06 00 08 00 03");
    let write = with_crc("01 06 0C 1B 00 05");
    for (persistent, coil_65) in [
        (false, "01 05 00 40 00 00 CC 1E"),
        (true, "01 05 00 40 FF 00 8D EE"),
    ] {
        let (mut modbus, peer) = master(&protocols::MODBUS, &[&select_index, coil_65, &write]);
        let written = if persistent {
            modbus.write_persistent_at::<registers::PresetReference>(3, 5)
        } else {
            modbus.write_ram_at::<registers::PresetReference>(3, 5)
        };
        assert_eq!(written.unwrap(), Some(5), "06 echoes the value written");
        assert_eq!(
            shown(&peer.join().unwrap()),
            [select_index.as_str(), coil_65, write.as_str()],
            "persistent: {persistent}"
        );
    }
    let (mut modbus, _peer) = master(&protocols::MODBUS, &[]);
    let error = modbus
        .write_ram_at::<registers::PresetReference>(4, 5)
        .unwrap_err();
    assert!(
        error.to_string().contains("outside the array of 4"),
        "{error}"
    );
}

#[test]
fn persistent_modbus_writes_switch_coil_65_first() {
    let (mut modbus, peer) = master(
        &protocols::MODBUS,
        &["01 05 00 40 FF 00 8D EE", "01 10 0B D5 00 02 52 14"],
    );
    assert_eq!(
        modbus
            .write_persistent::<registers::MaximumReference>(60.0)
            .unwrap(),
        None,
        "a 10 reply names the registers written, not their value"
    );
    assert_eq!(
        shown(&peer.join().unwrap()),
        [
            "01 05 00 40 FF 00 8D EE",
            "01 10 0B D5 00 02 04 00 00 EA 60 02 B4"
        ]
    );
    let (mut modbus, peer) = master(
        &protocols::MODBUS,
        &["01 05 00 40 00 00 CC 1E", "01 06 03 F1 00 01 19 BD"],
    );
    assert_eq!(
        modbus.write_ram::<registers::Parameter101>(1).unwrap(),
        Some(1),
        "06 echoes the value written"
    );
    assert_eq!(
        shown(&peer.join().unwrap()),
        ["01 05 00 40 00 00 CC 1E", "01 06 03 F1 00 01 19 BD"]
    );
}

#[test]
fn fc_persistent_word_writes_use_ak_e() {
    let (mut fc, peer) = master(
        &protocols::FC,
        &["02 0E 01 15 8E 00 00 00 00 00 02 00 03 00 00 97"],
    );
    assert_eq!(
        fc.write_persistent::<registers::Parameter1422>(2).unwrap(),
        Some(2)
    );
    assert_eq!(peer.join().unwrap()[0][3], 0xE5, "AK E, parameter 58Eh");
}

#[test]
fn text_parameters_read_as_text() {
    let (mut fc, _peer) = master(
        &protocols::FC,
        &["02 12 01 F6 0A 00 00 31 33 32 46 30 30 30 32 00 03 00 00 9A"],
    );
    assert_eq!(
        fc.read_text::<registers::OrderingNumber>().unwrap(),
        "132F0002"
    );
}

#[test]
fn a_decoded_text_reply_gives_its_bytes() {
    let frame = hex("02 12 01 F6 0A 00 00 31 33 32 46 30 30 30 32 00 03 00 00 9A");
    let reply = protocols::FC.decode_reply_exact(None, &frame).unwrap();
    let vfd_runtime::Reply::Data {
        command, values, ..
    } = reply
    else {
        panic!("a data reply: {reply:?}")
    };
    let text = values.bytes(&command.reply, vfd_runtime::Role::Text, &frame);
    assert_eq!(text, Some(&b"132F0002"[..]));
}

#[test]
fn process_words_go_out_and_come_back() {
    let (mut fc, peer) = master(&protocols::FC, &["02 06 01 0D 07 20 00 2F"]);
    let control = bits::ControlWord::new()
        .with_no_dc_brake(true)
        .with_no_coast(true)
        .with_no_quick_stop(true)
        .with_no_freeze(true)
        .with_start(true)
        .with_data_valid(true);
    let reference = fc51::REFERENCE_SCALING.raw(50.0).unwrap();
    let [status, output] = fc.exchange_process(control.bits(), reference).unwrap();
    assert_eq!(shown(&peer.join().unwrap()), ["02 06 01 04 7C 20 00 5D"]);
    let status = bits::StatusWord(status);
    assert!(status.running() && status.at_reference() && !status.tripped());
    let values = |id: &str| match id {
        "reference_range" => Some(1.0),
        "maximum_reference" => Some(60.0),
        _ => None,
    };
    assert_eq!(fc51::REFERENCE_SCALING.value(output, values), Some(30.0));
}

#[test]
fn process_words_through_modbus_coils() {
    let (mut modbus, peer) = master(
        &protocols::MODBUS,
        &["01 01 02 00 20 B8 24", "01 0F 00 00 00 10 54 07"],
    );
    assert_eq!(
        modbus.read::<registers::OutputFrequency>().unwrap(),
        Percent(50.0)
    );
    let run = bits::ControlWord(0x047C);
    modbus.write_ram::<registers::ControlWord>(run).unwrap();
    let sent = shown(&peer.join().unwrap());
    assert_eq!(sent[0], "01 01 00 30 00 10 3D C9");
    assert_eq!(
        &sent[1][..26],
        "01 0F 00 00 00 10 02 7C 04",
        "16 coils, low byte first"
    );
}

#[test]
fn error_replies_name_the_manual_error() {
    // FC: AK 7 with error number 2 in PWE.
    let (mut fc, _peer) = master(
        &protocols::FC,
        &["02 0E 01 71 2F 00 00 00 00 00 02 00 03 00 00 52"],
    );
    let error = fc
        .write_ram::<registers::MaximumReference>(99.0)
        .unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Rejected { code: 2, .. }),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(
        message.contains("参数的值超出该参数的上限") && message.contains("303"),
        "{message}"
    );
    // Modbus: exception 83h with error number 0.
    let (mut modbus, _peer) = master(&protocols::MODBUS, &["01 83 00 41 30"]);
    let error = modbus.read::<registers::JogFrequency>().unwrap_err();
    assert!(
        error
            .to_string()
            .contains("Parameter number does not exist"),
        "{error}"
    );
}

#[test]
fn a_bad_bcc_is_a_typed_error() {
    let (mut fc, _peer) = master(&protocols::FC, &["02 06 01 00 03 20 00 06"]);
    let error = fc.exchange_process(0x043C, 0x2000).unwrap_err();
    assert!(
        matches!(&error.kind, TransactionErrorKind::Decode(source) if source.kind() == DecodeErrorKind::ChecksumMismatch),
        "{error:?}"
    );
}

#[test]
fn a_request_the_protocol_cannot_carry_names_the_register() {
    // Modbus has no text function: the error must say which parameter was asked for.
    let (mut modbus, peer) = master(&protocols::MODBUS, &[]);
    let error = modbus.read_text::<registers::OrderingNumber>().unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Encode(_)),
        "{error:?}"
    );
    let message = error.to_string();
    for needle in ["1546", "参数 1546", "read_text", "modbus"] {
        assert!(
            message.contains(needle),
            "`{message}` should contain {needle}"
        );
    }
    assert!(peer.join().unwrap().is_empty(), "nothing may be sent");
}
