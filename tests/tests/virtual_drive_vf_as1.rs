//! The virtual drive as VF-AS1's manual describes it, driven through the typed generated API
//! over its three protocols: the ramp, stops, coasting and trips, refusals with the manual's
//! codes per protocol, and Modbus reading one word only.

use std::time::Duration;
use vfd_drives::vf_as1;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, DriveProtocol, Request};
use vfd_tests::outcomes::refused;

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
