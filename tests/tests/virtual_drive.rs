//! The virtual drive, driven through the typed generated API for both described drives and
//! every protocol: ramps on the simulated clock, status bits, trips, refusals with the
//! manual's codes, RAM against EEPROM and silence for other stations.

use std::time::Duration;
use vfd_drives::{dv1, fc51, vf_as1, yd1000};
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::{Fault, Simulator};
use vfd_runtime::{CommandKind, DriveProtocol, Request, Space, TransactionErrorKind};
use vfd_tests::outcomes::{refused, timed_out};

const YD1000_PROTOCOLS: [&DriveProtocol<yd1000::Drive>; 2] =
    [&yd1000::protocols::ASCII, &yd1000::protocols::BINARY];

mod yd1000_drive {
    use super::*;
    use yd1000::bits::CommandWord as Word;
    use yd1000::registers::*;

    fn run_forward() -> Word {
        Word::new()
            .with_command_enabled(true)
            .with_frequency_enabled(true)
            .with_run(true)
    }

    #[test]
    fn runs_to_60_hz_on_the_ramp_stops_trips_and_resets() {
        for protocol in YD1000_PROTOCOLS {
            let sim = Simulator::new(&yd1000::DRIVE);
            let mut master = sim.master(protocol);
            master.write_ram::<FrequencyCommand>(Hertz(60.0)).unwrap();
            master.write_ram::<CommandWord>(run_forward()).unwrap();
            // Acc = 10 s from 0 Hz to FH = 80 Hz: 8 Hz per second.
            sim.advance(Duration::from_secs(5));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(40.0));
            assert!(master.read::<Status>().unwrap().running());
            sim.advance(Duration::from_secs(5));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(60.0));
            assert_eq!(master.read::<OutputFrequencyNow>().unwrap(), Hertz(60.0));
            assert_eq!(master.read::<FrequencyReference>().unwrap(), Hertz(60.0));
            // The section 9 example: 077Bh at 60 Hz.
            assert_eq!(master.read::<OutputCurrent>().unwrap(), Percent(19.15));
            let status = master.read::<Status>().unwrap();
            assert!(status.running() && !status.reverse() && !status.tripped);

            master
                .write_ram::<CommandWord>(run_forward().with_run(false))
                .unwrap();
            sim.advance(Duration::from_secs(4));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(28.0));
            sim.advance(Duration::from_secs(10));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            assert!(!master.read::<Status>().unwrap().running());

            // Err5 (0018h), as section 9 reads it: lower-case replies, the code in FC90.
            master.write_ram::<CommandWord>(run_forward()).unwrap();
            sim.advance(Duration::from_secs(3));
            sim.inject_trip(0x0018);
            let alarm = master.read::<AlarmCode>().unwrap();
            assert!(alarm.tripped, "{}", protocol.id);
            assert_eq!(alarm.value, 0x0018);
            assert_eq!(master.read::<PastTrip1>().unwrap(), 0x0018);
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            master
                .write_ram::<CommandWord>(Word::new().with_command_enabled(true).with_reset(true))
                .unwrap();
            let alarm = master.read::<AlarmCode>().unwrap();
            assert!(!alarm.tripped);
            assert_eq!(alarm.value, 0);
            assert_eq!(master.read::<PastTrip1>().unwrap(), 0x0018);
        }
    }

    #[test]
    fn refuses_out_of_range_read_only_and_running_writes_with_the_manuals_codes() {
        for protocol in YD1000_PROTOCOLS {
            let sim = Simulator::new(&yd1000::DRIVE);
            let mut master = sim.master(protocol);
            // FA01 may go up to FH (80 Hz by default), UL up to FH, LL up to UL.
            assert_eq!(
                refused(master.write_ram::<FrequencyCommand>(Hertz(85.0))),
                1
            );
            master
                .write_ram::<UpperLimitFrequency>(Hertz(50.0))
                .unwrap();
            assert_eq!(
                refused(master.write_ram::<LowerLimitFrequency>(Hertz(55.0))),
                1
            );
            master
                .write_ram::<LowerLimitFrequency>(Hertz(45.0))
                .unwrap();
            // A read-only monitor: "cannot execute".
            let write_monitor = Request::raw(CommandKind::WriteRam, 0xFE00, 0x1770);
            assert_eq!(refused(master.transact(&write_monitor)), 0);
            // An unknown communication number.
            let nowhere = Request::raw(CommandKind::Read, 0x7777, 0);
            assert_eq!(refused(master.transact(&nowhere)), 2);
            // FH cannot change while running; UL can.
            master.write_ram::<FrequencyCommand>(Hertz(30.0)).unwrap();
            master.write_ram::<CommandWord>(run_forward()).unwrap();
            sim.advance(Duration::from_secs(1));
            assert_eq!(
                refused(master.write_ram::<MaximumFrequency>(Hertz(100.0))),
                0
            );
            master
                .write_ram::<UpperLimitFrequency>(Hertz(60.0))
                .unwrap();
        }
    }

    #[test]
    fn a_power_cycle_drops_ram_writes_and_after_reset_parameters_wait() {
        for protocol in YD1000_PROTOCOLS {
            let sim = Simulator::new(&yd1000::DRIVE);
            let mut master = sim.master(protocol);
            master
                .write_ram::<DecelerationTime1>(Seconds(20.0))
                .unwrap();
            master
                .write_persistent::<AccelerationTime1>(Seconds(5.0))
                .unwrap();
            master.write_ram::<FrequencyCommand>(Hertz(60.0)).unwrap();
            sim.power_cycle();
            // Silent while it starts up (section 3: about 1 s after power-on).
            timed_out(master.read::<DecelerationTime1>());
            sim.advance(yd1000::SERIAL.timing.startup_delay);
            assert_eq!(master.read::<DecelerationTime1>().unwrap(), Seconds(10.0));
            assert_eq!(master.read::<AccelerationTime1>().unwrap(), Seconds(5.0));
            assert_eq!(master.read::<FrequencyCommand>().unwrap(), Hertz(0.0));

            // F800 (baud rate) takes effect after a reset.
            master
                .write_persistent::<BaudRate>(yd1000::codes::BaudRate::Bps4800)
                .unwrap();
            assert_eq!(sim.lock().raw_in_effect("F800"), Some(3));
            sim.lock().reset();
            assert_eq!(sim.lock().raw_in_effect("F800"), Some(2));
        }
    }

    #[test]
    fn other_stations_requests_and_bad_checksums() {
        for protocol in YD1000_PROTOCOLS {
            let sim = Simulator::new(&yd1000::DRIVE);
            let mut master = sim.master(protocol).with_address(Some(7));
            timed_out(master.read::<MaximumFrequency>());
            // Without a station number every drive on the line answers.
            let mut master = sim.master(protocol).with_address(None);
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
        }
        // A bad checksum gets the manual's checksum error (N0004).
        let sim = Simulator::new(&yd1000::DRIVE);
        let mut drive = sim.lock();
        let outcome = drive.respond(yd1000::protocols::ASCII.protocol(), b"(R0011&00)\r");
        assert_eq!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Reply(b"(N0004&60)\r".to_vec())
        );
    }
}

mod fc51_drive {
    use super::*;
    use fc51::bits::ControlWord as Word;
    use fc51::registers::*;

    fn run() -> Word {
        Word::new()
            .with_no_dc_brake(true)
            .with_no_coast(true)
            .with_no_quick_stop(true)
            .with_no_freeze(true)
            .with_start(true)
            .with_data_valid(true)
    }

    #[test]
    fn fc_process_telegrams_run_to_the_reference_and_show_a_trip() {
        let sim = Simulator::new(&fc51::DRIVE);
        let mut master = sim.master(&fc51::protocols::FC);
        let sixty_percent: u16 = 9830; // 60 % of 4000h
        let [status, output] = master
            .exchange_process(run().bits(), sixty_percent)
            .unwrap();
        assert_eq!((status & 0x0800, output), (0x0800, 0));
        sim.advance(Duration::from_secs(3));
        let [status, output] = master
            .exchange_process(run().bits(), sixty_percent)
            .unwrap();
        assert_eq!(
            status, 0x0D07,
            "running at the reference, as the manual's example"
        );
        assert_eq!(output, sixty_percent);
        // The parameter telegram's PCD words carry the status word and the output too.
        sim.inject_trip(1);
        let [status, output] = master
            .exchange_process(run().bits(), sixty_percent)
            .unwrap();
        assert_eq!((status & 0x0008, output), (0x0008, 0));
        let reset = run().with_reset(true).with_start(false);
        let [status, _] = master.exchange_process(reset.bits(), 0).unwrap();
        assert_eq!(status & 0x0008, 0);
        assert_eq!(sim.lock().trip(), None);
    }

    #[test]
    fn modbus_coils_run_to_the_reference_and_show_a_trip() {
        let sim = Simulator::new(&fc51::DRIVE);
        let mut master = sim.master(&fc51::protocols::MODBUS);
        master.write_ram::<BusReference>(Percent(60.0)).unwrap();
        master.write_ram::<ControlWord>(run()).unwrap();
        sim.advance(Duration::from_secs(1));
        let status = master.read::<StatusWord>().unwrap();
        assert!(status.running() && !status.at_reference());
        sim.advance(Duration::from_secs(2));
        let output = master.read::<OutputFrequency>().unwrap();
        assert!((output.0 - 60.0).abs() < 0.01, "{output:?}");
        let status = master.read::<StatusWord>().unwrap();
        assert!(status.running() && status.at_reference() && !status.tripped());
        master
            .write_ram::<ControlWord>(run().with_start(false))
            .unwrap();
        sim.advance(Duration::from_secs(3));
        assert!(!master.read::<StatusWord>().unwrap().running());
        sim.inject_trip(1);
        assert!(master.read::<StatusWord>().unwrap().tripped());
        master
            .write_ram::<ControlWord>(run().with_start(false).with_reset(true))
            .unwrap();
        assert!(!master.read::<StatusWord>().unwrap().tripped());
    }

    #[test]
    fn refuses_with_the_manuals_error_numbers() {
        let sim = Simulator::new(&fc51::DRIVE);
        let mut fc = sim.master(&fc51::protocols::FC);
        let mut modbus = sim.master(&fc51::protocols::MODBUS);
        // A word parameter written beyond 16 bits: above the upper limit (2).
        let too_big = Request::raw(CommandKind::WriteRam, 310, 0x1_0000);
        assert_eq!(refused(fc.transact(&too_big)), 2);
        // No such parameter: 0 in FC telegrams, invalid data address (64) over Modbus.
        let nowhere = Request::raw(CommandKind::Read, 999, 0);
        assert_eq!(refused(fc.transact(&nowhere)), 0);
        assert_eq!(refused(modbus.transact(&nowhere)), 64);
        // The status word is read-only (1).
        let write_status = Request::raw(CommandKind::WriteRam, 33, 0).in_space(Space::Coil);
        assert_eq!(refused(modbus.transact(&write_status)), 1);
        // Parameters cannot be written while the motor runs (17).
        modbus.write_ram::<BusReference>(Percent(50.0)).unwrap();
        modbus.write_ram::<ControlWord>(run()).unwrap();
        sim.advance(Duration::from_secs(1));
        assert_eq!(refused(fc.write_ram::<MaximumReference>(60.0)), 17);
        assert_eq!(refused(modbus.write_ram::<MaximumReference>(60.0)), 17);
    }

    #[test]
    fn a_power_cycle_drops_ram_writes_over_both_protocols() {
        let sim = Simulator::new(&fc51::DRIVE);
        let mut fc = sim.master(&fc51::protocols::FC);
        let mut modbus = sim.master(&fc51::protocols::MODBUS);
        fc.write_persistent::<MaximumReference>(50.0).unwrap();
        fc.write_ram::<MaximumReference>(60.0).unwrap();
        modbus.write_persistent_at::<PresetReference>(2, 7).unwrap();
        modbus.write_ram_at::<PresetReference>(2, 9).unwrap();
        assert_eq!(modbus.read::<MaximumReference>().unwrap(), 60.0);
        assert_eq!(fc.read_at::<PresetReference>(2).unwrap(), 9);
        sim.power_cycle();
        sim.advance(fc51::SERIAL.timing.startup_delay);
        assert_eq!(modbus.read::<MaximumReference>().unwrap(), 50.0);
        assert_eq!(fc.read_at::<PresetReference>(2).unwrap(), 7);
        assert_eq!(modbus.read_at::<PresetReference>(2).unwrap(), 7);
    }

    #[test]
    fn other_stations_get_no_answer() {
        let sim = Simulator::new(&fc51::DRIVE);
        timed_out(
            sim.master(&fc51::protocols::FC)
                .with_address(Some(9))
                .read::<MaximumReference>(),
        );
        timed_out(
            sim.master(&fc51::protocols::MODBUS)
                .with_address(Some(9))
                .read::<MaximumReference>(),
        );
    }
}

mod faults {
    use super::*;
    use yd1000::registers::MaximumFrequency;

    #[test]
    fn injected_faults_become_typed_errors_and_tolerated_ones_do_not() {
        for protocol in YD1000_PROTOCOLS {
            let sim = Simulator::new(&yd1000::DRIVE);
            let mut master = sim.master(protocol);
            sim.inject(Fault::DropReply);
            timed_out(master.read::<MaximumFrequency>());
            sim.inject(Fault::Delay);
            timed_out(master.read::<MaximumFrequency>());
            sim.inject(Fault::CorruptChecksum);
            assert!(master.read::<MaximumFrequency>().is_err());
            sim.inject(Fault::WrongStation);
            assert!(master.read::<MaximumFrequency>().is_err());
            // Noise before the start byte, a split reply and an echo are read through.
            sim.inject(Fault::GarbageBefore(vec![0x00, 0xFF, 0x55]));
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
            sim.inject(Fault::SplitBytes(2));
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
            sim.inject(Fault::Noise);
            assert!(master.read::<MaximumFrequency>().is_err());
            sim.lock().clear_faults();
            assert_eq!(master.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
            let mut other = sim.master(protocol).with_address(Some(9));
            sim.inject(Fault::AnswerBroadcast);
            assert_eq!(other.read::<MaximumFrequency>().unwrap(), Hertz(80.0));
        }
    }

    #[test]
    fn an_echoing_line_returns_every_request_until_cleared_even_when_the_drive_is_silent() {
        let protocol = yd1000::protocols::BINARY.protocol();
        let sim = Simulator::new(&yd1000::DRIVE);
        let mut frame = [0u8; 32];
        let request = Request::read::<MaximumFrequency>();
        let len = protocol
            .encode_request(&request, Some(1), &mut frame)
            .unwrap();
        let request = frame[..len].to_vec();
        let sent = |sim: &Simulator| -> Vec<Vec<u8>> {
            let mut input = request.clone();
            let sent = sim.lock().receive(protocol, &mut input);
            sent.into_iter().map(|t| t.bytes).collect()
        };
        let reply = sent(&sim).remove(0);
        sim.inject(Fault::EchoRequest);
        assert_eq!(sent(&sim), [request.clone(), reply.clone()]);
        assert_eq!(
            sent(&sim),
            [request.clone(), reply.clone()],
            "still echoing"
        );
        sim.inject(Fault::DropReply);
        assert_eq!(
            sent(&sim),
            std::slice::from_ref(&request),
            "the line echoes a silent drive's request"
        );
        sim.clear_faults();
        assert_eq!(sent(&sim), [reply]);
        assert_eq!(sim.requests(), 5);
    }
}

mod over_a_pseudo_terminal {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use vfd_runtime::transport::PseudoTerminal;
    use vfd_runtime::virtual_drive::serve;

    #[test]
    fn the_serve_loop_answers_a_master_with_the_lines_timing() {
        let (line, mut drive_end) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        let sim = Simulator::new(&fc51::DRIVE);
        let stop = Arc::new(AtomicBool::new(false));
        let server = {
            let (sim, stop) = (sim.clone(), Arc::clone(&stop));
            std::thread::spawn(move || {
                serve(
                    &sim,
                    fc51::protocols::MODBUS.protocol(),
                    &mut drive_end,
                    fc51::SERIAL.default,
                    &stop,
                )
            })
        };
        let mut master = Master::new(
            line,
            &fc51::protocols::MODBUS,
            fc51::SERIAL.default,
            fc51::SERIAL.timing,
        )
        .with_address(Some(1));
        master
            .write_persistent::<fc51::registers::MaximumReference>(50.0)
            .unwrap();
        assert_eq!(
            master.read::<fc51::registers::MaximumReference>().unwrap(),
            50.0
        );
        sim.inject(Fault::SplitBytes(1));
        assert_eq!(
            master.read::<fc51::registers::MaximumReference>().unwrap(),
            50.0
        );
        let mut other = Master::new(
            master.into_transport(),
            &fc51::protocols::MODBUS,
            fc51::SERIAL.default,
            fc51::SERIAL.timing,
        )
        .with_address(Some(2));
        timed_out(other.read::<fc51::registers::MaximumReference>());
        stop.store(true, Ordering::Relaxed);
        server.join().unwrap().unwrap();
        drop(other);
    }
}

const VF_AS1_PROTOCOLS: [&DriveProtocol<vf_as1::Drive>; 3] = [
    &vf_as1::protocols::ASCII,
    &vf_as1::protocols::BINARY,
    &vf_as1::protocols::MODBUS,
];

mod vf_as1_drive {
    use super::*;
    use vf_as1::bits::CommandWord1 as Word;
    use vf_as1::registers::*;

    /// C400h, the 4.5 example: command and frequency priority, forward run.
    fn run_forward() -> Word {
        Word::new()
            .with_command_priority(true)
            .with_frequency_priority(true)
            .with_run(true)
    }

    #[test]
    fn runs_to_60_hz_on_the_ramp_stops_coasts_and_trips() {
        for protocol in VF_AS1_PROTOCOLS {
            let sim = Simulator::new(&vf_as1::DRIVE);
            let mut master = sim.master(protocol);
            assert_eq!(run_forward().bits(), 0xC400);
            // ACC and DEC have no factory setting in the manual: 10 s from 0 Hz to FH (80 Hz).
            master
                .write_ram::<AccelerationTime1>(Seconds(10.0))
                .unwrap();
            master
                .write_ram::<DecelerationTime1>(Seconds(10.0))
                .unwrap();
            master
                .write_ram::<FrequencyCommand2wire>(Hertz(60.0))
                .unwrap();
            assert_eq!(master.read::<Status1>().unwrap().value.0, 0x4000);
            master
                .write_ram::<CommandWord12wire>(run_forward())
                .unwrap();
            sim.advance(Duration::from_secs(5));
            assert_eq!(
                master.read::<OutputFrequency>().unwrap(),
                Hertz(40.0),
                "{}",
                protocol.id
            );
            assert!(master.read::<Status1>().unwrap().running());
            sim.advance(Duration::from_secs(5));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(60.0));
            assert_eq!(master.read::<FrequencyCommandValue>().unwrap(), Hertz(60.0));
            // The 4.1.3 Y reply: 6400h, 60.00 Hz, 67.94 %.
            assert_eq!(master.read::<OutputCurrent>().unwrap(), Percent(67.94));
            let status = master.read::<Status1>().unwrap();
            assert_eq!(status.value.0, 0x6400);
            assert!(status.running() && !status.reverse() && !status.tripped);

            master
                .write_ram::<CommandWord12wire>(run_forward().with_run(false))
                .unwrap();
            sim.advance(Duration::from_secs(4));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(28.0));
            sim.advance(Duration::from_secs(10));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            assert!(!master.read::<Status1>().unwrap().running());

            // Without frequency priority (8600h) the communication frequency does not act.
            master
                .write_ram::<CommandWord12wire>(run_forward().with_frequency_priority(false))
                .unwrap();
            sim.advance(Duration::from_secs(2));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));

            // The emergency stop (bit 12) stops at once, and FD01 bit 12 shows it.
            master
                .write_ram::<CommandWord12wire>(run_forward())
                .unwrap();
            sim.advance(Duration::from_secs(3));
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(24.0));
            master
                .write_ram::<CommandWord12wire>(run_forward().with_emergency_stop(true))
                .unwrap();
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            assert!(master.read::<Status1>().unwrap().emergency_stop());

            // Err5 (0018h), as 4.5 reads it: the code in FC90 and FE10, status 0003h.
            master
                .write_ram::<CommandWord12wire>(run_forward())
                .unwrap();
            sim.advance(Duration::from_secs(3));
            sim.inject_trip(0x0018);
            let trip = master.read::<TripCode>().unwrap();
            assert_eq!(trip.value, 0x0018);
            // Lower-case replies in the Toshiba protocol; Modbus replies carry no such sign.
            assert_eq!(trip.tripped, protocol.id != "modbus", "{}", protocol.id);
            assert_eq!(master.read::<PastTrip1>().unwrap(), 0x0018);
            assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
            assert_eq!(master.read::<Status1>().unwrap().value.0, 0x0003);
        }
    }

    #[test]
    fn refuses_with_the_manuals_codes_per_protocol() {
        for protocol in VF_AS1_PROTOCOLS {
            let modbus = protocol.id == "modbus";
            let code = |toshiba: u16, modbus_code: u16| if modbus { modbus_code } else { toshiba };
            let sim = Simulator::new(&vf_as1::DRIVE);
            let mut master = sim.master(protocol);
            // FA01 may go up to FH (80 Hz here).
            assert_eq!(
                refused(master.write_ram::<FrequencyCommand2wire>(Hertz(85.0))),
                code(1, 3)
            );
            let write_monitor = Request::raw(CommandKind::WriteRam, 0xFD00, 0x1770);
            assert_eq!(refused(master.transact(&write_monitor)), code(0, 4));
            let nowhere = Request::raw(CommandKind::Read, 0x7777, 0);
            assert_eq!(refused(master.transact(&nowhere)), 2);
            // FH cannot change while running (4.1.1).
            master
                .write_ram::<FrequencyCommand2wire>(Hertz(30.0))
                .unwrap();
            master
                .write_ram::<CommandWord12wire>(run_forward())
                .unwrap();
            sim.advance(Duration::from_secs(1));
            assert_eq!(
                refused(master.write_ram::<MaximumFrequency>(Hertz(60.0))),
                code(0, 4)
            );
        }
    }
    #[test]
    fn modbus_reads_one_word_only_as_the_manual_shows() {
        // 5.1.1: a read of two words gets exception 03, byte for byte as printed.
        let sim = Simulator::new(&vf_as1::DRIVE);
        let mut drive = sim.lock();
        drive.set_address(1);
        let outcome = drive.respond(
            vf_as1::protocols::MODBUS.protocol(),
            &[0x01, 0x03, 0xFD, 0x00, 0x00, 0x02, 0xF5, 0xA7],
        );
        assert_eq!(
            outcome,
            vfd_runtime::virtual_drive::Outcome::Reply(vec![0x01, 0x83, 0x03, 0x01, 0x31])
        );
    }
}

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
