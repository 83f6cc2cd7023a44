//! Commands of one kind that reach different tables of a drive by their function code (the
//! Huanyang HY: 01 reads a parameter, 04 a status value; 02 writes a parameter, 03 the
//! control byte, 05 the frequency): the library takes, for each register, the command whose
//! register field carries its number (`Protocol::command_for_register`), over the typed API
//! and against the virtual drive.

use std::time::Duration;
use vfd_drives::hy::{self, bits, protocols, registers::*};
use vfd_runtime::prelude::*;
use vfd_runtime::units::Hertz;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, DataType, EncodeError, Space};

fn encode(request: &vfd_runtime::DriveRequest<hy::Drive>) -> Vec<u8> {
    let mut frame = [0u8; 32];
    let len = protocols::RTU
        .encode_request(request, Some(1), &mut frame)
        .expect("encodes");
    frame[..len].to_vec()
}

#[test]
fn each_register_takes_the_function_of_its_table() {
    // Status value 1 (Out F): function 04 with CFG 01, not a parameter read of 0401h.
    assert_eq!(
        encode(&OutputFrequency::read()),
        [0x01, 0x04, 0x01, 0x01, 0x80, 0x49]
    );
    // A parameter: function 01, LEN 3, PD005, data 0000h.
    assert_eq!(
        encode(&MaximumFrequency::read()),
        [0x01, 0x01, 0x03, 0x05, 0x00, 0x00, 0x2C, 0x4F]
    );
    // The frequency: function 05 (its function byte is its register field).
    assert_eq!(
        encode(&FrequencyCommand::write_ram(Hertz(200.0)).unwrap()),
        [0x01, 0x05, 0x02, 0x4E, 0x20, 0x8C, 0xB4]
    );
    // The control byte: function 03, run + r/f.
    let reverse = bits::ControlCommand::new().with_run(true).with_r_f(true);
    assert_eq!(
        encode(&ControlCommand::write_ram(reverse).unwrap()),
        [0x01, 0x03, 0x01, 0x11, 0x30, 0x44]
    );
    // A parameter write: function 02, a word (LEN 3) or a byte (LEN 2) as the register is wide.
    assert_eq!(
        encode(&MainFrequency::write_persistent(Hertz(30.0)).unwrap()),
        [0x01, 0x02, 0x03, 0x03, 0x0B, 0xB8, 0x8F, 0x0C]
    );
    assert_eq!(
        encode(&MotorPoles::write_persistent(2).unwrap()),
        [0x01, 0x02, 0x02, 0x8F, 0x02, 0x5C, 0x49]
    );
}

#[test]
fn a_command_for_one_register_is_never_taken_for_another() {
    // 05 is the only RAM write of a word, but its field allows only its own function code:
    // a RAM write of PD003 has no command, rather than going out as a frequency write.
    let mut frame = [0u8; 32];
    let request = vfd_runtime::Request {
        kind: CommandKind::WriteRam,
        ..MainFrequency::write_persistent(Hertz(30.0))
            .unwrap()
            .into_request()
    };
    assert!(matches!(
        protocols::RTU
            .protocol()
            .encode_request(&request, Some(1), &mut frame),
        Err(EncodeError::UnsupportedCommand { .. })
    ));
    let info = MainFrequency::INFO;
    assert!(protocols::RTU
        .command_for_register(
            CommandKind::WriteRam,
            Space::Parameter,
            DataType::Word,
            info.address
        )
        .is_none());
    // Status values can be read, the status byte (carried by 03's reply only) cannot.
    assert!(protocols::RTU.can_read(OutputFrequency::INFO));
    assert!(!protocols::RTU.can_read(ControlStatus::INFO));
}

#[test]
fn a_master_runs_the_virtual_drive_through_every_function() {
    let sim = Simulator::new(&hy::DRIVE);
    let mut master = sim.master(&protocols::RTU);
    master
        .write_persistent::<MaximumFrequency>(Hertz(400.0))
        .unwrap();
    master.write_ram::<FrequencyCommand>(Hertz(200.0)).unwrap();
    // The reply to 03 carries the status byte, not the byte written: the master takes it.
    master
        .write_ram::<ControlCommand>(bits::ControlCommand::new().with_run(true))
        .unwrap();
    sim.advance(Duration::from_secs(60));
    assert_eq!(master.read::<SetFrequency>().unwrap(), Hertz(200.0));
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(200.0));
    let status = sim.lock().raw("CNST").unwrap();
    assert_eq!(status & 0x09, 0x09, "run and running: {status:02X}h");
    assert_eq!(status & 0x24, 0, "forward: {status:02X}h");
    master
        .write_ram::<ControlCommand>(bits::ControlCommand::new().with_stop(true))
        .unwrap();
    sim.advance(Duration::from_secs(60));
    assert_eq!(master.read::<OutputFrequency>().unwrap(), Hertz(0.0));
    assert_eq!(sim.lock().raw("CNST").unwrap() & 0x09, 0);
}
