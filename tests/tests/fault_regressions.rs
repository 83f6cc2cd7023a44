//! Regressions from the fault campaign: the master against an echoing adapter, false
//! starts, noise, a line that never falls silent, stale input, late replies, refused
//! pre-steps and retries, over the in-memory transport with a scripted drive. Each test
//! names the fault it guards against; time bounds are generous multiples of the master's
//! own timeout.

use std::sync::mpsc;
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};
use vfd_drives::fc51::{self, protocols, registers};
use vfd_runtime::protocol::Found;
use vfd_runtime::serial::DriveTiming;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{memory_pair, MemoryTransport, Transport};
use vfd_runtime::{CommandKind, DriveProtocol, Request, TransactionErrorKind};
use vfd_tests::scripted_peer::answer;
use vfd_tests::watched::Watched;

/// Added to a bound that says "no hang": time the machine may lose to other work (a
/// loaded CI runner), so the assertion is about hangs, not durations.
const HANG: Duration = Duration::from_secs(2);

type Fc51Master<T> = Master<T, fc51::Drive>;

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("hex"))
        .collect()
}

/// A Modbus RTU frame from its bytes without the CRC, with the CRC appended.
fn with_crc(text: &str) -> Vec<u8> {
    let mut bytes = hex(text);
    let crc = vfd_runtime::checksum::crc16_modbus(&bytes);
    bytes.extend(crc.to_le_bytes());
    bytes
}

/// The drive's timing with a short allowance, so that timeouts end quickly.
fn timing() -> DriveTiming {
    DriveTiming {
        processing_allowance: Duration::from_millis(50),
        ..fc51::SERIAL.timing
    }
}

fn master<T: Transport>(
    transport: T,
    protocol: &'static DriveProtocol<fc51::Drive>,
) -> Fc51Master<T> {
    Master::new(transport, protocol, fc51::SERIAL.default, timing()).with_address(Some(1))
}

/// Reads one whole request frame from `transport` (`None` when none comes within 5 s).
fn next_request<T: Transport>(
    transport: &mut T,
    protocol: &DriveProtocol<fc51::Drive>,
) -> Option<Vec<u8>> {
    let deadline = Instant::now() + Duration::from_secs(5);
    let mut buffer = Vec::new();
    loop {
        let mut chunk = [0u8; 64];
        let got = transport.receive(&mut chunk, deadline).ok()?;
        if got == 0 {
            return None;
        }
        buffer.extend_from_slice(&chunk[..got]);
        if let Ok(Found::Frame { frame, .. }) = protocol.decode_request(&buffer) {
            return Some(buffer[..frame.len].to_vec());
        }
    }
}

/// A scripted drive, behind a half-duplex adapter that echoes when `echo` is set: for each
/// entry of `replies` it waits for a request (which the adapter returns to the master
/// unchanged), then sends the entry's bursts, each after its pause. Returns the requests
/// received.
fn drive_with_bursts(
    mut transport: MemoryTransport,
    protocol: &'static DriveProtocol<fc51::Drive>,
    echo: bool,
    replies: Vec<Vec<(Duration, Vec<u8>)>>,
) -> JoinHandle<Vec<Vec<u8>>> {
    thread::spawn(move || {
        let mut received = Vec::new();
        for bursts in replies {
            let Some(request) = next_request(&mut transport, protocol) else {
                break;
            };
            if echo {
                let _ = transport.send(&request);
            }
            received.push(request);
            for (pause, burst) in bursts {
                thread::sleep(pause);
                let _ = transport.send(&burst);
            }
        }
        received
    })
}

/// One burst sent at once.
fn now(bytes: Vec<u8>) -> (Duration, Vec<u8>) {
    (Duration::ZERO, bytes)
}

/// Runs `work` on another thread and gives its result, or fails the test when it has not
/// finished within `limit` (a hang must fail, not stall the suite).
fn within<R: Send + 'static>(limit: Duration, work: impl FnOnce() -> R + Send + 'static) -> R {
    let (done, result) = mpsc::channel();
    thread::spawn(move || {
        let _ = done.send(work());
    });
    result
        .recv_timeout(limit)
        .unwrap_or_else(|_| panic!("still running after {limit:?}: the exchange hangs"))
}

// Fault 1: an echoing adapter returns the FC request, which decodes as a reply.

#[test]
fn an_echoed_fc_request_is_not_taken_for_the_reply() {
    let (ours, theirs) = memory_pair();
    let drive = drive_with_bursts(
        theirs,
        &protocols::FC,
        true,
        vec![
            vec![now(hex("02 0E 01 21 2F 00 00 00 00 EA 60 00 03 00 00 8A"))],
            vec![now(hex("02 06 01 0D 07 20 00 2F"))],
        ],
    );
    let mut fc = master(ours, &protocols::FC);
    let started = Instant::now();
    let read = fc.read::<registers::MaximumReference>().unwrap();
    assert_eq!(
        read, 60.0,
        "the drive's value, not the 0 of the echoed request"
    );
    let words = fc.exchange_process(0x047C, 0x2000).unwrap();
    assert_eq!(
        words,
        [0x0D07, 0x2000],
        "the drive's status word, not the words sent"
    );
    let bound = fc.reply_timeout(16) * 2 + HANG;
    assert!(
        started.elapsed() < bound,
        "{:?} >= {bound:?}",
        started.elapsed()
    );
    assert_eq!(drive.join().unwrap().len(), 2);
}

#[test]
fn an_echoed_modbus_write_waits_for_the_drive_s_own_reply() {
    // Modbus answers a single write with the request's own bytes, so the echo looks like
    // success: once the line is known to echo, the drive's refusal must come through.
    let read = with_crc("01 03 0B D5 00 02");
    let coil_65 = hex("01 05 00 40 00 00 CC 1E");
    let (ours, theirs) = memory_pair();
    let drive = drive_with_bursts(
        theirs,
        &protocols::MODBUS,
        true,
        vec![
            vec![now(hex("01 03 04 00 00 EA 60 B5 7B"))],
            vec![now(coil_65.clone())],
            vec![now(with_crc("01 86 02"))],
        ],
    );
    let mut modbus = master(ours, &protocols::MODBUS);
    assert_eq!(modbus.read::<registers::MaximumReference>().unwrap(), 60.0);
    let error = modbus.write_ram::<registers::Parameter101>(1).unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Rejected { code: 2, .. }),
        "{error:?}"
    );
    let sent = drive.join().unwrap();
    assert_eq!(sent[0], read);
    assert_eq!(sent[1], coil_65);
}

// Fault 2: a false start followed by the whole reply passes the FC XOR check.

#[test]
fn a_false_start_before_an_fc_reply_is_passed_over() {
    let read_3 = Request::raw(CommandKind::Read, 3, 0);
    for bursts in [
        // All at once, as the fault campaign sent it.
        vec![now(hex(
            "02 0E 01 10 03 00 00 00 02 0E 01 10 03 00 00 00 00 12 34 06 03 10 00 2D",
        ))],
        // The false start, a pause, then the reply.
        vec![
            now(hex("02 0E 01 10 03 00 00 00")),
            (
                Duration::from_millis(20),
                hex("02 0E 01 10 03 00 00 00 00 12 34 06 03 10 00 2D"),
            ),
        ],
    ] {
        let (ours, theirs) = memory_pair();
        let _drive = drive_with_bursts(theirs, &protocols::FC, false, vec![bursts]);
        let mut fc = master(ours, &protocols::FC);
        let answer = fc.transact(&read_3).unwrap();
        assert_eq!(answer.data, Some(0x1234), "not 0x20E01");
        assert_eq!(answer.process, Some([0x0603, 0x1000]));
    }
}

#[test]
fn a_silence_inside_a_modbus_reply_starts_a_new_frame() {
    // A fragment whose CRC happens to match once the first two bytes of the real reply
    // follow it: only the line's timing (more than 3.5 character times of silence before
    // the reply) tells it is not part of the reply.
    let crc_of = |d: [u8; 2]| vfd_runtime::checksum::crc16_modbus(&[0x01, 0x03, 0x02, d[0], d[1]]);
    let data = (0..=u16::MAX)
        .map(u16::to_be_bytes)
        .find(|d| crc_of(*d).to_le_bytes() == [0x01, 0x03])
        .expect("CRC-16 reaches every value with two free bytes");
    let fragment = vec![0x01, 0x03, 0x02, data[0], data[1]];
    let reply = with_crc("01 03 02 00 07");
    let (ours, theirs) = memory_pair();
    // The reply's two bursts follow each other at once, after 30 ms of silence.
    let _drive = drive_with_bursts(
        theirs,
        &protocols::MODBUS,
        false,
        vec![vec![
            now(fragment),
            (Duration::from_millis(30), reply[..2].to_vec()),
            now(reply[2..].to_vec()),
        ]],
    );
    let mut modbus = master(ours, &protocols::MODBUS);
    let answer = modbus
        .transact(&Request::raw(CommandKind::Read, 101, 0))
        .unwrap();
    assert_eq!(
        answer.data,
        Some(7),
        "not {:#06X}",
        u16::from_be_bytes(data)
    );
}

// Fault 3: pre-steps went out before the main request was checked.

#[test]
fn a_request_the_encoder_refuses_sends_no_pre_step() {
    // Parameter 7000 has no Modbus address (7000 x 10 - 1 > FFFFh).
    let persistent = Request::raw(CommandKind::WritePersistent, 7000, 1);
    let indexed = Request {
        index: Some(1),
        ..Request::raw(CommandKind::Read, 7000, 0)
    };
    for request in [persistent, indexed] {
        let (ours, theirs) = memory_pair();
        let mut modbus = master(ours, &protocols::MODBUS);
        let started = Instant::now();
        let error = modbus.transact(&request).unwrap_err();
        assert!(
            matches!(error.kind, TransactionErrorKind::Encode(_)),
            "{error:?}"
        );
        assert_eq!(
            error.request,
            Some(request),
            "the caller's request is named"
        );
        assert_eq!(theirs.pending(), 0, "no step may reach the drive");
        assert!(
            started.elapsed() < modbus.reply_timeout(8),
            "refused at once"
        );
    }
}

// Fault 4: a transport that always has bytes kept a read going past its deadline.

/// A line full of noise: every receive returns bytes at once.
struct EndlessNoise;

impl Transport for EndlessNoise {
    fn send(&mut self, _bytes: &[u8]) -> std::io::Result<()> {
        Ok(())
    }
    fn receive(&mut self, buf: &mut [u8], _deadline: Instant) -> std::io::Result<usize> {
        let count = buf.len().min(3);
        buf[..count].fill(0x55);
        Ok(count)
    }
}

#[test]
fn endless_noise_ends_at_the_reply_deadline() {
    for protocol in [&protocols::FC, &protocols::MODBUS] {
        let limit = master(EndlessNoise, protocol).reply_timeout(16) * 2 + HANG;
        let (outcome, elapsed) = within(Duration::from_secs(10), move || {
            let mut master = master(EndlessNoise, protocol);
            let started = Instant::now();
            let outcome = master.transact(&Request::raw(CommandKind::Read, 303, 0));
            (outcome, started.elapsed())
        });
        let error = outcome.unwrap_err();
        assert!(
            matches!(error.kind, TransactionErrorKind::Timeout { .. }),
            "{error:?}"
        );
        assert!(elapsed < limit, "{}: {elapsed:?} >= {limit:?}", protocol.id);
    }
}

// Fault 5: error replies were always named from the drive's table.

#[test]
fn an_error_reply_is_named_from_the_table_of_the_protocol_that_answered() {
    use vfd_codegen::ir::ErrorTableIr;
    let name_of = |table: &ErrorTableIr, drive: &vfd_codegen::DriveIr, code: u16| {
        let codes = match table {
            ErrorTableIr::Drive => &drive.error_codes.codes,
            ErrorTableIr::Protocol(own) => &own.codes,
        };
        codes
            .iter()
            .find(|c| c.code == code)
            .map(|c| c.name.clone())
    };
    // The fc51 manual lists its Errornum table for Modbus exception replies too, so its
    // table names both protocols' errors: exception 02 is its "value above the upper limit".
    let path = std::path::Path::new("../drives/fc51.yaml");
    let text = std::fs::read_to_string(path).expect("drives/fc51.yaml");
    let drive = vfd_codegen::compile_text(path, text.clone(), None).expect("fc51 compiles");
    for protocol in &drive.protocols {
        assert!(
            matches!(protocol.error_table, ErrorTableIr::Drive),
            "{}",
            protocol.id
        );
    }
    let exception = protocols::MODBUS
        .decode_reply_exact(None, &with_crc("01 83 02"))
        .expect("an exception reply");
    let vfd_runtime::Reply::Error { info, .. } = exception else {
        panic!("an error reply: {exception:?}")
    };
    assert_eq!(
        info.map(|i| i.name.as_ref()),
        Some("Value above the upper limit")
    );
    // A drive whose table covers only its FC telegrams: Modbus replies take the Modbus
    // protocol file's own exception codes (and its refusals answer with those codes).
    let fc_only = text
        .replace("protocols: [fc, modbus]", "protocols: [fc]")
        .replace(
            "modbus: { unknown_register: 64, read_only: 1, out_of_range: 2, while_running: 17 }",
            "modbus: { unknown_register: 2, read_only: 2, out_of_range: 3, while_running: 4 }",
        );
    assert_ne!(fc_only, text);
    let drive = vfd_codegen::compile_text(path, fc_only, None).expect("still valid");
    let table = |id: &str| {
        &drive
            .protocols
            .iter()
            .find(|p| p.id == id)
            .expect(id)
            .error_table
    };
    assert_eq!(
        name_of(table("modbus"), &drive, 2).as_deref(),
        Some("Illegal data address")
    );
    assert_eq!(
        name_of(table("fc"), &drive, 2).as_deref(),
        Some("Value above the upper limit")
    );
    assert_eq!(drive.error_codes.protocols, ["fc"]);
}

vfd_macros::include_drive!(
    "fixtures/error-tables/drive.yaml",
    protocols = "../drives/protocols"
);

#[test]
fn a_modbus_exception_is_named_from_the_modbus_table_when_the_drive_s_does_not_apply() {
    use error_tables::{protocols as own, registers as regs, SERIAL};
    let run = |protocol: &'static DriveProtocol<error_tables::Drive>, reply: Vec<u8>| {
        let (ours, theirs) = memory_pair();
        let _drive = answer(theirs, protocol, vec![reply]);
        let mut master =
            Master::new(ours, protocol, SERIAL.default, timing()).with_address(Some(1));
        master.read::<regs::MaximumFrequency>().unwrap_err()
    };
    let named = |error: vfd_runtime::TransactionError| match error.kind {
        TransactionErrorKind::Rejected {
            code,
            info: Some(info),
            ..
        } => (code, info.name.to_string()),
        other => panic!("a rejection naming the code: {other:?}"),
    };
    // Modbus exception 02: the protocol's own "illegal data address".
    let error = run(&own::MODBUS, with_crc("01 83 02"));
    assert!(error.to_string().contains("非法数据地址"), "{error}");
    assert_eq!(named(error), (2, "Illegal data address".to_owned()));
    // Binary error reply 0002h: the drive's own table.
    let error = run(&own::BINARY, vec![0x2F, 0x01, 0x4E, 0x00, 0x02, 0x80]);
    assert_eq!(named(error), (2, "Communication number error".to_owned()));
}

// Fault 6: Modbus found no reply after noise or an echo.

#[test]
fn a_modbus_reply_is_found_after_noise_and_after_an_echo() {
    let reply = hex("01 03 04 00 00 EA 60 B5 7B");
    let noise_then_reply = [hex("00 FF 01 7F 05 01"), reply.clone()].concat();
    let echo_then_reply = [with_crc("01 03 0B D5 00 02"), reply.clone()].concat();
    for stream in [noise_then_reply, echo_then_reply] {
        let (ours, theirs) = memory_pair();
        let _drive = answer(theirs, &protocols::MODBUS, vec![stream.clone()]);
        let mut modbus = master(Watched::new(ours), &protocols::MODBUS);
        let read = modbus.read::<registers::MaximumReference>();
        assert_eq!(
            read.map(|r| r.into_value()).map_err(|e| e.to_string()),
            Ok(60.0),
            "{}",
            vfd_runtime::error::hex(&stream)
        );
        // Counted, not timed: no read of the line ran into its deadline.
        assert_eq!(
            modbus.transport().empty_receives_after_send(),
            0,
            "found without waiting for the timeout"
        );
    }
}

// Stale input: a late reply to an earlier request must not answer the next one.

/// A transport that cannot clear its input buffer (the trait's default).
struct NoClear(MemoryTransport);

impl Transport for NoClear {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.0.send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        self.0.receive(buf, deadline)
    }
}

#[test]
fn stale_input_is_dropped_before_a_request() {
    let (ours, mut theirs) = memory_pair();
    // A late reply to an earlier read of the same parameter: 50 000 instead of 60 000.
    theirs
        .send(&with_crc("01 03 04 00 00 C3 50"))
        .expect("the pipe is open");
    let _drive = answer(
        theirs,
        &protocols::MODBUS,
        vec![hex("01 03 04 00 00 EA 60 B5 7B")],
    );
    let mut modbus = master(NoClear(ours), &protocols::MODBUS);
    assert_eq!(modbus.read::<registers::MaximumReference>().unwrap(), 60.0);
}

// Retries: reads are repeated after a lost reply, writes never.

#[test]
fn reads_are_retried_and_writes_are_not() {
    let reply = hex("01 03 04 00 00 EA 60 B5 7B");
    let (ours, theirs) = memory_pair();
    let drive = answer(theirs, &protocols::MODBUS, vec![Vec::new(), reply]);
    let mut modbus = master(ours, &protocols::MODBUS).with_retries(2);
    let started = Instant::now();
    assert_eq!(modbus.read::<registers::MaximumReference>().unwrap(), 60.0);
    // A bound on a hang, not a duration: the retry follows the first deadline at once.
    assert!(started.elapsed() < modbus.reply_timeout(8) * 3 + HANG);
    assert_eq!(drive.join().unwrap().len(), 2, "the read went out twice");

    let (ours, theirs) = memory_pair();
    let mut modbus = master(ours, &protocols::MODBUS)
        .with_retries(2)
        .with_local_echo(Some(false));
    let write = Request::raw(CommandKind::WriteRam, 101, 1);
    let started = Instant::now();
    let error = modbus.transact(&write).unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Timeout { .. }),
        "{error:?}"
    );
    // The coil-65 selection and the write: each sent once, neither repeated.
    let sent = theirs.pending();
    assert_eq!(
        sent, 8,
        "one frame, the coil-65 selection, and nothing after its timeout"
    );
    assert!(started.elapsed() < modbus.reply_timeout(8) * 2 + HANG);
}

// Late replies (found by the fault matrix): a reply the drive sends after the master gave
// up arrives during the next exchange.

/// The virtual drive's reply to `request` over the FC telegram (encoded by our master's
/// encoder, answered by the simulator), to script late and current replies.
fn fc_reply(sim: &vfd_runtime::virtual_drive::Simulator, request: &Request) -> Vec<u8> {
    let protocol = protocols::FC.protocol();
    let mut frame = [0u8; 64];
    let len = protocol
        .encode_request(request, Some(1), &mut frame)
        .expect("the request encodes");
    match sim.lock().respond(protocol, &frame[..len]) {
        vfd_runtime::virtual_drive::Outcome::Reply(bytes) => bytes,
        other => panic!("the virtual drive answers {request:?}: {other:?}"),
    }
}

#[test]
fn a_late_reply_for_another_register_does_not_end_the_next_read() {
    let sim = vfd_runtime::virtual_drive::Simulator::new(&fc51::DRIVE);
    let read_302 = Request::read::<registers::MinimumReference>();
    let read_303 = Request::read::<registers::MaximumReference>();
    sim.lock().set_raw("303", 55_000);
    let late = fc_reply(&sim, &read_302);
    let current_read = fc_reply(&sim, &read_303);
    let (ours, theirs) = memory_pair();
    let _drive = drive_with_bursts(
        theirs,
        &protocols::FC,
        false,
        vec![
            vec![now(late.clone()), now(current_read)],
            // The late reply alone: a mismatch, at the deadline.
            vec![now(late)],
        ],
    );
    let mut fc = master(ours, &protocols::FC);
    assert_eq!(fc.read::<registers::MaximumReference>().unwrap(), 55.0);
    let started = Instant::now();
    let error = fc.read::<registers::MaximumReference>().unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Mismatch {
                field: vfd_runtime::transaction::ReplyField::Register,
                ..
            }
        ),
        "{error:?}"
    );
    let bound = fc.reply_timeout(16) * 2 + HANG;
    assert!(started.elapsed() < bound, "{:?}", started.elapsed());
}

#[test]
fn a_late_reply_to_an_earlier_write_does_not_answer_the_next_one() {
    use vfd_runtime::transaction::ReplyField;
    let sim = vfd_runtime::virtual_drive::Simulator::new(&fc51::DRIVE);
    let earlier = fc_reply(
        &sim,
        &Request::write_ram::<registers::MaximumReference>(50.0).unwrap(),
    );
    let current = fc_reply(
        &sim,
        &Request::write_ram::<registers::MaximumReference>(60.0).unwrap(),
    );
    let (ours, theirs) = memory_pair();
    let _drive = drive_with_bursts(
        theirs,
        &protocols::FC,
        false,
        vec![vec![now(earlier.clone()), now(current)], vec![now(earlier)]],
    );
    let mut fc = master(ours, &protocols::FC);
    assert_eq!(
        fc.write_ram::<registers::MaximumReference>(60.0).unwrap(),
        Some(60.0),
        "the reply to this write, not the 50.0 of the earlier one"
    );
    let started = Instant::now();
    let error = fc
        .write_ram::<registers::MaximumReference>(60.0)
        .unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Mismatch {
                field: ReplyField::Written,
                expected: 60_000,
                found: 50_000,
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("value written"), "{error}");
    let bound = fc.reply_timeout(16) * 2 + HANG;
    assert!(started.elapsed() < bound, "{:?}", started.elapsed());
}

#[test]
fn a_read_reply_of_another_size_is_not_the_reply() {
    // An echoed Modbus read of registers 0300h-03FFh parses as a reply: function 03, byte
    // count 03 (the address's high byte), three data bytes and the request's own CRC. A
    // line stated not to echo must still not take it for the reply: a read of one
    // register is answered with two data bytes.
    let read_101 = Request::raw(CommandKind::Read, 101, 0);
    let (ours, theirs) = memory_pair();
    let drive = drive_with_bursts(
        theirs,
        &protocols::MODBUS,
        true,
        vec![vec![(Duration::from_millis(5), with_crc("01 03 02 00 07"))]],
    );
    let mut modbus = master(ours, &protocols::MODBUS).with_local_echo(Some(false));
    let answer = modbus.transact(&read_101).unwrap();
    assert_eq!(answer.data, Some(7), "not 0xF10001, the echo read as data");
    assert_eq!(drive.join().unwrap()[0], with_crc("01 03 03 F1 00 01"));
}
