//! Functions a drive lacks, without a Python peer: the virtual drive answers a well-formed
//! request with a function its protocol entry does not list with the error code its
//! `unsupported_function` gives (DV1 l. 487 and VF-AS1 5.3: exception 01, function + 80h),
//! in Modbus RTU once the line falls silent and in Modbus ASCII at the CR LF; another
//! station's such request, a broken one, and any such request to a drive whose manual
//! does not say (FC 51) get no answer. (tests/tests/modbus_peer_master.rs shows pymodbus
//! and minimalmodbus getting IllegalFunction over a pseudo-terminal.)

use std::time::Duration;
use vfd_drives::{dv1, fc51, vf_as1};
use vfd_runtime::checksum::crc16_modbus;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::Protocol;

/// `bytes` with their CRC-16, low byte first.
fn rtu(bytes: &[u8]) -> Vec<u8> {
    let crc = crc16_modbus(bytes);
    [bytes, &crc.to_le_bytes()].concat()
}

/// `bytes` as a Modbus ASCII frame with its LRC.
fn ascii(bytes: &[u8]) -> Vec<u8> {
    let lrc = bytes
        .iter()
        .fold(0u8, |sum, b| sum.wrapping_add(*b))
        .wrapping_neg();
    let digits: String = bytes
        .iter()
        .chain([&lrc])
        .map(|b| format!("{b:02X}"))
        .collect();
    format!(":{digits}\r\n").into_bytes()
}

/// What a drive at station 1, up and running, sends back for `frame`: first while more
/// bytes may follow, then once the line is silent.
fn answers(sim: &Simulator, protocol: &Protocol, frame: &[u8]) -> (Vec<Vec<u8>>, Vec<Vec<u8>>) {
    sim.lock().set_address(1);
    sim.advance(Duration::from_secs(10));
    let mut input = frame.to_vec();
    let early = sim.lock().receive(protocol, &mut input);
    let settled = sim.lock().receive_before_silence(protocol, &mut input);
    let bytes = |t: Vec<vfd_runtime::virtual_drive::Transmission>| {
        t.into_iter().map(|t| t.bytes).collect::<Vec<_>>()
    };
    (bytes(early), bytes(settled))
}

#[test]
fn the_dv1_answers_functions_02_04_and_2b_with_exception_01_in_modbus_rtu() {
    let protocol = dv1::protocols::MODBUS.protocol();
    for request in [
        vec![0x01, 0x02, 0x00, 0x00, 0x00, 0x08],
        vec![0x01, 0x04, 0x00, 0xC3, 0x00, 0x01],
        vec![0x01, 0x2B, 0x0E, 0x01, 0x00],
        // 01, 05 and 0F are in the shared protocol file, not in the DV1's list.
        vec![0x01, 0x01, 0x00, 0x00, 0x00, 0x10],
    ] {
        let sim = Simulator::new(&dv1::DRIVE);
        let (early, settled) = answers(&sim, protocol, &rtu(&request));
        assert!(
            early.is_empty(),
            "{request:02X?}: only the silence ends an RTU frame"
        );
        assert_eq!(
            settled,
            [rtu(&[0x01, request[1] | 0x80, 0x01])],
            "{request:02X?}: function + 80h, exception 01"
        );
    }
}

#[test]
fn the_dv1_answers_function_04_with_exception_01_in_modbus_ascii_at_the_cr_lf() {
    let protocol = dv1::protocols::MODBUS_ASCII.protocol();
    let sim = Simulator::new(&dv1::DRIVE);
    let (early, _) = answers(
        &sim,
        protocol,
        &ascii(&[0x01, 0x04, 0x00, 0xC3, 0x00, 0x01]),
    );
    assert_eq!(early, [ascii(&[0x01, 0x84, 0x01])]);
}

#[test]
fn the_vf_as1_answers_function_04_with_exception_01() {
    let protocol = vf_as1::protocols::MODBUS.protocol();
    let sim = Simulator::new(&vf_as1::DRIVE);
    let (_, settled) = answers(&sim, protocol, &rtu(&[0x01, 0x04, 0xFD, 0x00, 0x00, 0x01]));
    assert_eq!(settled, [rtu(&[0x01, 0x84, 0x01])]);
}

#[test]
fn other_stations_broken_frames_and_silent_manuals_get_no_answer() {
    let dv1_rtu = dv1::protocols::MODBUS.protocol();
    let cases: [(&str, Simulator, &Protocol, Vec<u8>); 4] = [
        (
            "another station",
            Simulator::new(&dv1::DRIVE),
            dv1_rtu,
            rtu(&[0x02, 0x04, 0x00, 0xC3, 0x00, 0x01]),
        ),
        ("a wrong CRC", Simulator::new(&dv1::DRIVE), dv1_rtu, {
            let mut frame = rtu(&[0x01, 0x04, 0x00, 0xC3, 0x00, 0x01]);
            frame[7] ^= 0xFF;
            frame
        }),
        (
            "a broadcast",
            Simulator::new(&dv1::DRIVE),
            dv1_rtu,
            rtu(&[0x00, 0x04, 0x00, 0xC3, 0x00, 0x01]),
        ),
        (
            "the FC 51, whose manual does not say",
            Simulator::new(&fc51::DRIVE),
            fc51::protocols::MODBUS.protocol(),
            rtu(&[0x01, 0x04, 0x0B, 0xD5, 0x00, 0x02]),
        ),
    ];
    for (what, sim, protocol, frame) in cases {
        let (early, settled) = answers(&sim, protocol, &frame);
        assert!(
            early.is_empty() && settled.is_empty(),
            "{what}: {early:02X?} {settled:02X?}"
        );
    }
}

#[test]
fn a_request_the_drive_has_is_answered_after_a_lacking_one() {
    let protocol = dv1::protocols::MODBUS.protocol();
    let sim = Simulator::new(&dv1::DRIVE);
    let (_, settled) = answers(&sim, protocol, &rtu(&[0x01, 0x02, 0x00, 0x00, 0x00, 0x08]));
    assert_eq!(settled.len(), 1);
    // 03 of 02-15 (00C3h): answered at once, as before.
    let (early, _) = answers(&sim, protocol, &rtu(&[0x01, 0x03, 0x00, 0xC3, 0x00, 0x01]));
    assert_eq!(early.len(), 1, "{early:02X?}");
    assert_eq!(&early[0][..3], &[0x01, 0x03, 0x02]);
}

#[test]
fn the_reply_to_a_lacking_function_decodes_as_the_drives_error_reply() {
    use vfd_runtime::protocol::Reply;
    let cases: [(&str, &vfd_runtime::DriveInfo, &Protocol, Vec<u8>); 4] = [
        (
            "dv1 modbus",
            &dv1::DRIVE,
            dv1::protocols::MODBUS.protocol(),
            rtu(&[0x01, 0x01, 0x00, 0x00, 0x00, 0x10]),
        ),
        (
            "dv1 modbus 2Bh",
            &dv1::DRIVE,
            dv1::protocols::MODBUS.protocol(),
            rtu(&[0x01, 0x2B, 0x0E, 0x01, 0x00]),
        ),
        (
            "dv1 modbus_ascii",
            &dv1::DRIVE,
            dv1::protocols::MODBUS_ASCII.protocol(),
            ascii(&[0x01, 0x04, 0x00, 0xC3, 0x00, 0x01]),
        ),
        (
            "vf-as1 modbus",
            &vf_as1::DRIVE,
            vf_as1::protocols::MODBUS.protocol(),
            rtu(&[0x01, 0x01, 0x00, 0x00, 0x00, 0x10]),
        ),
    ];
    for (what, drive, protocol, request) in cases {
        let sim = Simulator::new(drive);
        let (early, settled) = answers(&sim, protocol, &request);
        let reply = early.into_iter().chain(settled).next().expect(what);
        let found = protocol.decode_reply(None, &reply);
        let Ok(vfd_runtime::protocol::Found::Frame {
            frame: Reply::Error {
                code, error, info, ..
            },
            ..
        }) = found
        else {
            panic!("{what}: {reply:02X?} does not decode as an error reply: {found:?}");
        };
        let function = if protocol.id == "modbus_ascii" {
            0x04
        } else {
            request[1]
        };
        assert_eq!((code, error), (u32::from(function) | 0x80, 0x01), "{what}");
        assert!(info.is_some(), "{what}: exception 01 is named");
    }
    // Exception 02 under a function the drive lacks is no reply of the drive's.
    let protocol = dv1::protocols::MODBUS.protocol();
    assert!(protocol
        .decode_reply(None, &rtu(&[0x01, 0x81, 0x02]))
        .is_err());
}
