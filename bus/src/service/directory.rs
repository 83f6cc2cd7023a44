//! The plant's names resolved once, when the service is set up: a bus's name to its index,
//! a station's name to its index on the bus, and each name a write request may give an
//! allowed register by (its code, id and aliases) to its entry in the station's allow-list.
//! A write request is routed with these handles ([`Target`]); the bus worker never looks a
//! station or a register up by name for a request the plant allows.

use crate::plant::Plant;
use std::collections::HashMap;

/// Where a write request goes, resolved from its names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Target {
    /// The bus's index in the plant.
    pub bus: usize,
    /// The station's index on the bus (`None`: the bus has no station of that name).
    pub station: Option<usize>,
    /// The register's entry in the station's allow-list (`None`: the name is none of the
    /// allowed registers' own names; the worker then finds what it names, to refuse it
    /// with the reason).
    pub allowed: Option<usize>,
}

/// A bus's entry.
#[derive(Debug, Default)]
struct BusEntry {
    index: usize,
    stations: HashMap<String, StationEntry>,
}

/// A station's entry.
#[derive(Debug, Default)]
struct StationEntry {
    index: usize,
    /// A name of an allowed register -> its entry in the allow-list.
    allowed: HashMap<String, usize>,
}

/// The names of a plant, resolved.
#[derive(Debug, Default)]
pub struct Directory {
    buses: HashMap<String, BusEntry>,
}

impl Directory {
    /// The directory of `plant`. A register's name is taken only where it means that
    /// register for a write on its drive (as `vfd write` finds it), so a request resolved
    /// here reaches the register a lookup by name would.
    pub fn new(plant: &Plant) -> Directory {
        let mut buses = HashMap::new();
        for (b, bus) in plant.buses.iter().enumerate() {
            let mut stations = HashMap::new();
            for (s, station) in bus.stations.iter().enumerate() {
                let mut allowed = HashMap::new();
                for (a, entry) in station.writes.iter().enumerate() {
                    let register = entry.register;
                    let names = [register.code, register.id]
                        .into_iter()
                        .chain(register.aliases.iter().copied());
                    for name in names {
                        let means = crate::lookup::register_for(
                            station.drive,
                            name,
                            true,
                            &station.drive_name,
                        );
                        if means
                            .is_ok_and(|found| crate::write_check::same_register(found, register))
                        {
                            allowed.entry(name.to_owned()).or_insert(a);
                        }
                    }
                }
                stations.insert(station.name.clone(), StationEntry { index: s, allowed });
            }
            buses.insert(bus.name.clone(), BusEntry { index: b, stations });
        }
        Directory { buses }
    }

    /// Where a request to `register` of `drive` on `bus` goes; `None`: no bus of that name.
    pub fn target(&self, bus: &str, drive: &str, register: &str) -> Option<Target> {
        let entry = self.buses.get(bus)?;
        let station = entry.stations.get(drive);
        Some(Target {
            bus: entry.index,
            station: station.map(|s| s.index),
            allowed: station.and_then(|s| s.allowed.get(register).copied()),
        })
    }

    /// The buses' names, sorted.
    pub fn bus_names(&self) -> Vec<&str> {
        let mut names: Vec<&str> = self.buses.keys().map(String::as_str).collect();
        names.sort_unstable();
        names
    }
}
