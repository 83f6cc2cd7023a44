//! Stage 2: reads a drive file and the protocol files it refers to, parsed into the
//! format's types ([`crate::parse::model`]), a protocol file `based_on` another merged with
//! its base ([`based_on`]), and gives every register its number ([`register_numbers`]:
//! those without an `address` take the one their place on a page or their wire numbers
//! give). Nothing else is checked, and nothing is lowered, here.

use crate::diagnostics::Diagnostics;
use crate::parse::model::{DriveFile, ProtocolFile};
use crate::parse::SourceFile;
use std::path::{Path, PathBuf};

pub(crate) mod based_on;
mod register_numbers;
mod shelf;
use based_on::Inherited;
pub(crate) use shelf::Shelf;
pub use shelf::Shipped;

/// A protocol file as one drive refers to it, parsed but not yet lowered.
#[derive(Debug, Clone)]
pub(crate) struct ProtocolSource {
    /// Index of the reference in the drive file's `protocols:` list.
    pub reference: usize,
    /// The protocol file.
    pub source: SourceFile,
    /// Its parsed content, with its base's merged in (`based_on`).
    pub file: ProtocolFile,
    /// What came from the base, when the file is `based_on` another.
    pub inherited: Option<Inherited>,
}

/// A drive file and the protocol files it refers to, parsed.
#[derive(Debug, Clone)]
pub(crate) struct LoadedDrive {
    /// The drive file.
    pub source: SourceFile,
    /// Its parsed content.
    pub model: DriveFile,
    /// The protocol files that could be read and parsed, in the drive's order.
    pub protocol_files: Vec<ProtocolSource>,
    /// Every file read, for quoting source lines in diagnostics.
    pub sources: Vec<SourceFile>,
    /// Elements (file, YAML path) holding a placeholder for a value in error.
    pub incomplete: Vec<(PathBuf, String)>,
}

/// Where protocol files are looked up: `<dir>/<uses>.yaml`.
pub fn default_protocols_dir(drive_path: &Path) -> PathBuf {
    drive_path
        .parent()
        .unwrap_or(Path::new("."))
        .join("protocols")
}

/// Parses a drive file and the protocol files it names, looked up in `protocols_dir`
/// (default: `protocols/` next to the drive file), then among `shipped`. Problems go to
/// `out`; `None` when the drive file itself cannot be parsed.
pub(crate) fn load(
    source: SourceFile,
    protocols_dir: Option<&Path>,
    shipped: Shipped,
    out: &mut Diagnostics,
) -> Option<LoadedDrive> {
    let shelf = Shelf {
        dir: protocols_dir
            .map(Path::to_owned)
            .unwrap_or_else(|| default_protocols_dir(&source.path)),
        shipped,
    };
    let read = source.read_model::<DriveFile>();
    read.problems
        .into_iter()
        .for_each(|problem| out.push(problem));
    let mut incomplete: Vec<(PathBuf, String)> = read
        .incomplete
        .into_iter()
        .map(|path| (source.path.clone(), path))
        .collect();
    let Some(mut model) = read.value else {
        out.attach_sources(|path| (path == source.path).then_some(source.text.as_str()));
        return None;
    };
    register_numbers::resolve(&source, &mut model, &mut incomplete, out);
    let mut sources = vec![source.clone()];
    let mut protocol_files = Vec::new();
    for (index, reference) in model.protocols.iter().enumerate() {
        let protocol_source = match shelf.read(&reference.uses) {
            Ok(protocol_source) => protocol_source,
            Err(path) => {
                out.push(
                    source
                        .error(
                            &format!("protocols[{index}].uses"),
                            format!(
                                "no protocol description `{}` ({} does not exist)",
                                reference.uses,
                                path.display()
                            ),
                        )
                        .hint(format!(
                            "protocol files are looked up in {}; available: {}",
                            shelf.describe(),
                            shelf.available()
                        )),
                );
                continue;
            }
        };
        if let Some(warning) = shelf.differs_from_shipped(&reference.uses, &protocol_source) {
            out.push(
                source
                    .warning(&format!("protocols[{index}].uses"), warning)
                    .hint(format!(
                        "an older copy is the likely cause: delete {} to use the shipped file; a file that changes the family on purpose takes an id of its own (with `based_on: {}` it keeps the shipped layouts)",
                        protocol_source.path.display(),
                        reference.uses
                    )),
            );
        }
        sources.push(protocol_source.clone());
        let read = protocol_source.read_model::<ProtocolFile>();
        read.problems
            .into_iter()
            .for_each(|problem| out.push(problem));
        incomplete.extend(
            read.incomplete
                .into_iter()
                .map(|path| (protocol_source.path.clone(), path)),
        );
        let Some(file) = read.value else {
            continue;
        };
        if let Some(merged) = based_on::merge(
            &protocol_source,
            file,
            &shelf,
            out,
            &mut sources,
            &mut incomplete,
        ) {
            protocol_files.push(ProtocolSource {
                reference: index,
                source: protocol_source,
                file: merged.file,
                inherited: merged.inherited,
            });
        }
    }
    Some(LoadedDrive {
        source,
        model,
        protocol_files,
        sources,
        incomplete,
    })
}
