//! `vfd serve --check PLANT`: the plant file's problems as `vfd check` prints a drive
//! file's (errors, then warnings, each at file:line:column with a hint; exit status 1 on
//! errors), or a summary of what the service would poll and allow. Nothing is opened. The
//! exit status is the check's whatever becomes of the output: a reader that stops early
//! (`vfd serve --check PLANT | head -1`) changes nothing.

use crate::Failure;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use vfd_bus::plant::interval;
use vfd_bus::plant::{Bus, Plant};
use vfd_bus::Catalogue;

/// Checks the plant file at `path` and prints the outcome.
pub fn run(catalogue: &Catalogue, path: &Path) -> Result<(), Failure> {
    let mut text = String::new();
    let outcome = match vfd_bus::plant::load(path, catalogue) {
        Ok(plant) => {
            summary(&plant, &mut text);
            if !plant.warnings.is_empty() {
                let _ = writeln!(text, "{}", plant.warnings);
            }
            Ok(())
        }
        Err(mut diagnostics) => {
            let warnings = diagnostics.take_warnings();
            let errors = diagnostics.items.len();
            let _ = writeln!(text, "{diagnostics}");
            if !warnings.is_empty() {
                let _ = writeln!(text, "{warnings}");
            }
            Err(Failure::new(format!(
                "{} has {errors} problem{}",
                path.display(),
                if errors == 1 { "" } else { "s" }
            ))
            .hint("fix them and run `vfd serve --check` again; docs/plant.md describes every key"))
        }
    };
    print(&text);
    outcome
}

/// Writes `text` on standard output. A closed pipe ends the writing, not the program: the
/// exit status stays the check's. Another write error is said on standard error.
fn print(text: &str) {
    let mut out = std::io::stdout().lock();
    let written = out.write_all(text.as_bytes()).and_then(|()| out.flush());
    match written {
        Err(error) if error.kind() != std::io::ErrorKind::BrokenPipe => {
            let _ = writeln!(std::io::stderr(), "vfd: cannot write the output: {error}");
        }
        _ => {}
    }
}

/// Loads the plant file for `vfd serve`: its warnings, or every problem, on standard error
/// as `--check` prints them; a failure when it has errors (nothing is opened then).
pub fn load_for_service(catalogue: &Catalogue, path: &Path) -> Result<Plant, Failure> {
    match vfd_bus::plant::load(path, catalogue) {
        Ok(plant) => {
            if !plant.warnings.is_empty() {
                let _ = writeln!(std::io::stderr(), "{}", plant.warnings);
            }
            Ok(plant)
        }
        Err(diagnostics) => {
            let errors = diagnostics
                .items
                .iter()
                .filter(|d| d.severity == vfd_codegen::Severity::Error)
                .count();
            let _ = writeln!(std::io::stderr(), "{diagnostics}");
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
fn summary(plant: &Plant, text: &mut String) {
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
    let _ = writeln!(
        text,
        "{}: ok ({}, {}, {} polled at {reads:.1} reads/s, {} writable)",
        plant.path.display(),
        plural(plant.buses.len(), "bus", "buses"),
        plural(stations, "drive", "drives"),
        plural(polled, "register", "registers"),
        plural(writable, "register", "registers"),
    );
    for bus in &plant.buses {
        let s = &bus.settings;
        let _ = writeln!(
            text,
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
            let _ = writeln!(
                text,
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
                let _ = writeln!(text, "      poll {}", polls.join("; "));
            }
            let _ = writeln!(
                text,
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
