//! The virtual drive as DV1's manual describes it, driven through the typed generated API
//! over Modbus RTU, Modbus ASCII and Eaton's framing: the registers' own Eaton command
//! codes, function 08's echo, writes of several registers, the run, the status and fault
//! registers, commands taken in communication mode only, and exception 02.

use std::time::Duration;
use vfd_drives::{dv1, vf_as1};
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, DriveProtocol, Request, TransactionErrorKind};
use vfd_tests::outcomes::refused;

// Every DV1 protocol: the 10xxh registers carry their Eaton command codes
// (`wire_numbers`: HED writes 1002h, H6F reads 1003h, ...).
const DV1_PROTOCOLS: [&DriveProtocol<dv1::Drive>; 3] = [
    &dv1::protocols::MODBUS,
    &dv1::protocols::MODBUS_ASCII,
    &dv1::protocols::EATON,
];

mod dv1_drive {
    use super::*;
    use dv1::bits::RunCommand as Word;
    use dv1::registers::*;

    #[test]
    fn eaton_requests_carry_the_registers_own_command_codes() {
        let protocol = dv1::protocols::EATON.protocol();
        let mut out = [0u8; 32];
        // 1002h is written as HED: 30h+30h+45h+44h+30h+31h+37h+37h+30h = 1E8h.
        let write = FrequencyCommandRam::write_ram(Hertz(60.0)).unwrap();
        let len = protocol.encode_request(&write, Some(0), &mut out).unwrap();
        assert_eq!(&out[..len], b"\x0500ED01770E8\r");
        // 1003h is read as H6F: 30h+30h+36h+46h+30h = 10Ch.
        let len = protocol
            .encode_request(&OutputFrequency::read(), Some(0), &mut out)
            .unwrap();
        assert_eq!(&out[..len], b"\x05006F00C\r");
        // The monitor block 1014h-1020h is Modbus only: refused before anything is sent.
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(&dv1::protocols::EATON);
        let error = master.read::<DcBusVoltage>().unwrap_err();
        assert!(
            matches!(
                error.kind,
                TransactionErrorKind::Encode(vfd_runtime::EncodeError::NotInProtocol {
                    register: 0x1019,
                    writing: false,
                    ..
                })
            ),
            "{error}"
        );
        assert_eq!(sim.lock().requests(), 0, "nothing was sent");
    }

    #[test]
    fn function_08_echoes_the_query_in_both_framings() {
        // Diagnostics, sub-function 0000h: the reply repeats the request (l. 351-356).
        for protocol in [&dv1::protocols::MODBUS, &dv1::protocols::MODBUS_ASCII] {
            let sim = Simulator::new(&dv1::DRIVE);
            let mut master = sim.master(protocol);
            assert_eq!(master.echo(0x1234).unwrap(), 0x1234);
            assert_eq!(master.echo(0xFFFF).unwrap(), 0xFFFF);
        }
        // The VF-AS1 answers 03 and 06 only: no 08 is sent.
        let sim = Simulator::new(&vf_as1::DRIVE);
        let mut master = sim.master(&vf_as1::protocols::MODBUS);
        let error = master.echo(0x1234).unwrap_err();
        assert!(
            matches!(error.kind, TransactionErrorKind::Encode(_)),
            "{error}"
        );
        assert_eq!(sim.lock().requests(), 0, "nothing was sent");
    }

    #[test]
    fn a_write_of_several_registers_puts_the_first_word_in_the_first_register() {
        // Function 10h, 07-03 = 0 and 07-04 = 1, then a read of both: Modbus sends the
        // first register's word first (a write once stored the whole data in 07-03).
        let sim = Simulator::new(&dv1::DRIVE);
        let mut drive = sim.lock();
        drive.set_address(1);
        let protocol = dv1::protocols::MODBUS.protocol();
        let with_crc = |mut frame: Vec<u8>| {
            let crc =
                vfd_runtime::checksum::compute(vfd_runtime::ChecksumAlgorithm::Crc16Modbus, &frame);
            frame.extend([crc as u8, (crc >> 8) as u8]);
            frame
        };
        let write = with_crc(vec![
            0x01, 0x10, 0x00, 0x30, 0x00, 0x02, 0x04, 0x00, 0x00, 0x00, 0x01,
        ]);
        assert!(matches!(
            drive.respond(protocol, &write),
            vfd_runtime::virtual_drive::Outcome::Reply(_)
        ));
        let read = with_crc(vec![0x01, 0x03, 0x00, 0x30, 0x00, 0x02]);
        assert_eq!(
            drive.respond(protocol, &read),
            vfd_runtime::virtual_drive::Outcome::Reply(with_crc(vec![
                0x01, 0x03, 0x04, 0x00, 0x00, 0x00, 0x01
            ]))
        );
    }

    #[test]
    fn runs_to_60_hz_stops_coasts_and_records_a_fault() {
        for protocol in DV1_PROTOCOLS {
            let sim = Simulator::new(&dv1::DRIVE);
            let mut master = sim.master(protocol);
            master
                .write_ram::<FrequencyCommandRam>(Hertz(60.0))
                .unwrap();
            // 例一: H0002, forward run. The model ramps 60 Hz in 5 s.
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            sim.advance(Duration::from_millis(2500));
            assert_eq!(
                master.read::<OutputFrequency>().unwrap(),
                Hertz(30.0),
                "{}",
                protocol.id
            );
            // 1001h read back is the inverter status, not the run command written.
            let status = master.read::<InverterStatus>().unwrap();
            assert!(status.running() && status.forward(), "{}", protocol.id);
            assert!(sim.lock().is_running());
            sim.advance(Duration::from_millis(2500));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(60.0));
            assert_eq!(master.read::<FrequencyCommandRam>().unwrap(), Hertz(60.0));
            // 例二: H0000, stop.
            master.write_ram::<RunCommand>(Word::new()).unwrap();
            sim.advance(Duration::from_secs(5));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            assert!(!sim.lock().is_running());
            // MRS (bit 7) stops the output at once.
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            sim.advance(Duration::from_secs(1));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(12.0));
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true).with_output_stop(true))
                .unwrap();
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            // A fault: its code in the low byte of 1007h (latest fault).
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            sim.advance(Duration::from_secs(1));
            sim.inject_trip(0x21);
            assert_eq!(master.read::<FaultCodes12>().unwrap().latest(), 0x21);
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            assert!(!sim.lock().is_running());
        }
    }

    #[test]
    fn the_status_at_1001h_shows_running_direction_frequency_reached_and_alarm() {
        use dv1::bits::InverterStatus as Status;
        for protocol in DV1_PROTOCOLS {
            let sim = Simulator::new(&dv1::DRIVE);
            let mut master = sim.master(protocol);
            // Factory state: stopped, no bit set.
            assert_eq!(master.read::<InverterStatus>().unwrap(), Status::new());
            master
                .write_ram::<FrequencyCommandRam>(Hertz(30.0))
                .unwrap();
            // STF (bit 1): running forward; at 30 Hz after 2.5 s, frequency reached.
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            let status = master.read::<InverterStatus>().unwrap();
            assert_eq!(
                status,
                Status::new().with_running(true).with_forward(true),
                "{}",
                protocol.id
            );
            sim.advance(Duration::from_millis(2500));
            let status = master.read::<InverterStatus>().unwrap();
            assert!(status.frequency_reached() && !status.reverse());
            // STR (bit 2) alone: through zero to -30 Hz, in reverse.
            master
                .write_ram::<RunCommand>(Word::new().with_reverse(true))
                .unwrap();
            sim.advance(Duration::from_secs(5));
            assert!((sim.lock().output() + 30.0).abs() < 1e-9);
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(30.0));
            let status = master.read::<InverterStatus>().unwrap();
            assert_eq!(
                status,
                Status::new()
                    .with_running(true)
                    .with_reverse(true)
                    .with_frequency_reached(true)
            );
            // STF and STR together: the model stops (the manual does not say).
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true).with_reverse(true))
                .unwrap();
            sim.advance(Duration::from_secs(5));
            assert_eq!(master.read::<InverterStatus>().unwrap(), Status::new());
            // A trip: b7 (异常发生), nothing running.
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            sim.advance(Duration::from_secs(1));
            sim.inject_trip(0x21);
            assert_eq!(
                master.read::<InverterStatus>().unwrap(),
                Status::new().with_alarm(true)
            );
            // The reset (1101h = 9696h, never answered) clears it; the fault record stays.
            assert_eq!(
                master
                    .write_ram::<InverterReset>(dv1::codes::InverterResetCode::Reset)
                    .unwrap(),
                None,
                "{}",
                protocol.id
            );
            assert_eq!(sim.lock().trip(), None, "{}", protocol.id);
            assert_eq!(master.read::<InverterStatus>().unwrap(), Status::new());
            assert_eq!(master.read::<FaultCodes12>().unwrap().latest(), 0x21);
            // After the reset the run command acts again.
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            assert!(master.read::<InverterStatus>().unwrap().running());
        }
    }

    #[test]
    fn four_fault_codes_newest_first_in_the_bytes_of_1007h_and_1008h() {
        for protocol in DV1_PROTOCOLS {
            let sim = Simulator::new(&dv1::DRIVE);
            let mut master = sim.master(protocol);
            for code in [0x21, 0x22, 0x23, 0x24, 0x25] {
                sim.inject_trip(code);
                master
                    .write_ram::<InverterReset>(dv1::codes::InverterResetCode::Reset)
                    .unwrap();
            }
            // 异常内容: 1007h low byte the latest, high byte the one before; 1008h the
            // third and fourth. The oldest (21h) has gone.
            let newer = master.read::<FaultCodes12>().unwrap();
            let older = master.read::<FaultCodes34>().unwrap();
            assert_eq!(
                [
                    newer.latest(),
                    newer.second(),
                    older.third(),
                    older.fourth()
                ],
                [0x25, 0x24, 0x23, 0x22],
                "{}",
                protocol.id
            );
            assert_eq!(sim.lock().raw("fault_codes_1_2"), Some(0x2425));
        }
        // 1102h = A5A5h (as 00-02 = 1 / P.996 = 1) clears the error codes only; over Eaton
        // it is HFC, which 1102h-1106h share (the data picks the register).
        for protocol in DV1_PROTOCOLS {
            let sim = Simulator::new(&dv1::DRIVE);
            let mut master = sim.master(protocol);
            sim.inject_trip(0x21);
            sim.inject_trip(0x22);
            master
                .write_ram::<FrequencyCommandRam>(Hertz(12.5))
                .unwrap();
            master
                .write_ram::<ParameterClear1102>(dv1::codes::ParameterClear1102::ClearErrorCodes)
                .unwrap();
            assert_eq!(master.read::<FaultCodes12>().unwrap().latest(), 0);
            assert_eq!(master.read::<FaultCodes12>().unwrap().second(), 0);
            assert_eq!(master.read::<FrequencyCommandRam>().unwrap(), Hertz(12.5));
        }
    }

    #[test]
    fn the_eaton_parameter_clear_hfc_is_one_code_whose_data_picks_the_register() {
        use vfd_runtime::virtual_drive::Outcome;
        let protocol = dv1::protocols::EATON.protocol();
        let mut out = [0u8; 32];
        // 1102h = A5A5h as HFC: 30h+30h+46h+43h+30h+41h+35h+41h+35h = 205h.
        let clear =
            ParameterClear1102::write_ram(dv1::codes::ParameterClear1102::ClearErrorCodes).unwrap();
        let len = protocol.encode_request(&clear, Some(0), &mut out).unwrap();
        assert_eq!(&out[..len], b"\x0500FC0A5A505\r".as_slice());
        // 1104h = 5A5Ah as HFC too (same sum).
        let like_p999 =
            ParameterClear1104::write_ram(dv1::codes::ParameterClear1104::LikeP9991).unwrap();
        let len = protocol
            .encode_request(&like_p999, Some(0), &mut out)
            .unwrap();
        assert_eq!(&out[..len], b"\x0500FC05A5A05\r".as_slice());
        // Decoded, the data names the register: A5A5h is 1102h, 9696h is 1106h
        // (communication 999 1, sum 1F7h), not the reset (9696h at HFD, 1101h).
        for (frame, register) in [
            (&b"\x0500FC0A5A505\r"[..], 0x1102),
            (&b"\x0500FC05A5A05\r"[..], 0x1104),
            (&b"\x0500FC09696F7\r"[..], 0x1106),
        ] {
            let decoded = protocol.decode_request_exact(frame).unwrap();
            assert_eq!(decoded.register, Some(register));
        }
        let sim = Simulator::new(&dv1::DRIVE);
        sim.inject_trip(0x21);
        let mut drive = sim.lock();
        drive.set_address(0);
        assert_eq!(
            drive.respond(protocol, b"\x0500FC09696F7\r"),
            Outcome::Reply(b"\x0600\r".to_vec())
        );
        assert_eq!(
            drive.trip(),
            Some(0x21),
            "HFC 9696h clears parameters, it is no reset"
        );
        assert_eq!(drive.raw("fault_codes_1_2"), Some(0x21));
        assert_eq!(
            drive.respond(protocol, b"\x0500FC0A5A505\r"),
            Outcome::Reply(b"\x0600\r".to_vec())
        );
        assert_eq!(drive.raw("fault_codes_1_2"), Some(0));
    }

    #[test]
    fn commands_are_taken_in_communication_mode_only() {
        use dv1::codes::OperationMode as Mode;
        // H0A (模式异常) over Eaton, 03 (refused in the current mode) over Modbus.
        for (protocol, code) in DV1_PROTOCOLS.into_iter().zip([3, 3, 0x0A]) {
            let sim = Simulator::new(&dv1::DRIVE);
            let mut master = sim.master(protocol);
            master.write_ram::<OperationMode>(Mode::External).unwrap();
            let run = master.write_ram::<RunCommand>(Word::new().with_forward(true));
            assert_eq!(refused(run), code, "{}", protocol.id);
            let frequency = master.write_ram::<FrequencyCommandRam>(Hertz(30.0));
            assert_eq!(refused(frequency), code, "{}", protocol.id);
            assert!(!sim.lock().is_running());
            // 例一: back to communication mode (0), and the drive takes both.
            master
                .write_ram::<OperationMode>(Mode::Communication)
                .unwrap();
            master
                .write_ram::<FrequencyCommandRam>(Hertz(30.0))
                .unwrap();
            master
                .write_ram::<RunCommand>(Word::new().with_forward(true))
                .unwrap();
            assert!(master.read::<InverterStatus>().unwrap().running());
        }
    }

    #[test]
    fn status_and_run_command_frames_over_modbus_rtu_and_eaton() {
        use vfd_runtime::virtual_drive::Outcome;
        let sim = Simulator::new(&dv1::DRIVE);
        let mut drive = sim.lock();
        drive.set_address(1);
        let rtu = dv1::protocols::MODBUS.protocol();
        let with_crc = |mut frame: Vec<u8>| {
            let crc =
                vfd_runtime::checksum::compute(vfd_runtime::ChecksumAlgorithm::Crc16Modbus, &frame);
            frame.extend([crc as u8, (crc >> 8) as u8]);
            frame
        };
        let read_status = with_crc(vec![0x01, 0x03, 0x10, 0x01, 0x00, 0x01]);
        let status_reply = |word: u16| {
            Outcome::Reply(with_crc(vec![
                0x01,
                0x03,
                0x02,
                (word >> 8) as u8,
                word as u8,
            ]))
        };
        // Write 1001h = 0002h (STF), echoed; read 1001h: b0 running + b1 forward.
        let forward = with_crc(vec![0x01, 0x06, 0x10, 0x01, 0x00, 0x02]);
        assert_eq!(
            drive.respond(rtu, &forward),
            Outcome::Reply(forward.clone())
        );
        assert_eq!(drive.respond(rtu, &read_status), status_reply(0x0003));
        // 0004h (STR): b0 running + b2 reverse.
        let reverse = with_crc(vec![0x01, 0x06, 0x10, 0x01, 0x00, 0x04]);
        assert_eq!(
            drive.respond(rtu, &reverse),
            Outcome::Reply(reverse.clone())
        );
        assert_eq!(drive.respond(rtu, &read_status), status_reply(0x0005));
        // Back to STF, then a trip: b7 alone; the reset 01 06 11 01 96 96 32 F8 gets no
        // reply and clears it.
        assert_eq!(
            drive.respond(rtu, &forward),
            Outcome::Reply(forward.clone())
        );
        drive.inject_trip(0x21);
        assert_eq!(drive.respond(rtu, &read_status), status_reply(0x0080));
        assert!(matches!(
            drive.respond(rtu, &[0x01, 0x06, 0x11, 0x01, 0x96, 0x96, 0x32, 0xF8]),
            Outcome::Silent(_)
        ));
        assert_eq!(drive.trip(), None);
        assert_eq!(drive.respond(rtu, &read_status), status_reply(0x0000));

        // The Eaton protocol, station 0: 例一's HFA H0002 (answered C), then H7A, read code
        // 7Ah: sum 30h+30h+37h+41h+30h = 108h. Format E: station, data 0003, unit digit 0,
        // ETX, sum 30h x 6 + 33h = 153h.
        drive.set_address(0);
        let eaton = dv1::protocols::EATON.protocol();
        drive.respond(rtu, &with_crc(vec![0x01, 0x06, 0x10, 0x01, 0x00, 0x00]));
        drive.advance(Duration::from_secs(10));
        assert_eq!(
            drive.respond(eaton, b"\x0500FA00002D9\r"),
            Outcome::Reply(b"\x0600\r".to_vec())
        );
        assert_eq!(
            drive.respond(eaton, b"\x05007A008\r"),
            Outcome::Reply(b"\x020000030\x0353\r".to_vec())
        );
        // STR: 30h+30h+46h+41h+30h+30h+30h+30h+34h = 1DBh; status 0005h, sum 155h.
        assert_eq!(
            drive.respond(eaton, b"\x0500FA00004DB\r"),
            Outcome::Reply(b"\x0600\r".to_vec())
        );
        assert_eq!(
            drive.respond(eaton, b"\x05007A008\r"),
            Outcome::Reply(b"\x020000050\x0355\r".to_vec())
        );
        // The reset HFD H9696 (sum 1F8h, dv1.NEEDS.md item 6) is never answered.
        assert_eq!(
            drive.respond(eaton, b"\x0500FA00002D9\r"),
            Outcome::Reply(b"\x0600\r".to_vec())
        );
        drive.inject_trip(0x21);
        assert_eq!(
            drive.respond(eaton, b"\x05007A008\r"),
            Outcome::Reply(b"\x020000800\x0358\r".to_vec())
        );
        assert!(matches!(
            drive.respond(eaton, b"\x0500FD09696F8\r"),
            Outcome::Silent(_)
        ));
        assert_eq!(drive.trip(), None);
    }

    #[test]
    fn modbus_refuses_unknown_and_read_only_addresses_with_exception_02() {
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(&dv1::protocols::MODBUS);
        let write_monitor = Request::raw(CommandKind::WriteRam, 0x1003, 0x1770);
        assert_eq!(refused(master.transact(&write_monitor)), 2);
        let nowhere = Request::raw(CommandKind::Read, 0x7777, 0);
        assert_eq!(refused(master.transact(&nowhere)), 2);
    }
}
