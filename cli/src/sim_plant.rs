//! The built-in virtual plant behind `vfd demo --plant`: two multi-drop buses, each a
//! pseudo-terminal served by a thread of its own, with five virtual stations of three drive
//! models, and the plant file (YAML, docs/plant.md) that polls them, pseudo-terminal paths
//! filled in. Line `line1`, Modbus RTU at 9600 baud 8E1: fc51 at 1 and 2, vf-as1 at 3;
//! line `line2`, Toshiba binary at 9600 baud 8E1: yd1000 at 1, vf-as1 at 2 (each drive takes
//! 9600 baud, even parity). Which registers are polled is named by code here and looked up
//! in each drive's description when the plant is started, so a code a description lacks is
//! an error, not a silent gap.

use crate::sim_station::{self, SimStation};
use crate::{lookup, Failure};
use std::fmt::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::transport::PseudoTerminal;
use vfd_runtime::virtual_drive::{serve_bus, BusStation, Simulator};

/// One station of the built-in plant: its name, drive, protocol, address, the registers
/// polled every second and the one that may be written (RAM).
struct Planned {
    name: &'static str,
    drive: &'static str,
    protocol: &'static str,
    address: u8,
    poll: &'static [&'static str],
    write: &'static str,
}

/// The built-in plant's buses: a name and the stations on it.
const PLANT: [(&str, &[Planned]); 2] = [
    (
        "line1",
        &[
            Planned {
                name: "pump1",
                drive: "fc51",
                protocol: "modbus",
                address: 1,
                poll: &["MAV", "REF", "STW"],
                write: "REF",
            },
            Planned {
                name: "pump2",
                drive: "fc51",
                protocol: "modbus",
                address: 2,
                poll: &["MAV", "REF", "STW"],
                write: "REF",
            },
            Planned {
                name: "fan1",
                drive: "vf-as1",
                protocol: "modbus",
                address: 3,
                poll: &["FD00", "FA01", "FD01", "FD03"],
                write: "FA01",
            },
        ],
    ),
    (
        "line2",
        &[
            Planned {
                name: "conveyor1",
                drive: "yd1000",
                protocol: "binary",
                address: 1,
                poll: &["FD00", "FA01", "FE01", "FE03"],
                write: "FA01",
            },
            Planned {
                name: "fan2",
                drive: "vf-as1",
                protocol: "binary",
                address: 2,
                poll: &["FD00", "FA01", "FD01", "FD03"],
                write: "FA01",
            },
        ],
    ),
];

/// The line every bus of the built-in plant runs at: 9600 baud, 8 data bits, even parity,
/// 1 stop bit.
fn line_settings() -> SerialSettings {
    SerialSettings {
        baud: 9600,
        parity: Parity::Even,
        data_bits: 8,
        stop_bits: 1,
    }
}

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

/// Starts the built-in virtual plant: one pseudo-terminal and one server thread per bus.
pub fn start() -> Result<VirtualPlant, Failure> {
    let settings = line_settings();
    let stop = Arc::new(AtomicBool::new(false));
    let mut plant = VirtualPlant {
        buses: Vec::new(),
        stations: Vec::new(),
        plant_file: String::from(
            "# The built-in virtual plant of `vfd demo --plant`: two multi-drop buses of virtual\n\
             # drives on pseudo-terminals (docs/plant.md describes every key).\nbuses:\n",
        ),
        stop: Arc::clone(&stop),
        servers: Vec::new(),
    };
    for (bus_name, planned) in PLANT {
        let mut stations: Vec<SimStation> = Vec::new();
        for p in planned {
            let drive = lookup::drive(p.drive)?;
            let protocol = lookup::protocol(drive, Some(p.protocol))?;
            for code in p.poll.iter().chain([&p.write]) {
                lookup::register(drive, code)?;
            }
            stations.push(sim_station::station(drive, protocol, p.address));
        }
        sim_station::check_line(&stations, &settings)?;
        let pty = PseudoTerminal::open()
            .map_err(|e| Failure::new(format!("cannot open a pseudo-terminal: {e}")))?;
        let device = pty.slave_path().display().to_string();
        let mut transport = pty
            .master()
            .map_err(|e| Failure::new(format!("cannot use the pseudo-terminal: {e}")))?;
        let bus: Vec<BusStation> = stations.iter().map(|s| s.bus.clone()).collect();
        let server = {
            let stop = Arc::clone(&stop);
            std::thread::Builder::new()
                .name(format!("virtual bus {bus_name}"))
                .spawn(move || serve_bus(&bus, &mut transport, settings, &stop))
                .map_err(|e| Failure::new(format!("cannot start virtual bus {bus_name}: {e}")))?
        };
        plant.servers.push(server);
        let _ = writeln!(
            plant.plant_file,
            "  - name: {bus_name}\n    port: {device}\n    baud: {}\n    parity: even\n    drives:",
            settings.baud
        );
        for (p, station) in planned.iter().zip(&stations) {
            let _ = writeln!(
                plant.plant_file,
                "      - name: {}\n        drive: {}\n        protocol: {}\n        station: {}\n        poll:\n          - every: 1s\n            registers: [{}]\n        write:\n          - {}",
                p.name,
                p.drive,
                p.protocol,
                p.address,
                p.poll.iter().map(|c| format!("\"{c}\"")).collect::<Vec<_>>().join(", "),
                format_args!("\"{}\"", p.write),
            );
            plant.stations.push(PlantStation {
                bus: bus_name.to_string(),
                name: p.name.to_string(),
                address: p.address,
                drive: p.drive,
                simulator: station.bus.simulator.clone(),
            });
        }
        plant.buses.push(PlantBus {
            name: bus_name.to_string(),
            device,
            settings,
        });
    }
    Ok(plant)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bus::{LineArgs, Session};

    fn line_args(drive: &str, protocol: &str, port: &str, address: u8) -> LineArgs {
        LineArgs {
            drive: drive.into(),
            protocol: Some(protocol.into()),
            port: port.into(),
            baud: Some(9600),
            parity: Some(crate::bus::ParityArg::Even),
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
        let plant = start().unwrap();
        assert!(plant.buses.len() >= 2);
        assert!(plant.stations.len() >= 3);
        for (bus_name, planned) in PLANT {
            let bus = plant.buses.iter().find(|b| b.name == bus_name).unwrap();
            assert!(plant.plant_file.contains(&format!("port: {}", bus.device)));
            for p in planned {
                let mut session =
                    Session::open(&line_args(p.drive, p.protocol, &bus.device, p.address))
                        .unwrap_or_else(|f| panic!("{bus_name} {}: {}", p.name, f.message));
                let drive = lookup::drive(p.drive).unwrap();
                for code in p.poll {
                    let info = lookup::register(drive, code).unwrap();
                    session
                        .read(info)
                        .unwrap_or_else(|f| panic!("{bus_name} {} {code}: {}", p.name, f.message));
                }
                let station = plant.station(bus_name, p.name).unwrap();
                assert_eq!(
                    station.simulator.tally().addressed,
                    station.simulator.tally().answered
                );
                assert!(station.simulator.tally().answered >= p.poll.len() as u64);
            }
        }
        // A station unplugged: silent, the others still answer.
        let pump2 = plant.station("line1", "pump2").unwrap();
        pump2.simulator.set_unplugged(true);
        let device = &plant.buses[0].device;
        let mav = lookup::register(lookup::drive("fc51").unwrap(), "MAV").unwrap();
        let mut two = Session::open(&line_args("fc51", "modbus", device, 2)).unwrap();
        assert!(two.read(mav).is_err());
        let mut one = Session::open(&line_args("fc51", "modbus", device, 1)).unwrap();
        one.read(mav).unwrap();
        assert!(plant.plant_file.contains("write:\n          - \"REF\""));
        plant.stop().unwrap();
    }
}
