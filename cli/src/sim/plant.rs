//! The built-in virtual plant behind `vfd demo --plant`: the plant file `sim_plant.yaml`
//! (two multi-drop buses, five stations of three drive models: every fact about them is
//! there, none here), each bus a pseudo-terminal served by a thread of its own with a
//! virtual drive per station, and the plant file with each bus's `port:` replaced by its
//! pseudo-terminal.

use crate::Failure;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use vfd_bus::plant::Plant;
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transport::PseudoTerminal;
use vfd_runtime::virtual_drive::{serve_bus, BusStation, Simulator};

/// The built-in plant file; each bus's `port:` names its virtual line.
const PLANT_FILE: &str = include_str!("plant.yaml");

/// The name the built-in plant file goes by in messages.
const PLANT_NAME: &str = "demo-plant.yaml";

/// A station of the running plant, to unplug it or look at what it saw.
#[derive(Debug, Clone)]
pub struct PlantStation {
    /// Its bus's name.
    pub bus: String,
    /// Its name in the plant file.
    pub name: String,
    /// Its station address.
    pub address: u8,
    /// Its drive id.
    pub drive: &'static str,
    /// The virtual drive: [`Simulator::set_unplugged`] pulls its plug,
    /// [`Simulator::tally`] tells what it received.
    pub simulator: Simulator,
}

/// One bus of the running plant.
#[derive(Debug, Clone)]
pub struct PlantBus {
    /// Its name in the plant file.
    pub name: String,
    /// The pseudo-terminal a master opens.
    pub device: String,
    /// Its line settings.
    pub settings: SerialSettings,
}

/// The built-in virtual plant, served until it is dropped (or [`VirtualPlant::stop`]).
pub struct VirtualPlant {
    /// The buses, in the plant file's order.
    pub buses: Vec<PlantBus>,
    /// Every station, bus by bus.
    pub stations: Vec<PlantStation>,
    /// The plant file (YAML) that polls it, device paths filled in.
    pub plant_file: String,
    stop: Arc<AtomicBool>,
    servers: Vec<JoinHandle<std::io::Result<()>>>,
}

impl VirtualPlant {
    /// The station named `name` on bus `bus`.
    pub fn station(&self, bus: &str, name: &str) -> Option<&PlantStation> {
        self.stations
            .iter()
            .find(|s| s.bus == bus && s.name == name)
    }

    /// Stops every bus's server and waits for them; a server's transport error is returned.
    pub fn stop(mut self) -> Result<(), Failure> {
        self.halt()
    }

    fn halt(&mut self) -> Result<(), Failure> {
        self.stop.store(true, Ordering::Relaxed);
        let mut result = Ok(());
        for server in self.servers.drain(..) {
            match server.join() {
                Ok(Ok(())) => {}
                Ok(Err(e)) => {
                    result = Err(Failure::new(format!("a virtual bus stopped: {e}")));
                }
                Err(_) => result = Err(Failure::new("a virtual bus's thread panicked")),
            }
        }
        result
    }
}

impl Drop for VirtualPlant {
    fn drop(&mut self) {
        let _ = self.halt();
    }
}

/// The built-in plant file, read and checked (its ports still the virtual lines' names).
fn template(catalogue: &vfd_bus::Catalogue) -> Result<Plant, Failure> {
    vfd_bus::plant::load_str(PLANT_FILE, Path::new(PLANT_NAME), catalogue).map_err(|problems| {
        Failure::new(format!("the built-in plant file is refused:\n{problems}"))
    })
}

/// Starts the built-in virtual plant: one pseudo-terminal and one server thread per bus,
/// one virtual drive per station of the plant file.
pub fn start(catalogue: &vfd_bus::Catalogue) -> Result<VirtualPlant, Failure> {
    let template = template(catalogue)?;
    let stop = Arc::new(AtomicBool::new(false));
    let mut plant = VirtualPlant {
        buses: Vec::new(),
        stations: Vec::new(),
        plant_file: PLANT_FILE.to_owned(),
        stop: Arc::clone(&stop),
        servers: Vec::new(),
    };
    for bus in &template.buses {
        let stations: Vec<BusStation> = bus
            .stations
            .iter()
            .map(|station| {
                let simulator = Simulator::new(station.drive);
                let address = station
                    .address
                    .unwrap_or_else(|| station.protocol.address_range.0.max(1));
                simulator.lock().set_address(address);
                if let Some(port) = station.port {
                    simulator.lock().set_port(port.id);
                }
                BusStation {
                    simulator,
                    protocol: station.protocol,
                }
            })
            .collect();
        let pty = PseudoTerminal::open()
            .map_err(|e| Failure::new(format!("cannot open a pseudo-terminal: {e}")))?;
        let device = pty.slave_path().display().to_string();
        let mut transport = pty
            .master()
            .map_err(|e| Failure::new(format!("cannot use the pseudo-terminal: {e}")))?;
        for (station, served) in bus.stations.iter().zip(&stations) {
            plant.stations.push(PlantStation {
                bus: bus.name.clone(),
                name: station.name.clone(),
                address: served.simulator.lock().address(),
                drive: station.drive.id,
                simulator: served.simulator.clone(),
            });
        }
        let settings = bus.settings;
        let name = bus.name.clone();
        let server = std::thread::Builder::new()
            .name(format!("virtual bus {name}"))
            .spawn({
                let stop = Arc::clone(&stop);
                move || serve_bus(&stations, &mut transport, settings, &stop)
            })
            .map_err(|e| Failure::new(format!("cannot start virtual bus {name}: {e}")))?;
        plant.servers.push(server);
        plant.plant_file = plant.plant_file.replace(
            &format!("port: {}\n", bus.port),
            &format!("port: {device}\n"),
        );
        plant.buses.push(PlantBus {
            name: bus.name.clone(),
            device,
            settings,
        });
    }
    Ok(plant)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::line_args::LineArgs;

    fn line_args(drive: &str, protocol: &str, port: &str, address: u8) -> LineArgs {
        LineArgs {
            drive: drive.into(),
            protocol: Some(protocol.into()),
            port: port.into(),
            baud: Some(9600),
            parity: Some(crate::line_args::ParityArg::Even),
            data_bits: None,
            stop_bits: None,
            address: Some(address),
            timeout: None,
            port_kind: None,
            variant: None,
            trace: false,
            retries: Some(1),
            gap_ms: None,
            host_latency_ms: None,
        }
    }

    #[test]
    fn every_station_of_the_virtual_plant_answers_a_read_on_its_bus() {
        let catalogue = vfd_bus::Catalogue::new();
        let plant = start(&catalogue).unwrap();
        assert!(plant.buses.len() >= 2);
        assert!(plant.stations.len() >= 3);
        // The plant file as served: every port is a pseudo-terminal now.
        let served =
            vfd_bus::plant::load_str(&plant.plant_file, Path::new(PLANT_NAME), &catalogue).unwrap();
        for bus in &served.buses {
            let device = &plant
                .buses
                .iter()
                .find(|b| b.name == bus.name)
                .unwrap()
                .device;
            assert_eq!(&bus.port, device);
            for station in &bus.stations {
                let address = station.address.unwrap();
                let mut session = crate::open_session::open_session(
                    &line_args(station.drive.id, &station.protocol.id, device, address),
                    &catalogue,
                )
                .unwrap_or_else(|f| panic!("{} {}: {}", bus.name, station.name, f.message));
                for poll in &station.polls {
                    session.read(poll.register).unwrap_or_else(|f| {
                        panic!(
                            "{} {} {}: {}",
                            bus.name,
                            station.name,
                            poll.register.code,
                            f.message()
                        )
                    });
                }
                let virtual_station = plant.station(&bus.name, &station.name).unwrap();
                let tally = virtual_station.simulator.tally();
                assert_eq!(tally.addressed, tally.answered);
                assert!(tally.answered >= station.polls.len() as u64);
            }
        }
        // A station unplugged: silent, the others on its bus still answer.
        let line1 = &served.buses[0];
        let (first, second) = (&line1.stations[0], &line1.stations[1]);
        plant
            .station(&line1.name, &second.name)
            .unwrap()
            .simulator
            .set_unplugged(true);
        let device = &plant.buses[0].device;
        let register = second.polls[0].register;
        let mut two = crate::open_session::open_session(
            &line_args(
                second.drive.id,
                &second.protocol.id,
                device,
                second.address.unwrap(),
            ),
            &catalogue,
        )
        .unwrap();
        assert!(two.read(register).is_err());
        let mut one = crate::open_session::open_session(
            &line_args(
                first.drive.id,
                &first.protocol.id,
                device,
                first.address.unwrap(),
            ),
            &catalogue,
        )
        .unwrap();
        one.read(first.polls[0].register).unwrap();
        plant.stop().unwrap();
    }
}
