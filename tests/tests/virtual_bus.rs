//! Several virtual drives on one line (`serve_bus`): each answers its own station and
//! ignores the others' frames, an unplugged station stays silent while it counts what
//! was addressed to it, and drives of two models share a line when their protocols share
//! a framing.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use vfd_drives::{fc51, vf_as1, yd1000};
use vfd_runtime::prelude::*;
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transport::PseudoTerminal;
use vfd_runtime::transport::Transport;
use vfd_runtime::virtual_drive::{same_framing, serve_bus, BusStation, Simulator};
use vfd_tests::outcomes::timed_out;

/// A station of `drive` at `address`, speaking `protocol`.
fn station(
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static vfd_runtime::Protocol,
    address: u8,
) -> BusStation {
    let simulator = Simulator::new(drive);
    simulator.lock().set_address(address);
    BusStation {
        simulator,
        protocol,
    }
}

/// A bus serving `stations` on a pseudo-terminal: the master's end, the stop flag and
/// the server thread.
fn bus(
    stations: Vec<BusStation>,
    settings: SerialSettings,
) -> (
    impl Transport + Send + 'static,
    Arc<AtomicBool>,
    JoinHandle<std::io::Result<()>>,
) {
    let (line, mut drive_end) = PseudoTerminal::open().unwrap().into_transports().unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || serve_bus(&stations, &mut drive_end, settings, &stop))
    };
    (line, stop, server)
}

fn stop(stop: &AtomicBool, server: JoinHandle<std::io::Result<()>>) {
    stop.store(true, Ordering::Relaxed);
    server.join().unwrap().unwrap();
}

/// fc51 at 9600 8E1 (its only speed), which the VF-AS1 can be set to too.
fn line() -> SerialSettings {
    fc51::SERIAL.default
}

#[test]
fn each_station_answers_its_own_frames_and_ignores_the_others() {
    use fc51::registers::MaximumReference;
    let stations = vec![
        station(&fc51::DRIVE, fc51::protocols::MODBUS.protocol(), 1),
        station(&fc51::DRIVE, fc51::protocols::MODBUS.protocol(), 2),
    ];
    let sims: Vec<Simulator> = stations.iter().map(|s| s.simulator.clone()).collect();
    let (line_end, stop_flag, server) = bus(stations, line());
    let mut master = Master::new(
        line_end,
        &fc51::protocols::MODBUS,
        line(),
        fc51::SERIAL.timing,
    )
    .with_address(Some(1));
    master.write_ram::<MaximumReference>(42.0).unwrap();
    assert_eq!(master.read::<MaximumReference>().unwrap(), 42.0);
    master = master.with_address(Some(2));
    // Station 2 kept its own value: station 1's write was not for it.
    assert_ne!(master.read::<MaximumReference>().unwrap(), 42.0);
    master = master.with_address(Some(3));
    timed_out(master.read::<MaximumReference>());
    let (one, two) = (sims[0].tally(), sims[1].tally());
    // The write (with its persistence pre-step, on this drive) and the read: all answered.
    assert!(one.writes >= 1);
    assert_eq!(one.addressed, one.answered);
    assert_eq!((two.addressed, two.answered, two.writes), (1, 1, 0));
    // Every station heard every frame: its own, the other's and station 3's.
    assert_eq!(sims[0].requests(), one.addressed + 2);
    assert_eq!(sims[1].requests(), sims[0].requests());
    stop(&stop_flag, server);
}

#[test]
fn an_unplugged_station_is_silent_acts_on_nothing_and_counts_what_it_was_sent() {
    use fc51::registers::MaximumReference;
    let stations = vec![
        station(&fc51::DRIVE, fc51::protocols::MODBUS.protocol(), 1),
        station(&fc51::DRIVE, fc51::protocols::MODBUS.protocol(), 2),
    ];
    let sims: Vec<Simulator> = stations.iter().map(|s| s.simulator.clone()).collect();
    let (line_end, stop_flag, server) = bus(stations, line());
    let mut master = Master::new(
        line_end,
        &fc51::protocols::MODBUS,
        line(),
        fc51::SERIAL.timing,
    )
    .with_address(Some(2));
    let before = master.read::<MaximumReference>().unwrap().value;
    sims[1].set_unplugged(true);
    timed_out(master.write_ram::<MaximumReference>(before + 1.0));
    timed_out(master.read::<MaximumReference>());
    let tally = sims[1].tally();
    assert_eq!(
        tally.addressed, 3,
        "the unplugged station counts what it was sent"
    );
    assert_eq!((tally.answered, tally.writes), (1, 0), "and does nothing");
    // Station 1 goes on answering.
    master = master.with_address(Some(1));
    master.read::<MaximumReference>().unwrap();
    sims[1].set_unplugged(false);
    master = master.with_address(Some(2));
    assert_eq!(master.read::<MaximumReference>().unwrap(), before);
    assert_eq!(sims[1].tally().writes, 0);
    stop(&stop_flag, server);
}

#[test]
fn two_models_share_a_line_when_their_protocols_share_a_framing() {
    let yd = yd1000::protocols::BINARY.protocol();
    let vf = vf_as1::protocols::BINARY.protocol();
    assert!(same_framing(yd, vf));
    assert!(!same_framing(vf, vf_as1::protocols::MODBUS.protocol()));
    assert!(same_framing(
        fc51::protocols::MODBUS.protocol(),
        vf_as1::protocols::MODBUS.protocol()
    ));
    let stations = vec![
        station(&yd1000::DRIVE, yd, 1),
        station(&vf_as1::DRIVE, vf, 2),
    ];
    let sims: Vec<Simulator> = stations.iter().map(|s| s.simulator.clone()).collect();
    let settings = yd1000::SERIAL.default;
    let (line_end, stop_flag, server) = bus(stations, settings);
    let mut yd_master = Master::new(
        line_end,
        &yd1000::protocols::BINARY,
        settings,
        yd1000::SERIAL.timing,
    )
    .with_address(Some(1));
    yd_master
        .write_ram::<yd1000::registers::FrequencyCommand>(Hertz(30.0))
        .unwrap();
    assert_eq!(
        yd_master
            .read::<yd1000::registers::FrequencyCommand>()
            .unwrap(),
        Hertz(30.0)
    );
    let mut vf_master = Master::new(
        yd_master.into_transport(),
        &vf_as1::protocols::BINARY,
        settings,
        vf_as1::SERIAL.timing,
    )
    .with_address(Some(2));
    vf_master
        .write_ram::<vf_as1::registers::FrequencyCommand2wire>(Hertz(20.0))
        .unwrap();
    assert_eq!(
        vf_master
            .read::<vf_as1::registers::FrequencyCommand2wire>()
            .unwrap(),
        Hertz(20.0)
    );
    assert_eq!(sims[0].tally().writes, 1);
    assert_eq!(sims[1].tally().writes, 1);
    stop(&stop_flag, server);
}
