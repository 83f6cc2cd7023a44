//! A frequency command in percent of a register (`behaviour.frequency.percent_of`;
//! drives/README.md "A frequency command in percent"), on the Huanyang GT's virtual drive:
//! 2000H is a percentage of the maximum frequency P0.03, the motor runs at that share of
//! P0.03 (read again when P0.03 changes), and 3000H and 3001H show hertz, not percent.

use std::time::Duration;
use vfd_drives::hy_gt;
use vfd_drives::hy_gt::codes::{ControlCommand as Code, InverterStatus as Status};
use vfd_drives::hy_gt::registers::*;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;

#[test]
fn the_motor_runs_at_the_commanded_share_of_the_maximum_frequency() {
    let sim = Simulator::new(&hy_gt::DRIVE);
    let mut master = sim.master(&hy_gt::protocols::MODBUS);
    master.write_ram::<MaximumFrequency>(Hertz(60.0)).unwrap();
    // 50.00 % of 60.00 Hz.
    master
        .write_ram::<CommunicationSetting>(Percent(50.0))
        .unwrap();
    master
        .write_ram::<ControlCommand>(Code::ForwardRun)
        .unwrap();
    // The model's ramp: 5 s over P0.03 (12 Hz a second here); 30 Hz is reached in 2.5 s.
    sim.advance(Duration::from_secs(1));
    assert_eq!(master.read::<OperationFrequency>().unwrap(), Hertz(12.0));
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<OperationFrequency>().unwrap(), Hertz(30.0));
    assert_eq!(master.read::<SettingFrequency>().unwrap(), Hertz(30.0));
    assert_eq!(
        master.read::<InverterStatus>().unwrap().value,
        Status::ForwardRunning
    );
    // The speed follows P2.03 at P2.02 (1440 rpm at 50.00 Hz by default): 864 rpm at 30 Hz.
    assert_eq!(master.read::<RotationSpeed>().unwrap(), Rpm(864.0));

    // 25.00 %: 15 Hz, on the deceleration ramp.
    master
        .write_ram::<CommunicationSetting>(Percent(25.0))
        .unwrap();
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<OperationFrequency>().unwrap(), Hertz(15.0));
    assert_eq!(master.read::<SettingFrequency>().unwrap(), Hertz(15.0));

    // Stop: the output ramps to zero and 1001H reads standby.
    master.write_ram::<ControlCommand>(Code::Stop).unwrap();
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<OperationFrequency>().unwrap(), Hertz(0.0));
    assert_eq!(
        master.read::<InverterStatus>().unwrap().value,
        Status::Standby
    );

    // A new maximum frequency (set while stopped) moves the same percentage: 25.00 % of
    // 100.00 Hz.
    master.write_ram::<MaximumFrequency>(Hertz(100.0)).unwrap();
    master
        .write_ram::<ControlCommand>(Code::ForwardRun)
        .unwrap();
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<OperationFrequency>().unwrap(), Hertz(25.0));
    assert_eq!(master.read::<SettingFrequency>().unwrap(), Hertz(25.0));
}
