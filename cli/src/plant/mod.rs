//! Plant files: the buses, drives, poll lists and write allow-lists `vfd serve` runs,
//! read with file:line:column diagnostics as drive files are, checked, and resolved into
//! a [`Plant`]. `vfd serve --check PLANT` prints what [`load`] finds. The format is in
//! docs/plant.md; its JSON Schema is `plants/plant.schema.json` ([`schema`]).

pub mod check;
pub mod file;
mod framing;
pub mod interval;
mod line;
pub mod model;
mod names;
mod problems;
mod registers;
mod resolve;
pub mod schema;
mod station;
mod unique;

pub use model::{Bus, Plant, Station};

use problems::Problems;
use std::path::{Path, PathBuf};
use vfd_codegen::yaml::SourceFile;
use vfd_codegen::Diagnostics;

/// Reads and checks the plant file at `path`. On success the plant carries its warnings
/// ([`Plant::warnings`]); on failure every problem, the errors first, then the warnings.
pub fn load(path: &Path) -> Result<Plant, Diagnostics> {
    match SourceFile::read(path) {
        Ok(source) => load_source(&source),
        Err(problem) => Err(Diagnostics {
            items: vec![problem],
        }),
    }
}

/// Like [`load`], for a plant file's text already in memory (`path` names it in messages,
/// and relative drive file paths start at its folder).
pub fn load_str(text: &str, path: &Path) -> Result<Plant, Diagnostics> {
    load_source(&SourceFile::from_text(path, text.to_owned()))
}

fn load_source(source: &SourceFile) -> Result<Plant, Diagnostics> {
    let read = source.read_model::<file::PlantFile>();
    let mut problems = Problems {
        source,
        found: Diagnostics {
            items: read.problems,
        },
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
    let incomplete: Vec<(PathBuf, String)> = read
        .incomplete
        .into_iter()
        .map(|element| (source.path.clone(), element))
        .collect();
    found.leave_out_consequences(keep, &incomplete);
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
