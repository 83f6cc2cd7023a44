//! The generator's commands: `vfd generate` (refresh or check the committed reference
//! pages, schema and key tables; dump a drive's IR), `vfd check` (validate drive files) and
//! `vfd registers` (a drive's registers, one line each).

use crate::out::say;
use std::path::{Path, PathBuf};
use vfd_bus::Catalogue;
use vfd_runtime::{DriveInfo, Space};

/// The workspace root: `--root`, or the nearest folder upwards holding `drives/` and `generated-docs/`.
pub fn workspace_root(explicit: Option<&str>) -> Result<PathBuf, String> {
    if let Some(root) = explicit {
        return Ok(PathBuf::from(root));
    }
    let start =
        std::env::current_dir().map_err(|e| format!("cannot read the current folder: {e}"))?;
    start
        .ancestors()
        .find(|dir| dir.join("drives").is_dir() && dir.join("generated-docs").is_dir())
        .map(Path::to_owned)
        .ok_or_else(|| "run this inside the repository (no folder above holds drives/ and generated-docs/), or pass --root DIR".to_owned())
}

/// `vfd generate`: refreshes (or with `check_only`, checks) the committed generated files;
/// with `dump_ir`, prints one drive's IR instead.
pub fn generate(
    check_only: bool,
    dump_ir: Option<Option<&str>>,
    root: Option<&str>,
) -> Result<(), String> {
    let root = workspace_root(root)?;
    let docs = root.join("generated-docs");
    // tests/tests/generated_docs.rs makes the same pages with the same options.
    let builder = vfd_codegen::Builder::new()
        .drives_in(root.join("drives"))
        .map_err(|e| e.to_string())?
        .display_root(&root)
        .regenerate_command("cargo run -p vfd-cli -- generate")
        .crate_path("vfd_drives")
        .manuals_location("shared/seeds");
    if dump_ir == Some(None) {
        return Err("--dump-ir needs a drive id, e.g. `vfd generate --dump-ir yd1000`".to_owned());
    }
    if let Some(Some(id)) = dump_ir {
        let generated = builder.generate_in_memory().map_err(|e| e.to_string())?;
        let drive = generated
            .drives
            .iter()
            .find(|d| d.ir.id == id)
            .ok_or_else(|| {
                let known: Vec<&str> = generated.drives.iter().map(|d| d.ir.id.as_str()).collect();
                format!(
                    "no drive `{id}` in {}; described drives: {}",
                    root.join("drives").display(),
                    known.join(", ")
                )
            })?;
        say!("{}", drive.ir.to_yaml().trim_end());
        return Ok(());
    }
    // Only this command writes generated-docs/ (builds never do), so what it reports as
    // changed is what it changed.
    let (generated, changed) = if check_only {
        let generated = builder.generate_in_memory().map_err(|e| e.to_string())?;
        let mut pages: Vec<(String, &str)> = generated
            .drives
            .iter()
            .map(|d| (format!("{}.md", d.ir.id), d.markdown.as_str()))
            .collect();
        pages.push(("README.md".to_owned(), &generated.index));
        let stale: Vec<String> = pages
            .iter()
            .filter(|(name, text)| {
                std::fs::read_to_string(docs.join(name)).ok().as_deref() != Some(*text)
            })
            .map(|(name, _)| name.clone())
            .collect();
        (generated, stale)
    } else {
        let generated = builder
            .docs_dir(&docs)
            .generate()
            .map_err(|e| e.to_string())?;
        let written = generated
            .written
            .iter()
            .map(|path| {
                path.strip_prefix(&docs)
                    .unwrap_or(path)
                    .display()
                    .to_string()
            })
            .collect();
        (generated, written)
    };
    // The description files' JSON Schema and the README's key tables, made from the model.
    let described = description_format_files(&root)?;
    let described_changed: Vec<String> = described
        .iter()
        .filter(|(path, text)| std::fs::read_to_string(path).ok().as_deref() != Some(text))
        .map(|(path, text)| {
            if !check_only {
                vfd_codegen::write_if_changed(path, text).map_err(|e| e.to_string())?;
            }
            Ok(path
                .strip_prefix(&root)
                .unwrap_or(path)
                .display()
                .to_string())
        })
        .collect::<Result<_, String>>()?;
    let pages = generated.drives.len() + 1;
    say!(
        "{:<8} {:<28} {:>9} {:>9} {:>6} {:>8} {:>7}  protocols",
        "drive",
        "model",
        "registers",
        "bitfields",
        "codes",
        "examples",
        "errata"
    );
    for drive in &generated.drives {
        let ir = &drive.ir;
        let errata = ir
            .examples
            .iter()
            .flat_map(|e| [&e.request, &e.reply])
            .filter(|f| f.as_ref().is_some_and(|f| f.printed.is_some()))
            .count();
        let protocols: Vec<&str> = ir.protocols.iter().map(|p| p.id.as_str()).collect();
        say!(
            "{:<8} {:<28} {:>9} {:>9} {:>6} {:>8} {:>7}  {}",
            ir.id,
            format!("{} {}", ir.vendor, ir.model),
            ir.registers.len(),
            ir.bitfields.len(),
            ir.code_tables.len() + 1,
            ir.examples.len(),
            errata + ir.manual_errata.len(),
            protocols.join(", ")
        );
        say!(
            "         Rust: {} lines of generated code",
            drive.rust.lines().count()
        );
    }
    // Warnings do not stop generation; they are printed after the summary, as `vfd check`
    // prints them after the errors.
    for drive in generated.drives.iter().filter(|d| !d.warnings.is_empty()) {
        say!("{}", drive.warnings);
    }
    match (check_only, described_changed.is_empty()) {
        (_, true) => {
            say!("drives/schema/, the key tables in drives/README.md and plants/plant.schema.json are up to date")
        }
        (false, false) => say!("changed: {}", described_changed.join(", ")),
        (true, false) => {
            return Err(format!(
                "stale: {}; run `cargo run -p vfd-cli -- generate`",
                described_changed.join(", ")
            ))
        }
    }
    match (check_only, changed.is_empty()) {
        (_, true) => say!("generated-docs/ is up to date ({pages} pages)"),
        (false, false) => say!(
            "changed in generated-docs/: {} (of {pages} pages)",
            changed.join(", ")
        ),
        (true, false) => {
            return Err(format!(
                "stale pages in generated-docs/: {}; run `cargo run -p vfd-cli -- generate`",
                changed.join(", ")
            ))
        }
    }
    Ok(())
}

/// `drives/schema/*.json` and `drives/README.md` with its key tables, as they should be
/// (tests/tests/schema.rs checks the same files), and the plant files' schema.
fn description_format_files(root: &Path) -> Result<Vec<(PathBuf, String)>, String> {
    let drives = root.join("drives");
    let schemas = vfd_codegen::schemas();
    let mut files: Vec<(PathBuf, String)> = schemas
        .files()
        .iter()
        .map(|(path, text)| (drives.join(path), (*text).to_owned()))
        .collect();
    let readme_path = drives.join("README.md");
    let readme = std::fs::read_to_string(&readme_path)
        .map_err(|e| format!("{}: {e}", readme_path.display()))?;
    let readme = vfd_codegen::with_key_tables(&readme).ok_or_else(|| {
        format!(
            "{} lacks the key-table markers `{}` and `{}`",
            readme_path.display(),
            vfd_codegen::KEY_TABLES_BEGIN,
            vfd_codegen::KEY_TABLES_END
        )
    })?;
    files.push((readme_path, readme));
    files.push((
        root.join(vfd_bus::plant::schema::PATH),
        vfd_bus::plant::schema::text(),
    ));
    Ok(files)
}

/// `vfd check`: validates drive files and prints every problem, errors first, then
/// warnings; with `deny_warnings` a file with warnings fails as one with errors does.
/// Protocol files are found as every command finds them ([`Catalogue::compile`]).
pub fn check(catalogue: &Catalogue, files: &[String], deny_warnings: bool) -> Result<(), String> {
    let mut failed = 0;
    for file in files {
        let compiled = catalogue.compile(Path::new(file));
        let warnings = compiled.warnings.items.len();
        let valid = compiled.drive.is_ok();
        // The run-time values the rehearsal built (not built again).
        let live = compiled.drive_info().filter(|_| valid);
        match compiled.drive {
            Ok(drive) => say!(
                "{file}: ok ({} registers, {} examples{})",
                drive.registers.len(),
                drive.examples.len(),
                match warnings {
                    0 => String::new(),
                    1 => ", 1 warning".to_owned(),
                    n => format!(", {n} warnings"),
                }
            ),
            Err(diagnostics) => {
                failed += 1;
                say!("{diagnostics}");
                if compiled.usable.is_some() {
                    say!(
                        "{file}: the problems above do not concern the wire: `vfd read`, `write`, `decode` and `sim` use the file without the parts that have them, after a warning"
                    );
                }
            }
        }
        if let Some(drive) = live {
            say!("{file}: {}", super::describe::control_line(drive));
        }
        if warnings > 0 {
            say!("{}", compiled.warnings);
            if deny_warnings && valid {
                failed += 1;
            }
        }
    }
    match (failed, deny_warnings) {
        (0, _) => Ok(()),
        (failed, false) => Err(format!("{failed} of {} file(s) have problems", files.len())),
        (failed, true) => Err(format!(
            "{failed} of {} file(s) have problems or warnings (--deny-warnings)",
            files.len()
        )),
    }
}

/// `vfd registers`: one line per register.
pub fn registers(drive: &DriveInfo) -> Result<(), String> {
    say!(
        "{} {} ({}): {} registers",
        drive.vendor,
        drive.model,
        drive.name_zh,
        drive.registers.len()
    );
    for r in drive.registers {
        let unit = r.unit_symbol();
        let address = if r.space == Space::Coil {
            format!("coil {}", r.address)
        } else if r.code.parse::<u16>().ok() == Some(r.address) {
            r.address.to_string()
        } else {
            format!("{:04X}", r.address)
        };
        say!(
            "  {:<8} {:<6} {:<44} {:<12} {:<10} {}{}{}",
            address,
            r.code,
            r.name,
            r.name_zh,
            r.access.as_str(),
            r.data_type.as_str(),
            if unit.is_empty() {
                String::new()
            } else {
                format!(", {} ({} {unit} steps)", unit, r.scale)
            },
            if r.ram_only { ", RAM only" } else { "" }
        );
    }
    Ok(())
}
