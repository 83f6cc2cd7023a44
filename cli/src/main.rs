//! `vfd`: the command-line tool for RS-485 frequency inverters described in `drives/*.yaml`.
//! It reads, writes and watches drives by register name with units, decodes captured
//! frames, backs up and restores parameters, runs the virtual drive on a pseudo-terminal,
//! shows the whole product in `vfd demo`, and runs the generator (`generate`, `check`).
//!
//! Everything about a drive comes from its `DriveInfo` (generated from the YAML): no drive or
//! protocol is named here. Errors are one line for people, a hint, and a non-zero exit.

/// mimalloc, not the system's malloc: `vfd serve`'s memory stays flat where glibc's
/// per-thread arenas fragment (cli/Cargo.toml says more).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

mod commands;
mod emit;
mod failure;
mod frame_text;
mod line_args;
mod open_session;
mod out;
mod paged;
mod service;
mod sim;
mod stop_flag;
mod trace;
mod traced_line;

use commands::{backup, block, control, decode, describe, encode, generate, ports, watch};
pub use failure::Failure;
use service::{plant_check, serve, serve_args};
#[cfg(all(unix, feature = "pty"))]
use sim::{demo, demo_plant};

use clap::{CommandFactory, Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use vfd_bus::Catalogue;
use vfd_runtime::meaning::Direction;

/// The environment variable holding more folders of drive files, separated as `PATH` is.
pub const DRIVES_VARIABLE: &str = "VFD_DRIVES";

/// Tools for RS-485 frequency inverters described in drives/*.yaml: read, write and watch
/// registers by name with units, decode frames, back up and restore parameters, run the
/// virtual drive, and generate code and docs.
#[derive(Debug, Parser)]
#[command(
    name = "vfd",
    version,
    propagate_version = true,
    arg_required_else_help = true
)]
#[command(
    after_help = "Start with `vfd demo` (no hardware needed), then `vfd list` and `vfd info DRIVE`."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// A folder of drive files whose drives `vfd list` shows and every command finds by
    /// id (repeat for several; the VFD_DRIVES environment variable adds more, separated
    /// as in PATH). A drive file can also be named by its path wherever a drive is asked for.
    #[arg(long = "drives", value_name = "DIR", global = true)]
    drives: Vec<PathBuf>,
    /// The folder of protocol files for drive files (default: `protocols/` next to each
    /// drive file; the protocol files shipped with vfd are the fallback).
    #[arg(long, value_name = "DIR", global = true)]
    protocols: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// List the described drives (compiled in, and those of --drives folders and
    /// VFD_DRIVES) and the protocols each speaks.
    List {
        /// Output format (docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
    },
    /// Show a drive's registers: unit, range, default, access, RAM or EEPROM, writable
    /// while running, and the manual's text.
    #[command(
        after_help = "Registers are found by code (FA01, FH, 3-03), address (0xFA01), id, or English or Chinese name (最高频率), without regard to case.\n\nExamples:\n  vfd info yd1000\n  vfd info yd1000 FH FA00\n  vfd info fc51 3-03"
    )]
    Info {
        /// Drive id (`vfd list`) or the path of a drive file (or give it with --drive,
        /// as the other commands take it).
        #[arg(required_unless_present = "drive_option")]
        drive: Option<String>,
        /// The drive, as the other commands name it: `vfd info --drive ./my_drive.yaml FH`.
        /// With it, every word after `info` is a register.
        #[arg(long = "drive", short = 'd', value_name = "DRIVE")]
        drive_option: Option<String>,
        /// Registers to show in full (all, one line each, when none is given).
        registers: Vec<String>,
        /// Output format (docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
    },
    /// Read registers from a drive, in engineering units.
    #[command(
        after_help = "Examples:\n  vfd read --drive yd1000 --port /dev/ttyUSB0 FA01 FE01 FC90\n  vfd read --drive yd1000 --port tcp://192.168.1.50:4001 FA01   (a serial device server)"
    )]
    Read {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Read with this command instead of the protocol's default, where the protocol
        /// has several (a letter such as G for the Toshiba binary G read, or a number such
        /// as 0x03); the drive page lists them.
        #[arg(long, value_name = "CODE")]
        command: Option<String>,
        /// Output format (docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
        /// Registers to read.
        #[arg(required = true)]
        registers: Vec<String>,
    },
    /// Write a value to a register (RAM only unless --persist), checked before anything is sent.
    #[command(
        after_help = "Values: 60, 60Hz, 30.0s, a raw word (C400h, 0xC400), a code's name (even), or bit fields by name (command_enabled,run).\n\nExamples:\n  vfd write --drive yd1000 --port /dev/ttyUSB0 FA01 60Hz\n  vfd write --drive yd1000 --port /dev/ttyUSB0 FA00 command_enabled,frequency_enabled,run\n  vfd write --drive vf-as1 --port /dev/ttyUSB0 --broadcast '*9' --reply-from 9 FA01 60Hz"
    )]
    Write {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Write RAM and EEPROM (EEPROM wears out; the default writes RAM only).
        #[arg(long)]
        persist: bool,
        /// Write with this command instead of the protocol's default (S for the Toshiba
        /// drive-to-drive command, s to say the sender has tripped). A command whose data is
        /// a percentage of another register takes the value as a percentage (50%); one that
        /// gets no reply returns once the frame is sent.
        #[arg(long, value_name = "CODE")]
        command: Option<String>,
        /// Broadcast the write instead of addressing one station: `all` (or `**`) for every
        /// station, or a group with `*` for each open digit (`*9`, `1*`), where the drive's
        /// description allows it.
        #[arg(long, value_name = "STATIONS")]
        broadcast: Option<String>,
        /// With --broadcast: the station that answers on this installation (its own number
        /// in the reply); left out, no answer is awaited.
        #[arg(long, value_name = "N", requires = "broadcast")]
        reply_from: Option<u8>,
        /// Register to write.
        register: String,
        /// Value in the register's unit.
        #[arg(allow_hyphen_values = true)]
        value: String,
    },
    /// Run the motor at a speed (any drive with control roles): the speed command, then
    /// the run command, in the order the drive needs; refused while tripped.
    #[command(
        after_help = "The speed is in the drive's speed command unit (Hz, or % where the command is one), or in Hz where the command is a percentage of a frequency (then 50% gives the percentage).\n\nExamples:\n  vfd run --drive yd1000 --port /dev/ttyUSB0 30Hz\n  vfd run --drive dv1 --port /dev/ttyUSB0 --reverse 45"
    )]
    Run {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Run in reverse.
        #[arg(long)]
        reverse: bool,
        /// The speed (`30`, `30Hz`, `50%`).
        speed: String,
    },
    /// Stop the motor (ramping down; always allowed).
    Stop {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Coast to a stop (the output off at once), where the drive can.
        #[arg(long)]
        coast: bool,
    },
    /// Reset a trip.
    Reset {
        #[command(flatten)]
        line: line_args::LineArgs,
    },
    /// Show what the drive is doing: running, direction, output, set point, at speed,
    /// tripped and its trip code, output current.
    State {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Output format: text, json or jsonl (docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
        /// Show it again every this many seconds (Ctrl-C stops).
        #[arg(long, value_name = "SECONDS")]
        watch: Option<f64>,
        /// With --watch: stop after this many states.
        #[arg(long, value_name = "N", requires = "watch")]
        count: Option<u64>,
    },
    /// Run one block transfer (write several words, read several, in one exchange) where
    /// the drive describes one; the words' registers are the drive's block selection.
    #[command(
        after_help = "The selection (the drive's block selector parameters) is read from the drive unless --defaults; the drive uses the values it had at its last reset.

Examples:
  vfd block --drive vf-as1 --port /dev/pts/5 --write command_priority,frequency_priority,run --write 60Hz
  vfd block --drive vf-as1 --port /dev/pts/5 --defaults --set F875=2 --reads 1"
    )]
    Block {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// A value to write, in its target register's units (repeat, in word order).
        #[arg(long = "write", value_name = "VALUE", allow_hyphen_values = true)]
        writes: Vec<String>,
        /// Words to read back (default: every read position).
        #[arg(long, value_name = "N")]
        reads: Option<u8>,
        /// Take the selectors at the description's defaults instead of reading them.
        #[arg(long)]
        defaults: bool,
        /// A selector's value, CODE=VALUE (repeat), instead of the drive's.
        #[arg(long = "set", value_name = "CODE=VALUE")]
        sets: Vec<String>,
    },
    /// Poll registers and show them live, with a trend line for numbers (Ctrl-C stops).
    ///
    /// The watch outlives the line: a timeout, a bad reply or an error reply shows the value
    /// as stale and counts an error; after an I/O error (an unplugged adapter) the port is
    /// reopened, first after 0.1 s, the wait doubling to 5 s (at least --interval). It ends
    /// after --count samples or on Ctrl-C with status 0, non-zero only when no read ever
    /// succeeded.
    Watch {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Time between polls, in milliseconds.
        #[arg(long, default_value_t = 500, value_name = "MS")]
        interval: u64,
        /// Stop after this many samples, failed ones included (default: until Ctrl-C).
        #[arg(long, value_name = "N")]
        count: Option<u64>,
        /// Output format: jsonl gives one object per sample and register, flushed at once;
        /// json writes its one document at the end (docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
        /// Registers to watch.
        #[arg(required = true)]
        registers: Vec<String>,
    },
    /// Save every readable parameter to a YAML (or .json) file, values in units.
    Backup {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// File to write (.yaml, .yml or .json).
        #[arg(long, value_name = "FILE")]
        to: PathBuf,
        /// Also list every parameter read on standard output in this format (the
        /// summary then goes to standard error; docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
    },
    /// Write a backup back: only writable values that differ, each read back; running it
    /// again after an interruption finishes the job.
    Restore {
        #[command(flatten)]
        line: line_args::LineArgs,
        /// Backup file made by `vfd backup`.
        #[arg(long, value_name = "FILE")]
        from: PathBuf,
        /// Show what would be written, write nothing.
        #[arg(long)]
        dry_run: bool,
        /// Write RAM and EEPROM (default: RAM only, lost at power-off).
        #[arg(long)]
        persist: bool,
        /// When the drive runs and some values cannot change while it runs, stop it first
        /// (default: refuse, writing nothing).
        #[arg(long)]
        stop_first: bool,
    },
    /// Run the virtual drive on a pseudo-terminal (or over TCP with --listen), or several
    /// stations on one line (--station, repeated); prints the device path (or
    /// tcp://HOST:PORT) first.
    #[command(
        after_help = "The first line of output is the device to open, e.g.:\n  vfd sim --drive yd1000 &\n  vfd read --drive yd1000 --port /dev/pts/5 FA01\n\nAs a serial device server (raw frames over TCP, \"RTU over TCP\"):\n  vfd sim --drive yd1000 --listen 127.0.0.1:0 &\n  vfd read --drive yd1000 --port tcp://127.0.0.1:40123 FA01\n\nSeveral stations on one line (a multi-drop bus; their protocols must share a framing):\n  vfd sim --station fc51:modbus@1 --station fc51:modbus@2 --station vf-as1:modbus@3 &\n  vfd read --drive vf-as1 --protocol modbus --port /dev/pts/5 --address 3 FA01\nWhile it runs, standard input takes one command a line, each answered on standard error:\n  unplug N   pull station N off the line (it neither answers nor acts on frames)\n  plug N     put it back\n  status     per station: requests received, answered, writes\nThe end of standard input does not stop it; SIGINT or SIGTERM does."
    )]
    Sim(sim::SimArgs),
    /// List the serial ports this system has (USB vendor and product where known).
    #[command(
        after_help = "Give a name it prints to --port, e.g. vfd read --drive yd1000 --port /dev/ttyUSB0 FA01"
    )]
    Ports {
        /// `text` (one line per port), `json` (an array of objects), `jsonl` or `csv`
        /// (fields: name, kind, vendor_id, product_id, manufacturer, product, serial_number).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
    },
    /// Show the whole product against the virtual drive on a pseudo-terminal, every frame
    /// printed (no hardware, ~5 s).
    Demo {
        /// Drive to show, by id or the path of a drive file (default: the first described
        /// drive with a behaviour model).
        #[arg(long)]
        drive: Option<String>,
        /// Seconds to watch the motor ramp (with --plant: seconds to serve the plant;
        /// default until Ctrl-C).
        #[arg(long)]
        seconds: Option<u64>,
        /// A virtual plant instead: two buses, five stations of three drive models, polled
        /// by `vfd serve` (JSON lines on standard output, or --mqtt).
        #[arg(long, conflicts_with = "drive")]
        plant: bool,
        /// With --plant: publish to this MQTT broker (mqtt://HOST:PORT) instead of printing.
        #[arg(long, value_name = "URL", requires = "plant")]
        mqtt: Option<String>,
    },
    /// Decode a captured frame (hex or text) and explain every field.
    #[command(
        after_help = "FRAME is hex (\"2F 52 FD 00 7E\", 2F52FD007E) or text with escapes (\"(RFD00)\\r\", \\x05).\nThe protocol, direction and drive are found when not given. Exit status 0 for a valid frame.\n\nExamples:\n  vfd decode \"2F 52 FD 00 7E\"\n  vfd decode --drive yd1000 --reply \"(RFD00)\\r\"\n  vfd decode yd1000 ascii \"(N0001&5D)\\r\""
    )]
    Decode {
        /// Drive id or the path of a drive file.
        #[arg(long, short = 'd')]
        drive: Option<String>,
        /// Protocol id.
        #[arg(long, short = 'p')]
        protocol: Option<String>,
        /// Decode as a request only.
        #[arg(long, conflicts_with = "reply")]
        request: bool,
        /// Decode as a reply only.
        #[arg(long)]
        reply: bool,
        /// Print one JSON object (the same as --format json).
        #[arg(long, conflicts_with = "format")]
        json: bool,
        /// Output format: json is one object; jsonl and csv give the frame's register value
        /// as `vfd read` does (docs/output.md names every field).
        #[arg(long, value_enum, default_value_t = emit::Format::Text)]
        format: emit::Format,
        /// The frame, optionally after a drive id and a protocol id (the older form).
        #[arg(required = true, num_args = 1..=3, value_name = "FRAME")]
        args: Vec<String>,
    },
    /// Print the request frame for a read or write, by register name with units.
    Encode {
        /// Drive id or the path of a drive file.
        drive: String,
        /// Protocol id.
        protocol: String,
        /// What to do.
        #[arg(value_enum)]
        action: encode::Action,
        /// Register (code, address, id or name).
        register: String,
        /// Value, for writes.
        #[arg(allow_hyphen_values = true)]
        value: Option<String>,
        /// Station address.
        #[arg(long, value_name = "N")]
        address: Option<u8>,
        /// Use this command instead of the protocol's default (G, S, s; see `vfd read
        /// --command`); a command whose data is a percentage takes the value as one (50%).
        #[arg(long, value_name = "CODE")]
        command: Option<String>,
    },
    /// List a drive's registers, one line each.
    Registers {
        /// Drive id or the path of a drive file.
        drive: String,
    },
    /// Regenerate generated-docs/, drives/schema/ and the key tables in drives/README.md.
    Generate {
        /// Only report stale files; exit 1 if any.
        #[arg(long)]
        check: bool,
        /// Print the generator's IR of one drive as YAML instead.
        #[arg(long, value_name = "DRIVE", num_args = 0..=1)]
        dump_ir: Option<Option<String>>,
        /// Repository root (default: found upwards from the current folder).
        #[arg(long, value_name = "DIR")]
        root: Option<String>,
    },
    /// Poll the drives of a plant file on their buses and publish what they read; with
    /// --check, check the plant file only.
    #[command(
        after_help = "Examples:\n  vfd serve --check plants/example.yaml\n\nThe plant file's format: docs/plant.md."
    )]
    Serve(serve_args::ServeArgs),
    /// Validate drive files and print every problem.
    Check {
        /// Fail (exit 1) when there are warnings, as when there are errors.
        #[arg(long)]
        deny_warnings: bool,
        /// Drive files.
        #[arg(required = true)]
        files: Vec<String>,
    },
    /// Print a shell completion script (e.g. `vfd completions bash > ~/.local/share/bash-completion/completions/vfd`).
    Completions {
        /// Shell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
}

/// What `vfd sim` and `vfd demo` say where this `vfd` was built without pseudo-terminals.
#[cfg(not(all(unix, feature = "pty")))]
pub fn needs_pty(command: &str, instead: &str) -> Failure {
    Failure::new(format!(
        "`{command}` needs a Unix pseudo-terminal, and this vfd was built without them (feature `pty`){instead}"
    ))
}

/// The catalogue of drives the command line gives: the compiled-in drives, the folders of
/// `--drives` and then of `VFD_DRIVES`, the protocols folder of `--protocols`; a drive file
/// used without some of its parts is said on standard error.
fn catalogue(mut drives: Vec<PathBuf>, protocols: Option<PathBuf>) -> Catalogue {
    if let Some(more) = std::env::var_os(DRIVES_VARIABLE) {
        drives.extend(std::env::split_paths(&more).filter(|p| !p.as_os_str().is_empty()));
    }
    Catalogue::new()
        .with_folders(drives)
        .with_protocols(protocols)
        .on_warning(|text| {
            use std::io::Write as _;
            let _ = writeln!(std::io::stderr(), "vfd: warning: {text}");
        })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let catalogue = catalogue(cli.drives, cli.protocols);
    match run(cli.command, &catalogue) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            // Not `eprintln!`, which panics when standard error is a closed pipe
            // (`vfd ... 2>&1 | head -1`): the exit status says it.
            use std::io::Write as _;
            let mut stderr = std::io::stderr().lock();
            let _ = writeln!(stderr, "vfd: {}", failure.message);
            if let Some(hint) = failure.hint {
                let _ = writeln!(stderr, "  hint: {hint}");
            }
            ExitCode::FAILURE
        }
    }
}

fn run(command: Command, catalogue: &Catalogue) -> Result<(), Failure> {
    match command {
        Command::List { format } => describe::list(catalogue, format),
        Command::Info {
            drive,
            drive_option,
            registers,
            format,
        } => match drive_option {
            // `--drive D R1 R2`: the first word is a register, not the drive.
            Some(named) => {
                let registers: Vec<String> = drive.into_iter().chain(registers).collect();
                describe::info(catalogue, &named, &registers, format)
            }
            None => describe::info(
                catalogue,
                drive.as_deref().unwrap_or_default(),
                &registers,
                format,
            ),
        },
        Command::Run {
            line,
            reverse,
            speed,
        } => control::run(catalogue, &line, &speed, reverse),
        Command::Stop { line, coast } => control::stop(catalogue, &line, coast),
        Command::Reset { line } => control::reset(catalogue, &line),
        Command::State {
            line,
            format,
            watch,
            count,
        } => control::state(catalogue, &line, format, watch, count),
        Command::Read {
            line,
            command,
            format,
            registers,
        } => watch::read(catalogue, &line, command.as_deref(), &registers, format),
        Command::Write {
            line,
            persist,
            command,
            broadcast,
            reply_from,
            register,
            value,
        } => match broadcast {
            Some(stations) => watch::broadcast_write(
                catalogue, &line, &register, &value, persist, &stations, reply_from,
            ),
            None => watch::write(
                catalogue,
                &line,
                command.as_deref(),
                &register,
                &value,
                persist,
            ),
        },
        Command::Block {
            line,
            writes,
            reads,
            defaults,
            sets,
        } => block::block(
            catalogue,
            &block::BlockArgs {
                line: &line,
                writes: &writes,
                reads,
                defaults,
                sets: &sets,
            },
        ),
        Command::Watch {
            line,
            interval,
            count,
            format,
            registers,
        } => watch::watch(catalogue, &line, &registers, interval, count, format),
        Command::Backup { line, to, format } => backup::backup(catalogue, &line, &to, format),
        Command::Restore {
            line,
            from,
            dry_run,
            persist,
            stop_first,
        } => backup::restore(catalogue, &line, &from, dry_run, persist, stop_first),
        Command::Ports { format } => ports::run(format),
        Command::Sim(args) => sim::run(catalogue, &args),
        #[cfg(all(unix, feature = "pty"))]
        Command::Demo {
            plant: true,
            seconds,
            mqtt,
            ..
        } => demo_plant::run(catalogue, mqtt.as_deref(), seconds),
        #[cfg(all(unix, feature = "pty"))]
        Command::Demo { drive, seconds, .. } => {
            demo::run(catalogue, drive.as_deref(), seconds.unwrap_or(4))
        }
        #[cfg(not(all(unix, feature = "pty")))]
        Command::Demo { .. } => Err(needs_pty("demo", "")),
        Command::Decode {
            drive,
            protocol,
            request,
            reply,
            json,
            format,
            mut args,
        } => {
            let format = if json { emit::Format::Json } else { format };
            let frame = args.pop().unwrap_or_default();
            let (drive, protocol) = match (args.as_slice(), drive, protocol) {
                ([], drive, protocol) => (drive, protocol),
                ([d], None, protocol) => (Some(d.clone()), protocol),
                ([d, p], None, None) => (Some(d.clone()), Some(p.clone())),
                _ => {
                    return Err(Failure::new("the drive and protocol are given twice").hint(
                        "use either `vfd decode DRIVE PROTOCOL FRAME` or --drive/--protocol",
                    ))
                }
            };
            let direction = if request {
                Some(Direction::Request)
            } else if reply {
                Some(Direction::Reply)
            } else {
                None
            };
            decode::decode(
                catalogue,
                &decode::DecodeArgs {
                    drive,
                    protocol,
                    direction,
                    format,
                    frame,
                },
            )
        }
        Command::Encode {
            drive,
            protocol,
            action,
            register,
            value,
            address,
            command,
        } => encode::encode(
            catalogue,
            &encode::EncodeArgs {
                drive: &drive,
                protocol: &protocol,
                action,
                register: &register,
                value: value.as_deref(),
                address,
                command: command.as_deref(),
            },
        ),
        Command::Registers { drive } => {
            generate::registers(catalogue.drive(&drive)?).map_err(Failure::from)
        }
        Command::Generate {
            check,
            dump_ir,
            root,
        } => generate::generate(
            check,
            dump_ir.as_ref().map(|d| d.as_deref()),
            root.as_deref(),
        )
        .map_err(Failure::from),
        Command::Check {
            deny_warnings,
            files,
        } => generate::check(catalogue, &files, deny_warnings).map_err(Failure::from),
        Command::Serve(args) if args.check => plant_check::run(catalogue, &args.plant),
        Command::Serve(args) => serve::run(catalogue, &args),
        Command::Completions { shell } => {
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "vfd", &mut script);
            out::print_raw(&String::from_utf8_lossy(&script));
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }
}
