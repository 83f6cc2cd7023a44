//! Request/reply exchanges through the master over in-memory pipes and a pseudo-terminal:
//! typed reads and writes, error replies, noise, bad checksums, silence.

use std::time::Duration;
use vfd_drives::yd1000::{self, protocols, registers};
use vfd_runtime::prelude::*;
use vfd_runtime::serial::DriveTiming;
use vfd_runtime::transaction::Master;
use vfd_runtime::transaction::ReplyField;
use vfd_runtime::transport::{memory_pair, PseudoTerminal};
use vfd_runtime::units::Hertz;
use vfd_runtime::{DecodeErrorKind, Request, TransactionErrorKind};
use vfd_tests::scripted_peer::answer;

/// The drive's timing with a short allowance, so the silence tests end quickly.
fn quick_timing() -> DriveTiming {
    DriveTiming {
        processing_allowance: Duration::from_millis(50),
        ..yd1000::SERIAL.timing
    }
}

fn master_with(
    replies: Vec<&[u8]>,
    protocol: &'static vfd_runtime::DriveProtocol<yd1000::Drive>,
) -> (
    Master<vfd_runtime::transport::MemoryTransport, yd1000::Drive>,
    std::thread::JoinHandle<Vec<Vec<u8>>>,
) {
    let (ours, theirs) = memory_pair();
    let peer = answer(
        theirs,
        protocol,
        replies.into_iter().map(<[u8]>::to_vec).collect(),
    );
    (
        Master::new(ours, protocol, yd1000::SERIAL.default, quick_timing()),
        peer,
    )
}

#[test]
fn reads_the_output_frequency_in_hertz() {
    let (mut master, peer) = master_with(vec![b"(RFD001770)\r"], &protocols::ASCII);
    assert_eq!(
        master.read::<registers::OutputFrequencyNow>().unwrap(),
        Hertz(60.0)
    );
    assert_eq!(peer.join().unwrap(), vec![b"(RFD00&8A)\r".to_vec()]);
}

#[test]
fn writes_60_hz_in_ram_over_binary() {
    let (mut master, peer) = master_with(
        vec![&[0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01]],
        &protocols::BINARY,
    );
    assert_eq!(
        master
            .write_ram::<registers::FrequencyCommand>(Hertz(60.0))
            .unwrap(),
        Some(Hertz(60.0)),
        "the drive's echo of the written value"
    );
    assert_eq!(
        peer.join().unwrap(),
        vec![vec![0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01]]
    );
}

#[test]
fn an_error_reply_names_the_code_and_its_meaning() {
    let (mut master, _peer) = master_with(vec![b"(N0001&5D)\r"], &protocols::ASCII);
    let error = master
        .write_ram::<registers::MaximumFrequency>(Hertz(100.0))
        .unwrap_err();
    assert!(
        matches!(
            &error.kind,
            TransactionErrorKind::Rejected {
                code: 1,
                tripped: false,
                info: Some(_),
                ..
            }
        ),
        "{error:?}"
    );
    let message = error.to_string();
    for needle in ["0001h", "Data error", "数据错误", "FH", "0011"] {
        assert!(
            message.contains(needle),
            "`{message}` should contain {needle}"
        );
    }
}

#[test]
fn a_lower_case_reply_reports_a_tripped_drive() {
    let (mut master, _peer) = master_with(vec![b"(rFE010400)\r", b"(n0000)\r"], &protocols::ASCII);
    let answer = master.transact(&registers::Status::read()).unwrap();
    assert!(answer.tripped);
    assert_eq!(answer.data, Some(0x0400));
    let error = master.transact(&registers::Status::read()).unwrap_err();
    assert!(error.to_string().contains("tripped"), "{error}");
}

#[test]
fn a_typed_read_shows_the_tripped_drive_with_its_value() {
    let (mut master, _peer) =
        master_with(vec![b"(rFE010400)\r", b"(RFD001770)\r"], &protocols::ASCII);
    let status = master.read::<registers::Status>().unwrap();
    assert!(status.tripped, "lower-case `r`: the drive is tripped");
    assert!(status.running(), "the value comes with it (bit 10)");
    assert!(status.to_string().ends_with("(drive tripped)"), "{status}");
    let frequency = master.read::<registers::OutputFrequencyNow>().unwrap();
    assert!(!frequency.tripped);
    assert_eq!(frequency.into_value(), Hertz(60.0));
}

#[test]
fn noise_before_the_start_character_is_skipped() {
    let (mut master, _peer) = master_with(vec![b"\x00\xFFzz)(RFD001770)\r"], &protocols::ASCII);
    assert_eq!(
        master.read::<registers::OutputFrequencyNow>().unwrap(),
        Hertz(60.0)
    );
    // Binary start bytes (2F) inside noise do not confuse the search either.
    let (mut master, _peer) = master_with(
        vec![&[0x2F, 0x00, 0x2F, 0x52, 0xFD, 0x00, 0x17, 0x70, 0x05]],
        &protocols::BINARY,
    );
    assert_eq!(
        master.read::<registers::OutputFrequencyNow>().unwrap(),
        Hertz(60.0)
    );
}

#[test]
fn a_wrong_checksum_is_a_typed_error_without_waiting_for_the_timeout() {
    let (mut master, _peer) = master_with(
        vec![&[0x2F, 0x52, 0xFC, 0x90, 0x00, 0x18, 0x45]],
        &protocols::BINARY,
    );
    let error = master.transact(&registers::AlarmCode::read()).unwrap_err();
    match &error.kind {
        TransactionErrorKind::Decode(source) => {
            assert_eq!(source.kind(), DecodeErrorKind::ChecksumMismatch)
        }
        other => panic!("expected a decode error, got {other:?}"),
    }
    assert!(error.to_string().contains("FC90"), "{error}");
}

#[test]
fn silence_is_a_timeout_not_a_hang() {
    let (mut master, _peer) = master_with(vec![b""], &protocols::ASCII);
    let error = master.read::<registers::OutputFrequencyNow>().unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Timeout {
                received_len: 0,
                ..
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("FD00"), "{error}");
}

#[test]
fn garbage_without_a_frame_times_out_and_reports_what_arrived() {
    let (mut master, _peer) = master_with(vec![b"garbage"], &protocols::ASCII);
    let error = master.read::<registers::OutputFrequencyNow>().unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Timeout {
                received_len: 7,
                ..
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("67 61 72"), "{error}");
}

#[test]
fn a_reply_for_another_register_is_a_mismatch() {
    let (mut master, _peer) = master_with(vec![b"(RFE001770)\r"], &protocols::ASCII);
    let error = master.read::<registers::OutputFrequencyNow>().unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Mismatch {
                field: ReplyField::Register,
                expected: 0xFD00,
                found: 0xFE00,
                ..
            }
        ),
        "{error:?}"
    );
}

#[test]
fn an_out_of_range_write_sends_nothing() {
    let (ours, theirs) = memory_pair();
    let mut master = Master::new(
        ours,
        &protocols::BINARY,
        yd1000::SERIAL.default,
        quick_timing(),
    );
    let error = master
        .write_ram::<registers::FrequencyCommand>(Hertz(400.0))
        .unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Value(_)),
        "{error:?}"
    );
    assert_eq!(theirs.pending(), 0, "no byte may reach the line");
}

#[test]
fn station_numbers_are_sent_and_checked() {
    let (master, peer) = master_with(
        vec![b"(07RFD001770)\r", b"(08RFD001770)\r"],
        &protocols::ASCII,
    );
    let mut master_7 = master.with_address(Some(7));
    assert_eq!(
        master_7.read::<registers::OutputFrequencyNow>().unwrap(),
        Hertz(60.0)
    );
    let error = master_7
        .read::<registers::OutputFrequencyNow>()
        .unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Mismatch {
                field: ReplyField::Address,
                expected: 7,
                found: 8,
                ..
            }
        ),
        "{error:?}"
    );
    let sent = peer.join().unwrap();
    assert!(
        sent[0].starts_with(b"(07R"),
        "{:?}",
        String::from_utf8_lossy(&sent[0])
    );
}

#[test]
fn exchanges_work_over_a_pseudo_terminal() {
    let pty = PseudoTerminal::open().expect("a pseudo-terminal");
    let (ours, theirs) = pty.into_transports().expect("both ends");
    let peer = answer(
        theirs,
        &protocols::BINARY,
        vec![
            vec![0x2F, 0x52, 0xFE, 0x03, 0x07, 0x7B, 0x04],
            vec![0x2F, 0x4E, 0x00, 0x02, 0x7F],
        ],
    );
    let mut master = Master::new(
        ours,
        &protocols::BINARY,
        yd1000::SERIAL.default,
        quick_timing(),
    );
    let answer = master
        .transact(&Request::read::<registers::OutputCurrent>())
        .unwrap();
    assert_eq!(answer.data, Some(0x077B));
    let error = master
        .transact(&Request::raw(vfd_runtime::CommandKind::Read, 0x1234, 0))
        .unwrap_err();
    assert!(
        error.to_string().contains("Communication number error"),
        "{error}"
    );
    assert_eq!(peer.join().unwrap().len(), 2);
}

#[test]
fn a_reply_missing_its_data_is_named_with_the_register() {
    let request = registers::OutputFrequencyNow::read().into_request();
    let error = vfd_runtime::TransactionError::new(
        Some(&request),
        TransactionErrorKind::Mismatch {
            field: ReplyField::Data,
            expected: 1,
            found: 0,
        },
    );
    let message = error.to_string();
    assert!(message.contains("carries no data"), "{message}");
    assert!(message.contains("FD00"), "names the register: {message}");
    assert!(!message.contains("0x"), "no raw presence counts: {message}");
}
