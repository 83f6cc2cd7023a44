//! Protocol variants (`variants:` in a protocol file, `protocols[].variant` in a drive
//! file): the DV1's Eaton protocol ends every frame in CR (07-06 = 1, the factory setting)
//! or in CR LF (07-06 = 2). The CR LF frames are derived, not printed: the manual's frames
//! with 0Ah after the 0Dh (the sum check never covers the terminator, *3) and *7)).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use vfd_drives::dv1;
use vfd_runtime::prelude::*;
use vfd_runtime::protocol::Found;
use vfd_runtime::transport::memory_pair;
use vfd_runtime::virtual_drive::{serve, Outcome, Simulator};
use vfd_runtime::Reply;

/// 例一 step 1: HFA (run command 1001h) = H0002, forward; the sum 1D9h gives "D9".
const RUN_FORWARD_CR: &[u8] = b"\x0500FA00002D9\r";
const RUN_FORWARD_CR_LF: &[u8] = b"\x0500FA00002D9\r\n";

fn cr_lf() -> &'static Protocol {
    dv1::protocols::EATON
        .protocol()
        .variant("cr_lf")
        .expect("eaton-ascii declares the variant cr_lf")
}

fn run_forward() -> vfd_runtime::DriveRequest<dv1::Drive> {
    dv1::registers::RunCommand::write_ram(dv1::bits::RunCommand::new().with_forward(true)).unwrap()
}

/// A drive whose 07-06 is `value`, in effect (set on the panel, then a reset).
fn drive_with_terminator(value: u32) -> Simulator {
    let sim = Simulator::new(&dv1::DRIVE);
    let mut drive = sim.lock();
    drive.set_address(0);
    assert!(drive.set_raw("07-06", value));
    drive.reset();
    drop(drive);
    sim
}

#[test]
fn the_variants_are_the_protocol_files_and_07_06_selects_them() {
    let eaton = dv1::protocols::EATON.protocol();
    assert_eq!(eaton.variant_id(), Some("cr"));
    let variants = eaton.variants.as_ref().unwrap();
    let ids: Vec<&str> = variants.choices.iter().map(|v| v.id.as_ref()).collect();
    assert_eq!(ids, ["cr", "cr_lf"]);
    // 07-06 is P.51, register 0033h: 1 selects CR, 2 CR LF; H03 answers the other one.
    let selector = variants.selected_by.as_ref().unwrap();
    assert_eq!(selector.register, 0x0033);
    assert_eq!(variants.selected_by_value(1), Some(0));
    assert_eq!(variants.selected_by_value(2), Some(1));
    assert_eq!(variants.mismatch_error, Some(0x03));
    // Built once: asked twice, the same protocol; back to `cr`, the generated static.
    assert!(std::ptr::eq(cr_lf(), cr_lf()));
    assert_eq!(cr_lf().variant_id(), Some("cr_lf"));
    assert!(std::ptr::eq(cr_lf().variant("cr").unwrap(), eaton));
    assert!(eaton.variant("lf").is_none());
    let error = eaton.variant_or_error("lf").unwrap_err();
    assert_eq!(
        error.to_string(),
        "protocol eaton has no variant `lf`; its variants: cr, cr_lf"
    );
    // A protocol without variants has none to give.
    assert!(dv1::protocols::MODBUS.protocol().variant("cr_lf").is_none());
    assert_eq!(dv1::protocols::MODBUS.protocol().variant_id(), None);
}

/// Each protocol owns the variants built from it (`Protocol::variant_cache`), not a
/// process-wide table: the generated static keeps its `cr_lf` for ever, a copy builds its
/// own, and neither shows in `Debug` or tells two protocols apart.
#[test]
fn a_protocol_owns_the_variants_built_from_it() {
    let eaton = dv1::protocols::EATON.protocol();
    let built = cr_lf();
    let cache = format!("{:?}", eaton.variant_cache);
    assert!(cache.contains("is_variant: false"), "{cache}");
    assert!(cache.contains("built: 1"), "{cache}");
    let cache = format!("{:?}", built.variant_cache);
    assert!(cache.contains("is_variant: true"), "{cache}");
    assert!(cache.contains("built: 0"), "{cache}");
    // Every variant, from either one: the static and the one it built.
    let all = |p: &'static Protocol| -> Vec<*const Protocol> {
        p.all_variants()
            .into_iter()
            .map(std::ptr::from_ref)
            .collect()
    };
    let expected = vec![std::ptr::from_ref(eaton), std::ptr::from_ref(built)];
    assert_eq!(all(eaton), expected);
    assert_eq!(all(built), expected);
    // A copy starts with no variants and builds its own, equal to the static's.
    let copy: &'static Protocol = Box::leak(Box::new(eaton.clone()));
    assert!(format!("{:?}", copy.variant_cache).contains("built: 0"));
    let its_own = copy.variant("cr_lf").unwrap();
    assert!(!std::ptr::eq(its_own, built));
    assert_eq!(its_own, built);
    assert!(std::ptr::eq(its_own.variant("cr").unwrap(), copy));
    // Not part of the value: `Debug` shows no cache, and is the same with or without one.
    let shown = format!("{eaton:?}");
    assert!(!shown.contains("VariantCache"), "{shown}");
    assert_eq!(shown, format!("{:?}", eaton.clone()));
    assert_eq!(format!("{its_own:?}"), format!("{built:?}"));
}

#[test]
fn example_one_in_cr_lf_encodes_and_decodes_exactly() {
    let mut out = [0u8; 32];
    // The request: 例一's bytes with LF after the CR.
    let len = cr_lf()
        .encode_request(&run_forward(), Some(0), &mut out)
        .unwrap();
    assert_eq!(&out[..len], RUN_FORWARD_CR_LF);
    // The factory variant still sends the printed frame.
    let len = dv1::protocols::EATON
        .encode_request(&run_forward(), Some(0), &mut out)
        .unwrap();
    assert_eq!(&out[..len], RUN_FORWARD_CR);
    let request = cr_lf().decode_request_exact(RUN_FORWARD_CR_LF).unwrap();
    assert_eq!((request.address, request.register), (Some(0), Some(0x1001)));
    assert_eq!(request.data, 0x0002);
    // The reply C: ACK, station "00", CR LF.
    let reply = cr_lf()
        .decode_reply_exact(Some(request.command), b"\x0600\r\n")
        .unwrap();
    assert!(
        matches!(
            reply,
            Reply::Data {
                address: Some(0),
                ..
            }
        ),
        "{reply:?}"
    );
    assert_eq!(
        cr_lf().check_answer(RUN_FORWARD_CR_LF, b"\x0600\r\n"),
        Ok(())
    );
    // Each variant reads its own frames only: no frame plus a stray byte, no frame cut
    // short at the CR.
    let eaton = dv1::protocols::EATON.protocol();
    let error = eaton.decode_request_exact(RUN_FORWARD_CR_LF).unwrap_err();
    assert_eq!(error.kind(), DecodeErrorKind::TrailingBytes, "{error}");
    assert!(matches!(
        cr_lf().decode_request(RUN_FORWARD_CR),
        Ok(Found::Incomplete)
    ));
    let error = cr_lf()
        .decode_request(b"\x0500FA00002D9\r\x05")
        .unwrap_err();
    assert_eq!(error.kind(), DecodeErrorKind::UnexpectedByte, "{error}");
    assert!(cr_lf()
        .decode_reply_exact(Some(request.command), b"\x0600\r")
        .is_err());
}

#[test]
fn the_drive_answers_a_frame_with_the_other_terminator_with_h03() {
    // 07-06 = 2: a CR-only request is a protocol error; the NAK D is
    // NAK, "00", "3", CR LF.
    let sim = drive_with_terminator(2);
    let outcome = sim
        .lock()
        .respond(dv1::protocols::EATON.protocol(), RUN_FORWARD_CR);
    assert_eq!(outcome, Outcome::Reply(b"\x15003\r\n".to_vec()));
    assert!(
        !sim.lock().is_running(),
        "the run command was not carried out"
    );
    // In its own terminator the request is carried out and acknowledged in CR LF.
    let outcome = sim
        .lock()
        .respond(dv1::protocols::EATON.protocol(), RUN_FORWARD_CR_LF);
    assert_eq!(outcome, Outcome::Reply(b"\x0600\r\n".to_vec()));
    assert!(sim.lock().is_running(), "the run command was carried out");
    // 07-06 = 1 (the factory setting): CR LF is the error, answered in CR.
    let sim = drive_with_terminator(1);
    let outcome = sim
        .lock()
        .respond(dv1::protocols::EATON.protocol(), RUN_FORWARD_CR_LF);
    assert_eq!(outcome, Outcome::Reply(b"\x15003\r".to_vec()));
    // Another station's frame gets no answer, whatever its terminator.
    let outcome = sim
        .lock()
        .respond(dv1::protocols::EATON.protocol(), b"\x0501FA00002DA\r\n");
    assert!(matches!(outcome, Outcome::Silent(_)), "{outcome:?}");
}

#[test]
fn a_drive_reading_a_byte_stream_waits_for_the_byte_after_the_cr() {
    let protocol = dv1::protocols::EATON.protocol();
    // 07-06 = 1: at the CR the frame may still go on with an LF; the LF decides.
    let sim = drive_with_terminator(1);
    let mut drive = sim.lock();
    let mut input = RUN_FORWARD_CR.to_vec();
    assert!(drive.receive(protocol, &mut input).is_empty());
    assert_eq!(input, RUN_FORWARD_CR, "kept until the next byte");
    input.push(b'\n');
    let sent = drive.receive(protocol, &mut input);
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0].bytes, b"\x15003\r");
    assert!(input.is_empty());
    // The next frame's ENQ instead: the CR frame stands and is answered.
    let mut input = [RUN_FORWARD_CR, b"\x05"].concat();
    let sent = drive.receive(protocol, &mut input);
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0].bytes, b"\x0600\r");
    assert_eq!(input, b"\x05");
    // Silence after the CR: the frame stands.
    let mut input = RUN_FORWARD_CR.to_vec();
    let sent = drive.receive_before_silence(protocol, &mut input);
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0].bytes, b"\x0600\r");
    drop(drive);
    // 07-06 = 2: a CR-only frame waits for its LF; silence, or another byte, makes it H03.
    let sim = drive_with_terminator(2);
    let mut drive = sim.lock();
    let mut input = RUN_FORWARD_CR.to_vec();
    assert!(drive.receive(protocol, &mut input).is_empty());
    let sent = drive.receive_before_silence(protocol, &mut input);
    assert_eq!(sent.len(), 1);
    assert_eq!(sent[0].bytes, b"\x15003\r\n");
    let mut input = [RUN_FORWARD_CR, RUN_FORWARD_CR_LF].concat();
    let sent = drive.receive(protocol, &mut input);
    let sent: Vec<&[u8]> = sent.iter().map(|t| t.bytes.as_slice()).collect();
    assert_eq!(sent, [&b"\x15003\r\n"[..], &b"\x0600\r\n"[..]]);
}

#[test]
fn a_master_in_cr_lf_reads_and_writes_a_drive_set_to_cr_lf() {
    use dv1::registers::{FrequencyCommandRam, OutputFrequency};
    let sim = drive_with_terminator(2);
    let mut master = sim
        .master(&dv1::protocols::EATON)
        .with_variant("cr_lf")
        .unwrap();
    assert_eq!(master.variant(), Some("cr_lf"));
    master
        .write_ram::<FrequencyCommandRam>(Hertz(50.0))
        .unwrap();
    assert_eq!(master.read::<FrequencyCommandRam>().unwrap(), Hertz(50.0));
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
    // A master left in CR is told H03 (its CR frame is an error to this drive).
    let mut plain = sim.master(&dv1::protocols::EATON);
    let error = plain.read::<FrequencyCommandRam>().unwrap_err();
    assert!(
        matches!(
            error.kind,
            TransactionErrorKind::Rejected {
                code: 3,
                info: Some(info),
                ..
            } if info.id == "protocol_error"
        ),
        "{error}"
    );
    // An unknown variant is refused, naming the protocol's.
    let error = sim
        .master(&dv1::protocols::EATON)
        .with_variant("crlf")
        .err()
        .unwrap();
    assert!(error.to_string().contains("cr, cr_lf"), "{error}");
}

#[test]
fn the_drive_selects_its_variant_as_the_cli_asks() {
    // `vfd sim --variant cr_lf` sets 07-06 to the value that selects it.
    let sim = Simulator::new(&dv1::DRIVE);
    assert!(sim.lock().select_variant(cr_lf()));
    assert_eq!(sim.lock().raw_in_effect("07-06"), Some(2));
    // Modbus has no variants to select.
    assert!(!sim.lock().select_variant(dv1::protocols::MODBUS.protocol()));
}

#[test]
fn a_served_drive_answers_in_cr_lf_over_a_byte_line() {
    // In wall time: the master's bytes arrive through `serve`, which settles a frame after
    // two character times of silence.
    let sim = drive_with_terminator(2);
    let (master_end, mut drive_end) = memory_pair();
    let stop = Arc::new(AtomicBool::new(false));
    let (server, flag) = (sim.clone(), stop.clone());
    let settings = dv1::SERIAL.default;
    let handle = std::thread::spawn(move || {
        serve(
            &server,
            dv1::protocols::EATON.protocol(),
            &mut drive_end,
            settings,
            &flag,
        )
        .unwrap();
    });
    let mut master = Master::new(
        master_end,
        &dv1::protocols::EATON,
        dv1::SERIAL.default,
        dv1::SERIAL.timing,
    )
    .with_address(Some(0))
    .with_variant("cr_lf")
    .unwrap();
    master
        .write_ram::<dv1::registers::FrequencyCommandRam>(Hertz(45.5))
        .unwrap();
    let read = master.read::<dv1::registers::FrequencyCommandRam>();
    // A CR-only request on the same line: the drive waits for the LF, then answers H03.
    let mut line = master.into_transport();
    line.send(RUN_FORWARD_CR).unwrap();
    let mut got = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(2);
    let mut buf = [0u8; 16];
    while !got.ends_with(b"\r\n") && Instant::now() < deadline {
        let n = line.receive(&mut buf, deadline).unwrap();
        got.extend_from_slice(&buf[..n]);
    }
    stop.store(true, Ordering::Relaxed);
    handle.join().unwrap();
    assert_eq!(read.unwrap(), Hertz(45.5));
    assert_eq!(got, b"\x15003\r\n");
}
