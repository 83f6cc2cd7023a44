//! `vfd serve --check PLANT`: the plant file's problems as `vfd check` prints a drive
//! file's (errors, then warnings, each at file:line:column with a hint; exit status 1 on
//! errors), or a summary of what the service would poll and allow. Nothing is opened.

use super::interval;
use super::model::{Bus, Plant};
use crate::out::say;
use crate::Failure;
use std::path::Path;

/// Checks the plant file at `path` and prints the outcome.
pub fn run(path: &Path) -> Result<(), Failure> {
    match super::load(path) {
        Ok(plant) => {
            summary(&plant);
            if !plant.warnings.is_empty() {
                say!("{}", plant.warnings);
            }
            Ok(())
        }
        Err(mut diagnostics) => {
            let warnings = diagnostics.take_warnings();
            let errors = diagnostics.items.len();
            say!("{diagnostics}");
            if !warnings.is_empty() {
                say!("{warnings}");
            }
            Err(Failure::new(format!(
                "{} has {errors} problem{}",
                path.display(),
                if errors == 1 { "" } else { "s" }
            ))
            .hint("fix them and run `vfd serve --check` again; docs/plant.md describes every key"))
        }
    }
}

/// Loads the plant file for `vfd serve`: its warnings, or every problem, on standard error
/// as `--check` prints them; a failure when it has errors (nothing is opened then).
pub fn load_for_service(path: &Path) -> Result<Plant, Failure> {
    match super::load(path) {
        Ok(plant) => {
            if !plant.warnings.is_empty() {
                eprintln!("{}", plant.warnings);
            }
            Ok(plant)
        }
        Err(diagnostics) => {
            let errors = diagnostics
                .items
                .iter()
                .filter(|d| d.severity == vfd_codegen::Severity::Error)
                .count();
            eprintln!("{diagnostics}");
            Err(Failure::new(format!(
                "{} has {errors} problem{}; nothing was opened",
                path.display(),
                if errors == 1 { "" } else { "s" }
            ))
            .hint("`vfd serve --check PLANT` checks it; docs/plant.md describes every key"))
        }
    }
}

/// Reads per second a poll list asks for.
fn rate(bus: &Bus) -> f64 {
    bus.stations
        .iter()
        .flat_map(|s| &s.polls)
        .fold(0.0, |sum, p| sum + 1.0 / p.every.as_secs_f64())
}

/// The plant in a few lines: totals, then each bus and drive.
fn summary(plant: &Plant) {
    let stations: usize = plant.buses.iter().map(|b| b.stations.len()).sum();
    let polled: usize = plant
        .buses
        .iter()
        .flat_map(|b| &b.stations)
        .map(|s| s.polls.len())
        .sum();
    let writable: usize = plant
        .buses
        .iter()
        .flat_map(|b| &b.stations)
        .map(|s| s.writes.len())
        .sum();
    let reads: f64 = plant.buses.iter().map(rate).fold(0.0, |sum, r| sum + r);
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    say!(
        "{}: ok ({}, {}, {} polled at {reads:.1} reads/s, {} writable)",
        plant.path.display(),
        plural(plant.buses.len(), "bus", "buses"),
        plural(stations, "drive", "drives"),
        plural(polled, "register", "registers"),
        plural(writable, "register", "registers"),
    );
    for bus in &plant.buses {
        let s = &bus.settings;
        say!(
            "  bus {}: {} at {} baud {}{}{}, {}, {reads:.1} reads/s",
            bus.name,
            bus.port,
            s.baud,
            s.data_bits,
            s.parity
                .as_str()
                .chars()
                .next()
                .unwrap_or('n')
                .to_ascii_uppercase(),
            s.stop_bits,
            plural(bus.stations.len(), "drive", "drives"),
            reads = rate(bus),
        );
        for station in &bus.stations {
            let mut groups: Vec<(std::time::Duration, Vec<&str>)> = Vec::new();
            for poll in &station.polls {
                match groups.iter_mut().find(|(every, _)| *every == poll.every) {
                    Some((_, codes)) => codes.push(poll.register.code),
                    None => groups.push((poll.every, vec![poll.register.code])),
                }
            }
            let polls: Vec<String> = groups
                .iter()
                .map(|(every, codes)| {
                    format!("every {}: {}", interval::show(*every), codes.join(" "))
                })
                .collect();
            let writes: Vec<String> = station
                .writes
                .iter()
                .map(|w| {
                    format!(
                        "{}{}",
                        w.register.code,
                        if w.persistent { " (persistent)" } else { "" }
                    )
                })
                .collect();
            say!(
                "    {} = {} {}{}{}",
                station.name,
                station.drive.id,
                station.protocol.id,
                station
                    .address
                    .map(|a| format!(" station {a}"))
                    .unwrap_or_default(),
                station
                    .port
                    .map(|p| format!(" ({} port)", p.id))
                    .unwrap_or_default(),
            );
            if !polls.is_empty() {
                say!("      poll {}", polls.join("; "));
            }
            say!(
                "      write {}",
                if writes.is_empty() {
                    "nothing".to_owned()
                } else {
                    writes.join(", ")
                }
            );
        }
    }
}
