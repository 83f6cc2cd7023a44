//! The DV1's target frequency, RAM (1002h, Eaton HED) and EEPROM (1009h, Eaton HEE), is
//! taken while the motor runs, over every protocol: the command list makes 频率写入 a
//! class of its own beside 参数写入 (l. 141-145), and a running drive's speed is changed
//! by it; a parameter (07-08) is still refused while running (H0A, 模式异常).

use std::time::Duration;
use vfd_drives::dv1;
use vfd_drives::dv1::registers::*;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::DriveProtocol;
use vfd_tests::outcomes::refused;

const PROTOCOLS: [&DriveProtocol<dv1::Drive>; 3] = [
    &dv1::protocols::MODBUS,
    &dv1::protocols::MODBUS_ASCII,
    &dv1::protocols::EATON,
];

#[test]
fn both_frequency_commands_are_written_while_the_motor_runs() {
    for protocol in PROTOCOLS {
        let sim = Simulator::new(&dv1::DRIVE);
        let mut master = sim.master(protocol);
        master
            .write_ram::<FrequencyCommandRam>(Hertz(20.0))
            .unwrap();
        master
            .write_ram::<RunCommand>(dv1::bits::RunCommand::new().with_forward(true))
            .unwrap();
        sim.advance(Duration::from_secs(1));
        assert!(sim.lock().is_running(), "{}", protocol.id);
        master
            .write_ram::<FrequencyCommandRam>(Hertz(40.0))
            .unwrap_or_else(|e| panic!("{}: 1002h while running: {e}", protocol.id));
        // Over Eaton the instruction decides the storage (HEE: RAM and EEPROM), so 1009h
        // is written persistently there; elsewhere its write reaches RAM.
        let eeprom = if protocol.id == "eaton" {
            master.write_persistent::<FrequencyCommandEeprom>(Hertz(45.0))
        } else {
            master.write_ram::<FrequencyCommandEeprom>(Hertz(45.0))
        };
        eeprom.unwrap_or_else(|e| panic!("{}: 1009h while running: {e}", protocol.id));
        assert_eq!(
            master.read::<FrequencyCommandEeprom>().unwrap(),
            Hertz(45.0),
            "{}",
            protocol.id
        );
        // A parameter is refused while running, with the protocol's code.
        let code = refused(master.write_ram::<AllowedErrorCount>(5));
        let expected = if protocol.id == "eaton" { 0x0A } else { 0x03 };
        assert_eq!(code, expected, "{}", protocol.id);
    }
}
