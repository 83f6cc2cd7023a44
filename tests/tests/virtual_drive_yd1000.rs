//! The virtual drive as YD1000's manual describes it, driven through the typed generated API
//! over both its protocols: the ramp on the simulated clock, status bits, a trip and its
//! reset, refusals with the manual's codes, RAM against EEPROM and silence for other
//! stations.

use std::time::Duration;
use vfd_drives::yd1000;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, Request};
use vfd_tests::drive_protocols::YD1000_PROTOCOLS;
use vfd_tests::outcomes::{refused, timed_out};

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
