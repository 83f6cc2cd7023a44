//! Commands a protocol file offers as extras and commands that get no reply: the Toshiba
//! binary G read and S / s drive-to-drive command as the VF-AS1 has them (the YD1000, on the
//! same protocol file, has neither), and the DV1's inverter reset (register 1101h), whose
//! write is never answered. Through the typed API, the in-memory transport and the virtual
//! drive. That the master does not wait for a reply is shown by counting its reads of the
//! line, not by timing.

use std::time::{Duration, Instant};
use vfd_drives::{dv1, vf_as1, yd1000};
use vfd_runtime::prelude::*;
use vfd_runtime::protocol::PercentOf;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{memory_pair, Transport};
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, EncodeError, Request, TransactionErrorKind};
use vfd_tests::watched::Watched;

const G: u32 = b'G' as u32;
const S: u32 = b'S' as u32;
const S_TRIPPED: u32 = b's' as u32;

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("hex"))
        .collect()
}

/// A binary frame from its bytes without the sum, with the sum appended.
fn with_sum(text: &str) -> Vec<u8> {
    let mut frame = hex(text);
    frame.push(frame.iter().fold(0u8, |sum, b| sum.wrapping_add(*b)));
    frame
}

/// The bytes that arrive on `transport` within `wait`.
fn received<T: Transport>(transport: &mut T, wait: Duration) -> Vec<u8> {
    let deadline = Instant::now() + wait;
    let mut bytes = Vec::new();
    let mut chunk = [0u8; 64];
    while let Ok(got) = transport.receive(&mut chunk, deadline) {
        if got == 0 {
            break;
        }
        bytes.extend_from_slice(&chunk[..got]);
    }
    bytes
}

fn encode_error<T: std::fmt::Debug>(result: Result<T, TransactionError>) -> EncodeError {
    match result {
        Err(TransactionError {
            kind: TransactionErrorKind::Encode(error),
            ..
        }) => error,
        other => panic!("expected a request that cannot be sent, got {other:?}"),
    }
}

mod percentages {
    use super::*;

    /// 6.1: the master sends fc x 10000 / FH (truncated), the receiver runs at
    /// received x FH / 10000.
    #[test]
    fn the_manuals_worked_numbers_convert_both_ways() {
        let percent = PercentOf {
            register: "FH".into(),
            step: 0.01,
            received_by: Default::default(),
        };
        // Master FH 100 Hz, 50 Hz -> 5000 (50 %).
        assert_eq!(percent.to_raw(50.0, 100.0), Some(5000));
        // Slaves with FH 90 Hz and 80 Hz run at 45 Hz and 40 Hz.
        assert!((percent.from_raw(5000, 90.0) - 45.0).abs() < 1e-9);
        assert!((percent.from_raw(5000, 80.0) - 40.0).abs() < 1e-9);
        // 4.2: FH 80 Hz, 40 Hz -> 50 % = 1388h.
        assert_eq!(percent.to_raw(40.0, 80.0), Some(0x1388));
        // Truncated, as the manual says (error up to 0.01 %): 33.33 / 100 x 10000.
        assert_eq!(percent.to_raw(100.0 / 3.0, 100.0), Some(3333));
        // No word holds it, or no 100 %.
        assert_eq!(percent.to_raw(700.0, 1.0), None);
        assert_eq!(percent.to_raw(50.0, 0.0), None);
        assert_eq!(percent.to_raw(-1.0, 100.0), None);
    }
}

mod g_command {
    use super::*;
    use vf_as1::registers::{OutputCurrentAtTrip, OutputFrequency};

    #[test]
    fn a_read_by_g_encodes_to_the_manuals_frame_and_r_stays_the_default() {
        let protocol = &vf_as1::protocols::BINARY;
        let mut out = [0u8; 16];
        let len = protocol
            .encode_request(&OutputCurrentAtTrip::read().using(G), None, &mut out)
            .unwrap();
        assert_eq!(&out[..len], hex("2F 47 FE 03 00 00 77"));
        let len = protocol
            .encode_request(&OutputCurrentAtTrip::read(), None, &mut out)
            .unwrap();
        assert_eq!(&out[..len], hex("2F 52 FE 03 82"), "R unless G is named");
    }

    #[test]
    fn the_yd1000_has_no_g_and_says_so_before_sending() {
        let sim = Simulator::new(&yd1000::DRIVE);
        let mut master = sim.master(&yd1000::protocols::BINARY);
        let error = encode_error(master.read_using::<yd1000::registers::OutputFrequency>(G));
        assert!(
            matches!(error, EncodeError::NoSuchCommand { code, kind: CommandKind::Read, .. } if code == G),
            "{error}"
        );
        assert_eq!(sim.requests(), 0, "nothing went on the line");
        assert!(yd1000::protocols::BINARY
            .commands
            .iter()
            .all(|c| c.code != G && c.code != S));
    }

    #[test]
    fn the_virtual_drive_answers_g_with_g_and_g_lower_case_when_tripped() {
        let sim = Simulator::new(&vf_as1::DRIVE);
        let mut master = sim.master(&vf_as1::protocols::BINARY);
        let reading = master.read_using::<OutputFrequency>(G).unwrap();
        assert!(!reading.tripped);
        assert_eq!(master.last_reply()[..3], [0x2F, 1, b'G'], "station 1, G");
        // FE03 follows FD03 between trips and holds its value while tripped: set it then.
        sim.inject_trip(0x18);
        assert!(sim.lock().set_raw("FE03", 0x077B));
        let reading = master.read_using::<OutputCurrentAtTrip>(G).unwrap();
        assert_eq!(reading, Percent(19.15));
        assert!(reading.tripped, "g: the drive is tripped");
        assert_eq!(master.last_reply()[..3], [0x2F, 1, b'g']);
    }

    #[test]
    fn the_dummy_data_may_be_any_value() {
        let protocol = &vf_as1::protocols::BINARY;
        let mut sim = vfd_runtime::virtual_drive::VirtualDrive::new(&vf_as1::DRIVE);
        // FE35 (RR/S4 input) holds what the panel sets; FE03 would follow FD03 (0 at rest).
        sim.set_raw("FE35", 0x077B);
        // 2F 47 FE 35 12 34 + sum.
        let frame = with_sum("2F 47 FE 35 12 34");
        match sim.respond(protocol, &frame) {
            vfd_runtime::virtual_drive::Outcome::Reply(bytes) => {
                assert_eq!(bytes, with_sum("2F 47 FE 35 07 7B"));
            }
            other => panic!("expected the G reply, got {other:?}"),
        }
    }
}

mod s_command {
    use super::*;
    use vf_as1::registers::{FrequencyCommand2wire, FrequencyCommand4wire, MaximumFrequency};

    /// A master on the in-memory line, with the drive's settings.
    fn master_on_line() -> (
        Master<vfd_runtime::transport::MemoryTransport, vf_as1::Drive>,
        vfd_runtime::transport::MemoryTransport,
    ) {
        let (ours, theirs) = memory_pair();
        let master = Master::new(
            ours,
            &vf_as1::protocols::BINARY,
            vf_as1::DRIVE.serial.default,
            vf_as1::DRIVE.serial.timing,
        );
        (master, theirs)
    }

    #[test]
    fn the_master_sends_the_manuals_frame_and_returns_without_a_reply() {
        let (ours, mut drive) = memory_pair();
        let mut master = Master::new(
            Watched::new(ours),
            &vf_as1::protocols::BINARY,
            vf_as1::DRIVE.serial.default,
            vf_as1::DRIVE.serial.timing,
        );
        let started = Instant::now();
        // 4.2: FH 80 Hz, 40 Hz -> 50 % = 1388h.
        let raw = master
            .write_percent_of::<FrequencyCommand2wire, MaximumFrequency>(
                S,
                Hertz(40.0),
                Hertz(80.0),
            )
            .unwrap();
        let took = started.elapsed();
        assert_eq!(raw, 0x1388);
        assert_eq!(
            received(&mut drive, Duration::from_millis(50)),
            hex("2F 53 FA 01 13 88 18")
        );
        // Nothing answers, and the master did not wait for a reply: it never read the line
        // after sending (counted, not timed).
        assert_eq!(master.transport().sends(), 1);
        assert_eq!(master.transport().receives_after_send(), 0);
        // A lower bound only: the frame is on the line before the call returns.
        assert!(
            took >= vf_as1::DRIVE.serial.default.wire_time(7),
            "returns once the frame is on the line"
        );
        assert!(master.last_reply().is_empty());
    }

    #[test]
    fn the_manuals_master_numbers_give_5000() {
        let (mut master, mut drive) = master_on_line();
        let raw = master
            .write_percent_of::<FrequencyCommand4wire, MaximumFrequency>(
                S,
                Hertz(50.0),
                Hertz(100.0),
            )
            .unwrap();
        assert_eq!(raw, 5000);
        let frame = received(&mut drive, Duration::from_millis(50));
        assert_eq!(&frame[..6], hex("2F 53 FA 05 13 88"));
    }

    #[test]
    fn lower_case_s_says_the_sender_tripped() {
        let (mut master, mut drive) = master_on_line();
        let request =
            Request::for_register(CommandKind::WriteRam, FrequencyCommand2wire::INFO, 0x1388)
                .using(S_TRIPPED);
        master.transact(&request).unwrap();
        let frame = received(&mut drive, Duration::from_millis(50));
        assert_eq!(frame, hex("2F 73 FA 01 13 88 38"));
        let meaning = vfd_runtime::meaning::decode_meaning(
            &vf_as1::protocols::BINARY,
            vfd_runtime::meaning::Direction::Request,
            &frame,
        )
        .unwrap();
        assert_eq!((meaning.code, meaning.tripped), (Some(S_TRIPPED), true));
    }

    #[test]
    fn only_fa01_and_fa05_are_addressed_and_a_plain_write_never_becomes_s() {
        let (mut master, _drive) = master_on_line();
        let error = encode_error(
            master.write_percent_of::<MaximumFrequency, MaximumFrequency>(
                S,
                Hertz(50.0),
                Hertz(100.0),
            ),
        );
        assert!(
            matches!(
                error,
                EncodeError::RegisterNotServed {
                    register: 0x0011,
                    ..
                }
            ),
            "{error}"
        );
        let mut out = [0u8; 16];
        let len = vf_as1::protocols::BINARY
            .encode_request(
                &FrequencyCommand2wire::write_ram(Hertz(60.0)).unwrap(),
                None,
                &mut out,
            )
            .unwrap();
        assert_eq!(&out[..len], hex("2F 50 FA 01 17 70 01"), "P, not S");
    }

    #[test]
    fn a_percentage_of_another_register_is_refused() {
        let (mut master, _drive) = master_on_line();
        let error = encode_error(
            master.write_percent_of::<FrequencyCommand2wire, FrequencyCommand4wire>(
                S,
                Hertz(50.0),
                Hertz(100.0),
            ),
        );
        assert!(matches!(error, EncodeError::NotPercentOf { .. }), "{error}");
    }

    #[test]
    fn with_frequency_points_the_virtual_drive_converts_through_them() {
        // F810 = 1 (6.1): the received percentage maps through (F811 %, F812 Hz) -
        // (F813 %, F814 Hz); points (0 %, 0 Hz) - (100 %, 60 Hz): 50 % -> 30 Hz, where the
        // plain ratio of FH 80 Hz would give 40 Hz.
        let sim = Simulator::new(&vf_as1::DRIVE);
        assert!(sim.lock().set_raw("F810", 1));
        assert!(sim.lock().set_raw("F814", 6000));
        let outcome = sim
            .lock()
            .respond(&vf_as1::protocols::BINARY, &hex("2F 53 FA 01 13 88 18"));
        assert!(
            matches!(outcome, vfd_runtime::virtual_drive::Outcome::Silent(_)),
            "{outcome:?}"
        );
        assert_eq!(sim.lock().raw("FA01"), Some(3000));
        // F810 = 0: the plain ratio again.
        assert!(sim.lock().set_raw("F810", 0));
        sim.lock()
            .respond(&vf_as1::protocols::BINARY, &hex("2F 53 FA 01 13 88 18"));
        assert_eq!(sim.lock().raw("FA01"), Some(4000));
    }

    #[test]
    fn the_virtual_drive_takes_the_percentage_of_its_own_fh_and_stays_silent() {
        let sim = Simulator::new(&vf_as1::DRIVE);
        // Slave FH 90 Hz: 50 % -> 45 Hz (6.1).
        assert!(sim.lock().set_raw("FH", 9000));
        let mut master = sim.master(&vf_as1::protocols::BINARY);
        master
            .write_percent_of::<FrequencyCommand2wire, MaximumFrequency>(
                S,
                Hertz(50.0),
                Hertz(100.0),
            )
            .unwrap();
        assert_eq!(sim.lock().raw("FA01"), Some(4500));
        assert!(!sim.lock().sender_tripped());
        assert_eq!(master.read::<FrequencyCommand2wire>().unwrap(), Hertz(45.0));
        // The 4.2 frame, as the line delivers it: nothing comes back.
        let outcome = sim
            .lock()
            .respond(&vf_as1::protocols::BINARY, &hex("2F 53 FA 01 13 88 18"));
        assert!(
            matches!(outcome, vfd_runtime::virtual_drive::Outcome::Silent(_)),
            "{outcome:?}"
        );
        // s: the sender has tripped; the value still arrives.
        let outcome = sim
            .lock()
            .respond(&vf_as1::protocols::BINARY, &with_sum("2F 73 FA 05 07 D0"));
        assert!(matches!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Silent(_)
        ));
        assert!(sim.lock().sender_tripped());
        assert_eq!(sim.lock().raw("FA05"), Some(1800), "20 % of 90 Hz");
    }

    #[test]
    fn another_register_is_ignored_silently() {
        let sim = Simulator::new(&vf_as1::DRIVE);
        let before = sim.lock().raw("FA00");
        // S to FA00 (2F 53 FA 00 13 88 + sum): a communication-number error, which the
        // drive cannot send back.
        let frame = with_sum("2F 53 FA 00 13 88");
        let outcome = sim.lock().respond(&vf_as1::protocols::BINARY, &frame);
        assert!(matches!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Silent(_)
        ));
        assert_eq!(sim.lock().raw("FA00"), before);
    }
}

mod no_reply_register {
    use super::*;
    use dv1::codes::InverterResetCode;
    use dv1::registers::InverterReset;

    #[test]
    fn the_dv1_reset_is_sent_once_and_not_waited_for() {
        let (ours, mut theirs) = memory_pair();
        let mut master = Master::new(
            Watched::new(ours),
            &dv1::protocols::MODBUS,
            dv1::DRIVE.serial.default,
            dv1::DRIVE.serial.timing,
        )
        .with_address(Some(1))
        .with_retries(3);
        let written = master
            .write_ram::<InverterReset>(InverterResetCode::Reset)
            .unwrap();
        assert_eq!(written, None, "no reply, so no value reported written");
        // Not waited for: the master never read the line after sending (counted, not timed).
        assert_eq!(master.transport().sends(), 1);
        assert_eq!(master.transport().receives_after_send(), 0);
        // Derived frame (dv1.NEEDS.md item 6), sent once: never repeated.
        assert_eq!(
            received(&mut theirs, Duration::from_millis(50)),
            hex("01 06 11 01 96 96 32 F8")
        );
    }

    #[test]
    fn the_virtual_dv1_stays_silent_after_a_reset() {
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(&dv1::protocols::MODBUS);
        master
            .write_ram::<InverterReset>(InverterResetCode::Reset)
            .unwrap();
        assert_eq!(sim.requests(), 1);
        let outcome = sim
            .lock()
            .respond(&dv1::protocols::MODBUS, &hex("01 06 11 01 96 96 32 F8"));
        assert!(matches!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Silent(_)
        ));
    }
}
