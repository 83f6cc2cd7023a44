//! Reads a drive file and the protocol files it refers to, then validates the lot:
//! the front half of the pipeline, ending in a description the IR can trust.

use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::model::{DriveFile, ProtocolFile};
use crate::parse::SourceFile;
use crate::{protocols, validate};
use std::path::{Path, PathBuf};
use vfd_runtime::Protocol;

/// A protocol as one drive uses it.
#[derive(Debug, Clone)]
pub struct LoadedProtocol {
    /// Id within the drive (`ascii`).
    pub id: String,
    /// Protocol file id (`toshiba-ascii`).
    pub uses: String,
    /// Manual section describing it.
    pub source_section: String,
    /// The protocol file.
    pub source: SourceFile,
    /// Its parsed content.
    pub file: ProtocolFile,
    /// The runtime protocol built from it.
    pub runtime: Protocol,
}

/// A drive file with its protocols, parsed and validated.
#[derive(Debug, Clone)]
pub struct LoadedDrive {
    /// The drive file.
    pub source: SourceFile,
    /// Its parsed content.
    pub model: DriveFile,
    /// Its protocols, in file order.
    pub protocols: Vec<LoadedProtocol>,
}

/// Where protocol files are looked up: `<dir>/<uses>.yaml`.
pub fn default_protocols_dir(drive_path: &Path) -> PathBuf {
    drive_path
        .parent()
        .unwrap_or(Path::new("."))
        .join("protocols")
}

/// Loads and validates a drive file from disk.
pub fn load_drive(path: &Path, protocols_dir: Option<&Path>) -> Result<LoadedDrive, Diagnostics> {
    let source = SourceFile::read(path).map_err(single)?;
    load_source(source, protocols_dir)
}

/// Loads and validates a drive file already in memory.
pub fn load_source(
    source: SourceFile,
    protocols_dir: Option<&Path>,
) -> Result<LoadedDrive, Diagnostics> {
    let protocols_dir = protocols_dir
        .map(Path::to_owned)
        .unwrap_or_else(|| default_protocols_dir(&source.path));
    let mut diagnostics = Diagnostics::default();
    let mut texts: Vec<SourceFile> = vec![source.clone()];
    let result = (|| {
        let model: DriveFile = source.deserialize().map_err(|d| vec![d])?;
        let mut problems = Vec::new();
        let mut loaded = Vec::new();
        for (index, reference) in model.protocols.iter().enumerate() {
            let path = protocols_dir.join(format!("{}.yaml", reference.uses));
            let protocol_source = match SourceFile::read(&path) {
                Ok(protocol_source) => protocol_source,
                Err(_) => {
                    problems.push(
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
                                "protocol files live in {}; available: {}",
                                protocols_dir.display(),
                                available(&protocols_dir)
                            )),
                    );
                    continue;
                }
            };
            texts.push(protocol_source.clone());
            let file: ProtocolFile = match protocol_source.deserialize() {
                Ok(file) => file,
                Err(problem) => {
                    problems.push(problem);
                    continue;
                }
            };
            let reference_path = format!("protocols[{index}]");
            match protocols::build_protocol(
                reference,
                &reference_path,
                &file,
                &protocol_source,
                &source,
                &model,
            ) {
                Ok(runtime) => loaded.push(LoadedProtocol {
                    id: reference.id.clone(),
                    uses: reference.uses.clone(),
                    source_section: reference.source.clone(),
                    source: protocol_source,
                    file,
                    runtime,
                }),
                Err(mut more) => problems.append(&mut more),
            }
        }
        let drive = LoadedDrive {
            source: source.clone(),
            model,
            protocols: loaded,
        };
        problems.extend(validate::check(&drive));
        if problems.is_empty() {
            Ok(drive)
        } else {
            Err(problems)
        }
    })();
    match result {
        Ok(drive) => Ok(drive),
        Err(problems) => {
            for problem in problems {
                diagnostics.push(problem);
            }
            diagnostics.attach_sources(|path| {
                texts
                    .iter()
                    .find(|t| t.path == path)
                    .map(|t| t.text.clone())
            });
            Err(diagnostics)
        }
    }
}

fn single(diagnostic: Diagnostic) -> Diagnostics {
    Diagnostics {
        items: vec![diagnostic],
    }
}

fn available(dir: &Path) -> String {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .filter_map(|e| {
                    e.file_name()
                        .to_str()
                        .and_then(|n| n.strip_suffix(".yaml"))
                        .map(str::to_owned)
                })
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    if names.is_empty() {
        "none".to_owned()
    } else {
        names.join(", ")
    }
}
