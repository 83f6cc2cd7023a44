//! From the plant file as written to the checked [`Plant`]: every bus and drive resolved
//! and every check run, each problem collected (none stops the others), consequences of
//! one mistake left out.

use super::file::PlantFile;
use super::model::{Bus, Plant, Station};
use super::problems::Problems;
use super::station::Placed;
use super::unique::Keyed;
use super::{framing, line, line_load, names, registers, station, unique};
use std::path::Path;

/// Resolves and checks `file`, read from `problems.source`; drive files are found from
/// `dir`, the plant file's folder.
pub fn plant(file: &PlantFile, dir: &Path, problems: &mut Problems<'_>) -> Plant {
    if file.buses.is_empty() {
        problems.error(
            "buses",
            "the plant has no buses",
            "list the serial lines under `buses:`, each with its `port` and `drives`",
        );
    }
    let mut buses = Vec::new();
    for (b, entry) in file.buses.iter().enumerate() {
        let path = format!("buses[{b}]");
        if let Some((message, hint)) = names::problem(&entry.name) {
            problems.error(&format!("{path}.name"), message, hint);
        }
        line::port(entry, &path, problems);
        if entry.drives.is_empty() {
            problems.warning(
                &path,
                format!("bus `{}` has no drives", entry.name),
                "list the drives on it under `drives:`, or remove the bus",
            );
        }
        let alone = entry.drives.len() == 1;
        let mut placed: Vec<Placed> = Vec::new();
        let mut stations = Vec::new();
        for (d, drive) in entry.drives.iter().enumerate() {
            let at = format!("{path}.drives[{d}]");
            if let Some((message, hint)) = names::problem(&drive.name) {
                problems.error(&format!("{at}.name"), message, hint);
            }
            let Some(head) = station::resolve(drive, &at, dir, alone, problems) else {
                continue;
            };
            let polls = registers::polls(head.drive, &drive.poll, &at, problems);
            let writes = registers::writes(&head, &drive.write, &at, problems);
            stations.push(Station {
                name: drive.name.clone(),
                drive: head.drive,
                drive_name: problems.catalogue.name_for(head.drive),
                protocol: head.protocol,
                address: head.address,
                port: head.port,
                polls,
                writes,
            });
            placed.push(Placed {
                path: at,
                name: drive.name.clone(),
                head,
                protocol_named: drive.protocol.is_some(),
            });
        }
        let names: Vec<Keyed<'_>> = entry
            .drives
            .iter()
            .enumerate()
            .map(|(d, drive)| Keyed {
                path: format!("{path}.drives[{d}].name"),
                key: &drive.name,
            })
            .collect();
        unique::check(
            "drive name",
            &names,
            "names a drive's topics: give each drive on the bus its own",
            problems,
        );
        let addresses: Vec<String> = entry
            .drives
            .iter()
            .map(|drive| drive.station.map(|s| s.to_string()).unwrap_or_default())
            .collect();
        let stations_keyed: Vec<Keyed<'_>> = entry
            .drives
            .iter()
            .enumerate()
            .filter(|(_, drive)| drive.station.is_some())
            .map(|(d, _)| Keyed {
                path: format!("{path}.drives[{d}].station"),
                key: &addresses[d],
            })
            .collect();
        unique::check(
            "station",
            &stations_keyed,
            "two drives at one address answer together and garble each other's replies: set each drive to its own station address",
            problems,
        );
        framing::check(&entry.name, &placed, problems);
        let line = line::line(entry, &path, &placed, problems);
        line_load::check(
            &path,
            &entry.name,
            &stations,
            &line.settings,
            line.min_gap,
            problems,
        );
        buses.push(Bus {
            name: entry.name.clone(),
            port: entry.port.trim().to_owned(),
            settings: line.settings,
            timeout: line.timeout,
            min_gap: line.min_gap,
            host_latency: line.host_latency,
            retries: line.retries,
            offline_after: line.offline_after,
            backoff_first: line.backoff_first,
            backoff_cap: line.backoff_cap,
            stations,
        });
    }
    let bus_names: Vec<Keyed<'_>> = file
        .buses
        .iter()
        .enumerate()
        .map(|(b, bus)| Keyed {
            path: format!("buses[{b}].name"),
            key: &bus.name,
        })
        .collect();
    unique::check(
        "bus name",
        &bus_names,
        "names the bus's topics: give each bus its own",
        problems,
    );
    let ports: Vec<String> = file
        .buses
        .iter()
        .map(|bus| bus.port.trim().to_owned())
        .collect();
    let bus_ports: Vec<Keyed<'_>> = ports
        .iter()
        .enumerate()
        .filter(|(_, port)| !port.is_empty())
        .map(|(b, port)| Keyed {
            path: format!("buses[{b}].port"),
            key: port,
        })
        .collect();
    unique::check(
        "port",
        &bus_ports,
        "one port is one bus: list all the drives on that line under one bus",
        problems,
    );
    Plant {
        path: problems.source.path.clone(),
        buses,
        warnings: Default::default(),
    }
}
