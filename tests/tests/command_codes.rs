//! A behaviour model whose command register holds codes and whose state is a code
//! (`command.codes`, `status.state`; drives/README.md "Command codes and state codes"), on
//! the PI500's virtual drive: each code acts as its list says, a code in no list and a run
//! code while tripped change nothing, and 3000H shows the state.

use std::time::Duration;
use vfd_drives::pi500;
use vfd_drives::pi500::codes::{ControlCommand as Code, InverterState as State};
use vfd_drives::pi500::registers::*;
use vfd_runtime::prelude::*;
use vfd_runtime::virtual_drive::Simulator;

#[test]
fn codes_run_reverse_stop_coast_and_reset_and_the_state_register_follows() {
    let sim = Simulator::new(&pi500::DRIVE);
    let mut master = sim.master(&pi500::protocols::MODBUS);
    master.write_ram::<FrequencySetting>(Hertz(40.0)).unwrap();
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::Standby
    );

    // 1: forward run. The model's ramp: 5 s per 50 Hz, 10 Hz a second.
    master
        .write_ram::<ControlCommand>(Code::ForwardRun)
        .unwrap();
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(20.0));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::ForwardRunning
    );
    sim.advance(Duration::from_secs(3));
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(40.0));

    // 3 (forward jog) is in no list of the model: nothing changes.
    master
        .write_ram::<ControlCommand>(Code::ForwardJog)
        .unwrap();
    sim.advance(Duration::from_secs(1));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::ForwardRunning
    );
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(40.0));

    // 2: reverse run, through zero.
    master
        .write_ram::<ControlCommand>(Code::ReverseRun)
        .unwrap();
    sim.advance(Duration::from_secs(8));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::ReverseRunning
    );
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(40.0));

    // 6: stop on the ramp; still running while the output falls.
    master.write_ram::<ControlCommand>(Code::Stop).unwrap();
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(20.0));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::ReverseRunning
    );
    sim.advance(Duration::from_secs(3));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::Standby
    );

    // 5: coast: the output drops to zero at once.
    master
        .write_ram::<ControlCommand>(Code::ForwardRun)
        .unwrap();
    sim.advance(Duration::from_secs(4));
    master.write_ram::<ControlCommand>(Code::FreeStop).unwrap();
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(0.0));
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::Standby
    );

    // A trip: 3000H = 4, 8000H the code; a run code is ignored until 7 resets it.
    sim.inject_trip(0x0E);
    assert_eq!(master.read::<InverterState>().unwrap().value, State::Fault);
    assert_eq!(
        master.read::<FaultCode>().unwrap().value,
        0x0E,
        "module overheating"
    );
    master
        .write_ram::<ControlCommand>(Code::ForwardRun)
        .unwrap();
    sim.advance(Duration::from_secs(2));
    assert_eq!(master.read::<InverterState>().unwrap().value, State::Fault);
    assert_eq!(master.read::<RunningFrequency>().unwrap(), Hertz(0.0));
    master
        .write_ram::<ControlCommand>(Code::FaultReset)
        .unwrap();
    assert_eq!(
        master.read::<InverterState>().unwrap().value,
        State::Standby
    );
    assert_eq!(master.read::<FaultCode>().unwrap().value, 0);
    assert!(!sim.lock().is_running());
}
