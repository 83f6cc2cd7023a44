//! The virtual drive as FC51's manual describes it, driven through the typed generated API
//! over its FC and Modbus protocols: process telegrams and coils running to the reference,
//! trips, refusals with the manual's error numbers, RAM against EEPROM and silence for
//! other stations.

use std::time::Duration;
use vfd_drives::fc51;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, Request, Space};
use vfd_tests::outcomes::{refused, timed_out};

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
