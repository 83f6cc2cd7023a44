//! Plant files: the buses, drives, poll lists and write allow-lists `vfd serve` runs,
//! read with file:line:column diagnostics as drive files are, checked, and resolved into
//! a [`Plant`]. `vfd serve --check PLANT` prints what [`load`] finds. The format is in
//! docs/plant.md; its JSON Schema is `plants/plant.schema.json` ([`schema`]).

pub mod file;
pub mod framing;
pub mod interval;
mod line;
mod line_load;
pub mod model;
mod names;
mod problems;
mod registers;
mod resolve;
pub mod schema;
mod station;
mod unique;

pub use model::{Bus, Plant, Station};

use crate::Catalogue;
use problems::Problems;
use std::path::{Path, PathBuf};
use vfd_codegen::yaml::SourceFile;
use vfd_codegen::Diagnostics;

/// Reads and checks the plant file at `path`. On success the plant carries its warnings
/// ([`Plant::warnings`]); on failure every problem, the errors first, then the warnings.
pub fn load(path: &Path, catalogue: &Catalogue) -> Result<Plant, Diagnostics> {
    match SourceFile::read(path) {
        Ok(source) => load_source(&source, catalogue),
        Err(problem) => Err(Diagnostics {
            items: vec![problem],
        }),
    }
}

/// Like [`load`], for a plant file's text already in memory (`path` names it in messages,
/// and relative drive file paths start at its folder).
#[cfg_attr(not(all(unix, feature = "pty")), allow(dead_code))] // the plant demo's
pub fn load_str(text: &str, path: &Path, catalogue: &Catalogue) -> Result<Plant, Diagnostics> {
    load_source(&SourceFile::from_text(path, text.to_owned()), catalogue)
}

/// Whether `path` is `element` or lies under it.
fn within(path: &str, element: &str) -> bool {
    path.strip_prefix(element)
        .is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
}

fn load_source(source: &SourceFile, catalogue: &Catalogue) -> Result<Plant, Diagnostics> {
    let read = source.read_model::<file::PlantFile>();
    let mut problems = Problems {
        source,
        found: Diagnostics {
            items: read.problems,
        },
        catalogue,
    };
    let keep = problems.found.items.len();
    let dir = source
        .path
        .parent()
        .map(Path::to_owned)
        .unwrap_or_else(|| PathBuf::from("."));
    let plant = read
        .value
        .map(|file| resolve::plant(&file, &dir, &mut problems));
    let mut found = problems.found;
    // A value the reader refused holds a placeholder: what the checks then say at or under
    // it is a consequence, not a further mistake. (Narrower than the drive files' rule,
    // which leaves out the whole sequence item: a wrong `station` must not hide a wrong
    // interval of the same drive.)
    let refused: Vec<String> = found.items[..keep]
        .iter()
        .map(|item| item.path.clone())
        .collect();
    let mut index = 0;
    found.items.retain(|item| {
        index += 1;
        index <= keep || !refused.iter().any(|at| within(&item.path, at))
    });
    found.attach_sources(|path| (path == source.path).then_some(source.text.as_str()));
    // The reader's hints send people to the drive files' reference.
    for item in &mut found.items {
        if let Some(hint) = &mut item.hint {
            *hint = hint.replace("drives/README.md", "docs/plant.md");
        }
    }
    let warnings = found.take_warnings();
    match plant {
        Some(plant) if found.is_empty() => Ok(Plant { warnings, ..plant }),
        _ => {
            found.items.extend(warnings.items);
            if found.is_empty() {
                found.push(source.error("", "the plant file could not be read"));
            }
            Err(found)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    const PLANT: &str = "buses:
  - name: line1
    port: /dev/pts/9
    drives:
      - name: pump1
        drive: fc51
        protocol: modbus
        poll:
          - { every: 250ms, registers: [MAV, STW] }
        write: [REF]
";

    #[test]
    fn a_plant_in_memory_resolves_with_the_defaults() {
        let plant = load_str(PLANT, Path::new("demo.yaml"), &Catalogue::new()).unwrap();
        assert!(plant.warnings.is_empty(), "{}", plant.warnings);
        let bus = &plant.buses[0];
        assert_eq!(bus.port, "/dev/pts/9");
        assert_eq!(bus.settings, bus.stations[0].drive.serial.default);
        assert_eq!(
            (
                bus.retries,
                bus.offline_after,
                bus.backoff_first,
                bus.backoff_cap
            ),
            (0, 3, Duration::from_secs(1), Duration::from_secs(60))
        );
        let station = &bus.stations[0];
        assert_eq!(station.protocol.id.as_ref(), "modbus");
        assert_eq!(station.address, station.protocol.default_address());
        assert_eq!(station.polls.len(), 2);
        assert_eq!(station.polls[0].every, Duration::from_millis(250));
        assert_eq!(station.writes[0].register.code, "REF");
        assert!(!station.writes[0].persistent);
    }

    #[test]
    fn every_problem_is_collected_with_its_position() {
        let text = PLANT
            .replace("drive: fc51", "drive: fc51\n        station: 999")
            .replace("250ms", "0ms")
            .replace("[REF]", "[STW]");
        let problems = load_str(&text, Path::new("demo.yaml"), &Catalogue::new()).unwrap_err();
        let lines: Vec<String> = problems.items.iter().map(|d| d.location()).collect();
        assert_eq!(lines.len(), 3, "{problems}");
        assert!(
            lines.iter().all(|l| l.starts_with("demo.yaml:")),
            "{lines:?}"
        );
    }
}
