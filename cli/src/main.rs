//! `vfd`: the command-line tool. Generates code and reference pages, checks drive files,
//! and encodes or decodes frames of the described drives by register name with units.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use vfd_runtime::meaning::{decode_meaning, Direction, FrameMeaning};
use vfd_runtime::protocol::code_label;
use vfd_runtime::units::{raw_to_scaled, scaled_to_raw};
use vfd_runtime::{
    Access, CommandKind, DataType, DriveInfo, Protocol, RegisterInfo, Request, Space,
};

/// Prints a line for people. A closed pipe (`vfd registers yd1000 | head`) ends the program
/// quietly, as for other command-line tools; another write error is reported.
macro_rules! say {
    ($($arg:tt)*) => {
        print_line(format_args!($($arg)*))
    };
}

fn print_line(line: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(error) = out.write_fmt(line).and_then(|()| out.write_all(b"\n")) {
        if error.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("cannot write the output: {error}");
        std::process::exit(1);
    }
}

const USAGE: &str = "\
vfd: tools for RS-485 frequency inverters described in drives/*.yaml

USAGE:
  vfd generate [--check] [--root DIR]      regenerate generated-docs/, drives/schema/ and the
                                           key tables in drives/README.md; print a summary
                                           (--check: only report stale pages, exit 1 if any)
  vfd generate --dump-ir DRIVE [--root DIR]
                                           print the generator's IR of one drive as YAML
  vfd check [--protocols DIR] FILE.yaml... validate drive files, print every problem
                                           (DIR: protocol files, default protocols/ next
                                           to each drive file)
  vfd registers DRIVE                      list a drive's registers
  vfd encode DRIVE PROTOCOL read REG [--address N]
  vfd encode DRIVE PROTOCOL write-ram REG VALUE [--address N]
  vfd encode DRIVE PROTOCOL write-persistent REG VALUE [--address N]
                                           print the request frame (REG: code like FA01 or FH,
                                           or id; VALUE in the register's unit, e.g. 60 or 60Hz)
  vfd decode DRIVE PROTOCOL FRAME          decode a captured request or reply
                                           (FRAME: hex \"2F 52 FD 00 7E\" or text \"(RFD00)\\r\")

Drives and the protocols each speaks: `vfd registers DRIVE` heads, or generated-docs/README.md.";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &[String]) -> Result<(), String> {
    let words: Vec<&str> = args.iter().map(String::as_str).collect();
    match words.as_slice() {
        ["generate", rest @ ..] => generate(rest),
        ["check", "--protocols", dir, files @ ..] if !files.is_empty() => {
            check(files, Some(Path::new(dir)))
        }
        ["check", files @ ..] if !files.is_empty() => check(files, None),
        ["registers", drive] => registers(find_drive(drive)?),
        ["encode", drive, protocol, rest @ ..] => encode(find_drive(drive)?, protocol, rest),
        ["decode", drive, protocol, frame] => decode(find_drive(drive)?, protocol, frame),
        ["--help" | "-h" | "help"] | [] => {
            say!("{USAGE}");
            Ok(())
        }
        _ => Err(format!(
            "unrecognised arguments: {}\n\n{USAGE}",
            args.join(" ")
        )),
    }
}

fn find_drive(id: &str) -> Result<&'static DriveInfo, String> {
    vfd_drives::drive(id).ok_or_else(|| {
        let known: Vec<&str> = vfd_drives::ALL_DRIVES.iter().map(|d| d.id).collect();
        format!(
            "unknown drive `{id}`; described drives: {}",
            known.join(", ")
        )
    })
}

fn find_protocol(drive: &DriveInfo, id: &str) -> Result<&'static Protocol, String> {
    drive.protocol(id).ok_or_else(|| {
        let known: Vec<&str> = drive.protocols.iter().map(|p| p.id.as_ref()).collect();
        format!(
            "drive {} has no protocol `{id}`; it speaks: {}",
            drive.id,
            known.join(", ")
        )
    })
}

fn find_register(drive: &DriveInfo, name: &str) -> Result<&'static RegisterInfo, String> {
    drive.register(name).ok_or_else(|| format!("drive {} has no register `{name}` (use a code such as FA01 or FH, or an id; `vfd registers {}` lists them)", drive.id, drive.id))
}

/// The workspace root: `--root`, or the nearest folder upwards holding `drives/` and `generated-docs/`.
fn workspace_root(explicit: Option<&str>) -> Result<PathBuf, String> {
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

fn generate(args: &[&str]) -> Result<(), String> {
    let check_only = args.contains(&"--check");
    let root_arg = args.windows(2).find(|w| w[0] == "--root").map(|w| w[1]);
    let root = workspace_root(root_arg)?;
    let docs = root.join("generated-docs");
    // tests/tests/generated_docs.rs makes the same pages with the same options.
    let builder = vfd_codegen::Builder::new()
        .drives_in(root.join("drives"))
        .map_err(|e| e.to_string())?
        .display_root(&root)
        .regenerate_command("cargo run -p vfd-cli -- generate")
        .crate_path("vfd_drives")
        .manuals_location("shared/seeds");
    if args.last() == Some(&"--dump-ir") {
        return Err("--dump-ir needs a drive id, e.g. `vfd generate --dump-ir yd1000`".to_owned());
    }
    if let Some(id) = args.windows(2).find(|w| w[0] == "--dump-ir").map(|w| w[1]) {
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
    match (check_only, described_changed.is_empty()) {
        (_, true) => {
            say!("drives/schema/ and the key tables in drives/README.md are up to date")
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
/// (tests/tests/schema.rs checks the same files).
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
    Ok(files)
}

fn check(files: &[&str], protocols: Option<&Path>) -> Result<(), String> {
    let mut failed = 0;
    for file in files {
        match vfd_codegen::compile(Path::new(file), protocols) {
            Ok(drive) => say!(
                "{file}: ok ({} registers, {} examples)",
                drive.registers.len(),
                drive.examples.len()
            ),
            Err(diagnostics) => {
                failed += 1;
                say!("{diagnostics}");
            }
        }
    }
    if failed == 0 {
        Ok(())
    } else {
        Err(format!("{failed} of {} file(s) have problems", files.len()))
    }
}

fn registers(drive: &DriveInfo) -> Result<(), String> {
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

fn parse_number(text: &str) -> Option<f64> {
    match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16).ok().map(f64::from),
        None => text.parse().ok(),
    }
}

/// Parses `60`, `60Hz`, `60 Hz` or `0xC400` for `register`, refusing another unit.
fn parse_value(register: &'static RegisterInfo, text: &str) -> Result<u32, String> {
    let unit = register.unit_symbol();
    let trimmed = text.trim();
    let number = if !unit.is_empty() && trimmed.ends_with(unit) {
        trimmed[..trimmed.len() - unit.len()].trim()
    } else {
        trimmed
    };
    let value = parse_number(number).ok_or_else(|| {
        format!(
            "`{text}` is not a value for {}: give a number{}",
            register.label(),
            if unit.is_empty() {
                String::new()
            } else {
                format!(" in {unit}, e.g. 12.5{unit}")
            }
        )
    })?;
    scaled_to_raw(value, register).map_err(|e| e.to_string())
}

fn address_option(args: &[&str]) -> Result<(Vec<String>, Option<u8>), String> {
    let mut rest = Vec::new();
    let mut address = None;
    let mut iter = args.iter();
    while let Some(arg) = iter.next() {
        if *arg == "--address" {
            let value = iter.next().ok_or("--address needs a station number")?;
            address = Some(
                value
                    .parse::<u8>()
                    .map_err(|_| format!("station number `{value}` is not 0-255"))?,
            );
        } else {
            rest.push((*arg).to_owned());
        }
    }
    Ok((rest, address))
}

fn encode(drive: &'static DriveInfo, protocol: &str, args: &[&str]) -> Result<(), String> {
    let protocol = find_protocol(drive, protocol)?;
    let (rest, address) = address_option(args)?;
    let words: Vec<&str> = rest.iter().map(String::as_str).collect();
    let request = match words.as_slice() {
        ["read", name] => {
            let register = find_register(drive, name)?;
            let kind = if register.data_type == DataType::Text {
                CommandKind::ReadText
            } else {
                CommandKind::Read
            };
            Request::for_register(kind, register, 0)
        }
        [verb @ ("write-ram" | "write-persistent"), name, value] => {
            let register = find_register(drive, name)?;
            if register.access == Access::ReadOnly {
                return Err(format!("{} is read-only", register.label()));
            }
            let kind = if *verb == "write-ram" {
                CommandKind::WriteRam
            } else {
                CommandKind::WritePersistent
            };
            if kind == CommandKind::WritePersistent && register.ram_only {
                return Err(format!("{} is RAM-only: use write-ram", register.label()));
            }
            let data = parse_value(register, value)?;
            Request::for_register(kind, register, data)
        }
        _ => {
            return Err(format!(
                "encode needs `read REG` or `write-ram|write-persistent REG VALUE`\n\n{USAGE}"
            ))
        }
    };
    let mut frame = [0u8; 256];
    let len = protocol
        .encode_request(&request, address, &mut frame)
        .map_err(|e| e.to_string())?;
    print_frame(&frame[..len]);
    say!("{}", request.describe());
    Ok(())
}

fn print_frame(bytes: &[u8]) {
    say!("hex:   {}", vfd_runtime::error::hex(bytes));
    if bytes
        .iter()
        .all(|b| b.is_ascii_graphic() || matches!(b, b' ' | b'\r' | b'\n'))
    {
        say!(
            "ascii: {}",
            String::from_utf8_lossy(bytes)
                .replace('\r', "\\r")
                .replace('\n', "\\n")
        );
    }
}

/// Parses hex pairs, or text with `\r` and `\n` escapes.
fn parse_frame(text: &str) -> Vec<u8> {
    let compact: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if !compact.is_empty()
        && compact.len() % 2 == 0
        && compact.chars().all(|c| c.is_ascii_hexdigit())
    {
        return (0..compact.len())
            .step_by(2)
            .filter_map(|i| u8::from_str_radix(&compact[i..i + 2], 16).ok())
            .collect();
    }
    text.replace("\\r", "\r").replace("\\n", "\n").into_bytes()
}

fn describe_value(
    drive: &DriveInfo,
    space: Space,
    register: Option<u16>,
    wire: Option<u16>,
    data: u32,
) -> String {
    let info = register.and_then(|r| drive.register_at(space, r));
    match (info, register) {
        (Some(info), _) if !info.unit_symbol().is_empty() => {
            format!(
                "{} = {} {}",
                info.label(),
                raw_to_scaled(data, info),
                info.unit_symbol()
            )
        }
        (Some(info), _) => format!("{} = {data} ({data:04X}h)", info.label()),
        (None, Some(register)) => format!(
            "{} {register} (not described) = {data} ({data:04X}h)",
            space.as_str()
        ),
        (None, None) => match wire {
            Some(wire) => format!("wire register {wire:04X}h = {data} ({data:04X}h)"),
            None => format!("data {data} ({data:04X}h); the reply does not name the register"),
        },
    }
}

fn decode(drive: &'static DriveInfo, protocol: &str, frame: &str) -> Result<(), String> {
    let protocol = find_protocol(drive, protocol)?;
    let bytes = parse_frame(frame);
    print_frame(&bytes);
    // The same reading the generator checks every manual example with.
    let as_request = decode_meaning(protocol, Direction::Request, &bytes);
    let (direction, meaning) = match as_request {
        Ok(meaning) => (Direction::Request, meaning),
        Err(request_error) => match decode_meaning(protocol, Direction::Reply, &bytes) {
            Ok(meaning) => (Direction::Reply, meaning),
            Err(reply_error) => {
                return Err(format!(
                    "not a valid {} frame:\n  as a request: {request_error}\n  as a reply:   {reply_error}",
                    protocol.id
                ))
            }
        },
    };
    print_meaning(drive, protocol, direction, &meaning);
    Ok(())
}

/// What a decoded frame means, line by line, with the register's name and unit.
fn print_meaning(
    drive: &DriveInfo,
    protocol: &Protocol,
    direction: Direction,
    meaning: &FrameMeaning,
) {
    let station = meaning
        .address
        .map(|a| format!(", station {a}"))
        .unwrap_or_default();
    let tripped = if meaning.tripped {
        ", drive TRIPPED"
    } else {
        ""
    };
    let code = meaning
        .code
        .map(code_label)
        .unwrap_or_else(|| "—".to_owned());
    if let Some(error) = meaning.error_code {
        say!("error reply {code}: error {error}{tripped}");
        match protocol.error_code(error) {
            Some(info) => say!("  {} ({}): {}", info.name, info.name_zh, info.meaning),
            None => say!("  (code not in the manual's table)"),
        }
        return;
    }
    let kind = meaning.kind.map_or("?", CommandKind::as_str);
    say!("{}: {code} ({kind}){station}{tripped}", direction.as_str());
    if let Some(index) = meaning.index {
        say!("  index {index}");
    }
    if let Some(text) = &meaning.text {
        say!("  text {text:?}");
    } else if meaning.kind != Some(CommandKind::Process) {
        let space = meaning.space.unwrap_or(Space::Parameter);
        match meaning.data {
            Some(data) => say!(
                "  {}",
                describe_value(drive, space, meaning.register, meaning.wire_register, data)
            ),
            None => {
                if let Some(register) = meaning.register {
                    let target = drive
                        .register_at(space, register)
                        .map(|r| r.label())
                        .unwrap_or(format!("{} {register}", space.as_str()));
                    say!("  {target}");
                }
            }
        }
    }
    if let Some([first, second]) = meaning.process {
        match direction {
            Direction::Request => {
                say!("  control word {first:04X}h, reference {second:04X}h")
            }
            Direction::Reply => say!("  status word {first:04X}h, output value {second:04X}h"),
        }
    }
}
