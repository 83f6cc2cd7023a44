//! Relations between registers that the description states, through the typed API and the
//! virtual drive: the VF-AS1's two serial ports (a master and a virtual drive on the
//! 4-wire port use FA04/FA05 for FA00/FA01), the FExx registers holding the FDxx values at
//! a trip, the ACC/DEC step chosen by FA09, and the manual's formulas.

use std::time::Duration;
use vf_as1::bits::CommandWord1 as Word;
use vf_as1::registers::*;
use vfd_drives::{dv1, vf_as1, yd1000};
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{Port, TransactionErrorKind, ValueError};

/// C400h, the 4.5 example: command and frequency priority, forward run.
fn run_forward() -> Word {
    Word::new()
        .with_command_priority(true)
        .with_frequency_priority(true)
        .with_run(true)
}

const PROTOCOLS: [&vfd_runtime::DriveProtocol<vf_as1::Drive>; 3] = [
    &vf_as1::protocols::ASCII,
    &vf_as1::protocols::BINARY,
    &vf_as1::protocols::MODBUS,
];

#[test]
fn the_description_pairs_the_ports_registers() {
    let ports = vf_as1::DRIVE.ports.expect("the VF-AS1 has two ports");
    let ids: Vec<&str> = ports.ports.iter().map(|p| p.id).collect();
    assert_eq!(ids, ["two_wire", "four_wire"]);
    assert_eq!(ports.port("four_wire").unwrap().settings.len(), 4);
    assert!(
        ports.port("4-wire RS-485").is_some(),
        "found by English name"
    );
    let four = Port::of(&vf_as1::DRIVE, "four_wire").unwrap();
    for (two_wire, four_wire) in [
        ("FA00", "FA04"),
        ("FA01", "FA05"),
        ("FA20", "FA22"),
        ("FA30", "FA32"),
    ] {
        let info = vf_as1::DRIVE.register(two_wire).unwrap();
        assert_eq!(four.register(info).code, four_wire);
        // A copy maps to itself on its own port, and back on the other.
        let copy = vf_as1::DRIVE.register(four_wire).unwrap();
        assert_eq!(four.register(copy).code, four_wire);
        assert_eq!(vf_as1::ports::TWO_WIRE.register(copy).code, two_wire);
    }
    // Registers both ports share are not mapped.
    assert_eq!(four.register(MaximumFrequency::INFO).code, "FH");
    assert!(Port::of(&vf_as1::DRIVE, "usb").is_none());
    assert!(
        Port::of(&yd1000::DRIVE, "two_wire").is_none(),
        "one port only"
    );
    // A request built for the 2-wire register goes to the 4-wire copy.
    let request = four.map(*FrequencyCommand2wire::write_ram(Hertz(60.0)).unwrap());
    assert_eq!((request.register, request.data), (0xFA05, 6000));
    assert_eq!(request.info.unwrap().code, "FA05");
}

#[test]
fn a_drive_on_its_4_wire_port_runs_from_the_4_wire_registers_a_master_picks_once() {
    for protocol in PROTOCOLS {
        let sim = Simulator::new(&vf_as1::DRIVE);
        assert!(sim.lock().set_port("four_wire"));
        assert!(!sim.lock().set_port("usb"));
        assert_eq!(sim.lock().port(), Some("four_wire"));
        // A master without a port writes FA00/FA01: on the 4-wire port they do not act.
        let mut plain = sim.master(protocol);
        plain
            .write_ram::<FrequencyCommand2wire>(Hertz(60.0))
            .unwrap();
        plain.write_ram::<CommandWord12wire>(run_forward()).unwrap();
        sim.advance(Duration::from_secs(1));
        assert_eq!(
            plain.read::<OutputFrequency>().unwrap(),
            Hertz(0.0),
            "{}",
            protocol.id
        );
        plain.write_ram::<CommandWord12wire>(Word::new()).unwrap();
        // The same typed calls through a master on the 4-wire port write FA04/FA05.
        let mut master = sim
            .master(protocol)
            .with_port(Some(vf_as1::ports::FOUR_WIRE));
        master
            .write_ram::<FrequencyCommand2wire>(Hertz(30.0))
            .unwrap();
        master
            .write_ram::<CommandWord12wire>(run_forward())
            .unwrap();
        assert_eq!(sim.lock().raw("FA05"), Some(3000));
        assert_eq!(sim.lock().raw("FA04"), Some(0xC400));
        assert_eq!(
            sim.lock().raw("FA01"),
            Some(6000),
            "FA01 keeps what was written"
        );
        assert_eq!(master.read::<FrequencyCommand2wire>().unwrap(), Hertz(30.0));
        // ACC/DEC have no factory setting: the output steps at once to the command.
        sim.advance(Duration::from_secs(1));
        assert_eq!(
            master.read::<OutputFrequency>().unwrap(),
            Hertz(30.0),
            "{}",
            protocol.id
        );
        assert!(master.read::<Status1>().unwrap().running());
    }
}

#[test]
fn the_held_registers_keep_the_values_of_the_moment_of_the_trip() {
    for protocol in PROTOCOLS {
        let sim = Simulator::new(&vf_as1::DRIVE);
        let mut master = sim.master(protocol);
        master
            .write_ram::<AccelerationTime1>(Seconds(10.0))
            .unwrap();
        master
            .write_ram::<FrequencyCommand2wire>(Hertz(60.0))
            .unwrap();
        master
            .write_ram::<CommandWord12wire>(run_forward())
            .unwrap();
        sim.advance(Duration::from_secs(10));
        assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(60.0));
        // FE90 follows FD00 by the 8.2 formula: 60 Hz, F856 = 2 (4 poles) -> 1800 min-1.
        assert_eq!(master.read::<OutputMotorSpeed>().unwrap(), Rpm(1800.0));
        // Between trips the held copies follow the live values (4.6 example 1 reads FE00
        // as the output frequency; see the description's behaviour note).
        assert_eq!(master.read::<OutputFrequencyAtTrip>().unwrap(), Hertz(60.0));
        sim.inject_trip(0x0018);
        assert_eq!(master.read::<OutputFrequency>().unwrap().value, Hertz(0.0));
        assert_eq!(
            master.read::<OutputFrequencyAtTrip>().unwrap().value,
            Hertz(60.0)
        );
        assert_eq!(
            master.read::<FrequencyCommandValueAtTrip>().unwrap().value,
            Hertz(60.0)
        );
        assert_eq!(
            master.read::<OutputCurrentAtTrip>().unwrap().value,
            Percent(67.94)
        );
        let held = master.read::<Status1AtTrip>().unwrap().value;
        assert_eq!(held.0, 0x6400, "status 1 as it was, running at the command");
        assert_eq!(master.read::<Status1>().unwrap().value.0, 0x0003);
        // FE90 is live except while tripped: it keeps 1800 though the output is 0.
        assert_eq!(
            master.read::<OutputMotorSpeed>().unwrap().value,
            Rpm(1800.0)
        );
        sim.advance(Duration::from_secs(2));
        assert_eq!(
            master.read::<OutputMotorSpeed>().unwrap().value,
            Rpm(1800.0)
        );
        assert_eq!(
            master.read::<OutputFrequencyAtTrip>().unwrap().value,
            Hertz(60.0)
        );
    }
}

#[test]
fn fa09_chooses_the_step_of_acc_in_the_typed_api_and_the_virtual_drive() {
    // 9 (4): ACC 10 s is 03E8h in 0.01 s steps; 4.2: DEC 10 s is 0064h in 0.1 s steps.
    let acc = AccelerationTime1::write_ram_scaled(Seconds(10.0), 0).unwrap();
    assert_eq!(acc.data, 0x03E8);
    let dec = DecelerationTime1::write_ram_scaled(Seconds(10.0), 1).unwrap();
    assert_eq!(dec.data, 0x0064);
    assert_eq!(
        AccelerationTime1::value_scaled(0x03E8, 0).unwrap(),
        Seconds(10.0)
    );
    assert_eq!(
        AccelerationTime1::value_scaled(0x03E8, 1).unwrap(),
        Seconds(100.0)
    );
    // 0.01-600.0 s with FA09 = 0, 0.1-6000 s with FA09 = 1.
    assert!(matches!(
        AccelerationTime1::write_ram_scaled(Seconds(700.0), 0),
        Err(ValueError::OutOfRange { max, .. }) if (max - 600.0).abs() < 1e-9
    ));
    assert!(AccelerationTime1::write_ram_scaled(Seconds(700.0), 1).is_ok());
    assert!(matches!(
        AccelerationTime1::write_ram_scaled(Seconds(10.0), 7),
        Err(ValueError::UnknownScale {
            selector: "FA09",
            value: 7,
            ..
        })
    ));
    // Registers with a fixed scale take any selector.
    assert_eq!(MaximumFrequency::scaled_info(5).unwrap().code, "FH");

    for protocol in PROTOCOLS {
        // 03E8h in ACC: 100 s from 0 Hz to FH (80 Hz) with FA09 = 1 (the assumed
        // default), 10 s with FA09 = 0 (FA09 cannot change while running).
        for (unit, selector, seconds, after_5_s) in [
            (vf_as1::codes::AccDecTimeUnit::Deciseconds, 1, 100.0, 4.0),
            (vf_as1::codes::AccDecTimeUnit::Centiseconds, 0, 10.0, 40.0),
        ] {
            let sim = Simulator::new(&vf_as1::DRIVE);
            let mut master = sim.master(protocol);
            master.write_ram::<AccDecTimeUnit>(unit).unwrap();
            let write = AccelerationTime1::write_ram_scaled(Seconds(seconds), selector).unwrap();
            master.transact(&write).unwrap();
            assert_eq!(sim.lock().raw("ACC"), Some(0x03E8));
            master
                .write_ram::<FrequencyCommand2wire>(Hertz(60.0))
                .unwrap();
            master
                .write_ram::<CommandWord12wire>(run_forward())
                .unwrap();
            sim.advance(Duration::from_secs(5));
            assert_eq!(
                master.read::<OutputFrequency>().unwrap(),
                Hertz(after_5_s),
                "{}",
                protocol.id
            );
        }
        let sim = Simulator::new(&vf_as1::DRIVE);
        let mut master = sim.master(protocol);
        // Both steps allow 1-60000 raw steps: 60001 is refused whatever FA09 says.
        let beyond = vfd_runtime::Request::for_register(
            vfd_runtime::CommandKind::WriteRam,
            AccelerationTime1::INFO,
            60001,
        );
        match master.transact(&beyond) {
            Err(error) => assert!(
                matches!(error.kind, TransactionErrorKind::Rejected { .. }),
                "{}: {error}",
                protocol.id
            ),
            Ok(answer) => panic!("{}: 60001 steps accepted: {answer:?}", protocol.id),
        }
    }
}

#[test]
fn the_manuals_formulas_give_the_manuals_numbers() {
    use vf_as1::conversions::*;
    // 8.1: 1800 min-1 with F856 = 2 (4 poles) is 6000 = 60.00 Hz.
    assert_eq!(frequency_from_motor_speed(1800.0, 2.0), Some(6000.0));
    // 8.2: 60.00 Hz (FD00 60.0, times 100) with 4 poles is 1800 min-1.
    assert_eq!(motor_speed_from_frequency(60.0, 2.0), Some(1800.0));
    // 6.1: master at 50 Hz of FH 100 Hz sends 5000 (50 %); receivers with FH 90 / 80 Hz.
    assert_eq!(ratio_percent_from_frequency(50.0, 100.0), Some(5000.0));
    assert_eq!(frequency_from_ratio(5000.0, 90.0), Some(45.0));
    assert_eq!(
        frequency_from_points(5000.0, 0.0, 0.0, 100.0, 90.0),
        Some(45.0)
    );
    // Points at the same percentage divide by zero: no result, no panic.
    assert_eq!(frequency_from_points(5000.0, 50.0, 0.0, 50.0, 90.0), None);

    // The virtual drive evaluates them with its own register values: F810 = 0 by default.
    let sim = Simulator::new(&vf_as1::DRIVE);
    let drive = sim.lock();
    // FH is 80 Hz by default: 50 % is 40 Hz.
    assert_eq!(drive.convert("frequency_from_ratio", &[5000.0]), Some(40.0));
    assert_eq!(
        drive.convert("frequency_from_points", &[5000.0]),
        None,
        "F810 = 0"
    );
    assert_eq!(
        drive.convert("frequency_from_motor_speed", &[]),
        Some(0.0),
        "FA13 = 0"
    );
    drop(drive);
    let mut master = sim.master(&vf_as1::protocols::BINARY);
    master
        .write_ram::<FrequencyPointSelection>(vf_as1::codes::FrequencyPointSelection::TwoWire)
        .unwrap();
    master.write_ram::<Point2Frequency>(Hertz(60.0)).unwrap();
    assert_eq!(
        sim.lock().convert("frequency_from_points", &[5000.0]),
        Some(30.0)
    );
    assert_eq!(
        sim.lock().convert("frequency_from_ratio", &[5000.0]),
        None,
        "F810 != 0"
    );
}

#[test]
fn dv1_takes_99999_as_ffffh_besides_its_range_and_starts_with_it() {
    use dv1::registers::CommunicationInterval as Interval;
    // *6): a parameter's 99999 is written and read as FFFFh; 07-09's factory setting.
    assert_eq!(Interval::write_ram(Seconds(99999.0)).unwrap().data, 0xFFFF);
    assert_eq!(Interval::INFO.default_raw, Some(0xFFFF));
    assert!(matches!(
        Interval::write_ram(Seconds(1000.0)),
        Err(ValueError::OutOfRange { .. })
    ));
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    assert_eq!(master.read::<Interval>().unwrap(), Seconds(99999.0));
    master.write_ram::<Interval>(Seconds(2.0)).unwrap();
    assert_eq!(sim.lock().raw("07-09"), Some(20));
    master.write_ram::<Interval>(Seconds(99999.0)).unwrap();
    assert_eq!(sim.lock().raw("07-09"), Some(0xFFFF));
    assert_eq!(master.read::<Interval>().unwrap(), Seconds(99999.0));
}

#[test]
fn dv1_parameters_answer_to_their_p_numbers() {
    // 通讯参数组 (l. 19-52): every communication parameter has a group number and a P
    // number; 02-15 is P.195 (例三).
    for (code, alias) in [
        ("07-00", "P.33"),
        ("07-01", "P.36"),
        ("07-07", "P.154"),
        ("07-11", "P.34"),
        ("02-15", "P.195"),
    ] {
        let by_code = dv1::DRIVE.register(code).expect(code);
        assert_eq!(by_code.aliases, [alias], "{code}");
        let by_alias = dv1::DRIVE.register(alias).expect(alias);
        assert!(std::ptr::eq(by_code, by_alias), "{alias} names {code}");
        let lower = alias.to_ascii_lowercase();
        assert!(
            dv1::DRIVE
                .register(&lower)
                .is_some_and(|r| std::ptr::eq(r, by_code)),
            "{lower}"
        );
    }
    // The typed API's aliases are the same types.
    fn code_of<R: Register>() -> &'static str {
        R::INFO.code
    }
    assert_eq!(code_of::<dv1::registers::P195>(), "02-15");
    assert_eq!(code_of::<dv1::registers::P33>(), "07-00");
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    master
        .write_ram::<dv1::registers::P195>(Hertz(50.0))
        .unwrap();
    assert_eq!(
        master.read::<dv1::registers::Parameter0215>().unwrap(),
        Hertz(50.0)
    );
}

#[test]
fn dv1_refuses_the_communication_settings_its_manual_forbids() {
    // 5.8.1 设定, note 4 (l. 102): in the Eaton protocol (07-00 = 1, the factory setting),
    // two stop bits only without parity; 7 data bits, 1 stop bit and no parity cannot be
    // used. Note 1 (l. 94): Modbus (07-00 = 0) needs a station number other than 0.
    use dv1::registers::{DataLength, Parity, Protocol, StationNumber, StopBits};
    let rejected = |error: vfd_runtime::TransactionError| {
        matches!(
            error.kind,
            TransactionErrorKind::Rejected { code: 0x03, .. }
        )
    };
    let sim = Simulator::new(&dv1::DRIVE);
    let mut master = sim.master(&dv1::protocols::MODBUS);
    master
        .write_ram::<Parity>(dv1::codes::Parity::Even)
        .unwrap();
    let error = master
        .write_ram::<StopBits>(dv1::codes::StopBits::Bits2)
        .unwrap_err();
    assert!(rejected(error), "two stop bits with even parity");
    assert_eq!(sim.lock().raw("07-04"), Some(0), "07-04 unchanged");
    master
        .write_ram::<Parity>(dv1::codes::Parity::None)
        .unwrap();
    master
        .write_ram::<StopBits>(dv1::codes::StopBits::Bits2)
        .unwrap();
    // 07-04 = 1 now: parity must stay 0.
    assert!(rejected(
        master
            .write_ram::<Parity>(dv1::codes::Parity::Odd)
            .unwrap_err()
    ));
    master
        .write_ram::<StopBits>(dv1::codes::StopBits::Bits1)
        .unwrap();
    // 7 bits with 1 stop bit and no parity.
    assert!(rejected(
        master
            .write_ram::<DataLength>(dv1::codes::DataLength::Bits7)
            .unwrap_err()
    ));
    // Under Modbus (07-00 = 0) those rules do not apply, but the station must not be 0.
    // (The virtual drive answers at the station 07-01 holds, set to 1 for Modbus; a new
    // value takes effect after a reset, so the drive stays at station 1.)
    assert_eq!(sim.lock().raw("07-01"), Some(1));
    master.write_ram::<StationNumber>(0).unwrap();
    assert!(rejected(
        master
            .write_ram::<Protocol>(dv1::codes::Protocol::Modbus)
            .unwrap_err()
    ));
    master.write_ram::<StationNumber>(1).unwrap();
    master
        .write_ram::<Protocol>(dv1::codes::Protocol::Modbus)
        .unwrap();
    master
        .write_ram::<DataLength>(dv1::codes::DataLength::Bits7)
        .unwrap();
    assert!(rejected(master.write_ram::<StationNumber>(0).unwrap_err()));
    // The rule as a typed error, quoting the manual.
    let stop = dv1::DRIVE.register("07-04").unwrap();
    let error = dv1::DRIVE
        .check_combinations(stop, 1, |code| match code {
            "07-00" => Some(1),
            "07-05" => Some(2),
            _ => None,
        })
        .unwrap_err();
    assert_eq!(error.combination.id, "two_stop_bits_with_parity");
    let message = error.to_string();
    assert!(message.contains("请务必把 07-05 设定为 0"), "{message}");
    assert!(message.contains("note 4 (l. 102)"), "{message}");
}
