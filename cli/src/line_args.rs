//! The options every bus command shares (`--drive`, `--protocol`, `--port`, `--baud`,
//! `--parity`, `--data-bits`, `--stop-bits`, `--address`, `--timeout`, ...) and the line
//! settings they give, defaulting to the drive's factory serial settings.

use crate::Failure;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::DriveInfo;

/// Parity, as the command line spells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ParityArg {
    /// No parity bit.
    None,
    /// Even parity.
    Even,
    /// Odd parity.
    Odd,
}

impl From<ParityArg> for Parity {
    fn from(parity: ParityArg) -> Parity {
        match parity {
            ParityArg::None => Parity::None,
            ParityArg::Even => Parity::Even,
            ParityArg::Odd => Parity::Odd,
        }
    }
}

/// Which drive, which protocol, and the line settings (defaults: the drive's factory settings).
#[derive(Debug, Clone, clap::Args)]
pub struct LineArgs {
    /// Drive id (`vfd list` shows them) or the path of a drive file (./my_drive.yaml).
    #[arg(long, short = 'd', value_name = "DRIVE")]
    pub drive: String,
    /// Protocol id (default: the drive's first protocol).
    #[arg(long, short = 'p', value_name = "PROTOCOL")]
    pub protocol: Option<String>,
    /// Serial device, e.g. /dev/ttyUSB0, the pseudo-terminal `vfd sim` prints, or a serial
    /// device server as tcp://HOST:PORT (raw serial over TCP, "RTU over TCP": the line's
    /// frames unchanged, no Modbus TCP header; the baud rate and parity still set the timing,
    /// and 50 ms are added to each reply timeout for the network).
    #[arg(long, value_name = "DEVICE")]
    pub port: String,
    /// Baud rate (default: the drive's factory setting).
    #[arg(long, value_name = "BAUD")]
    pub baud: Option<u32>,
    /// Parity (default: the drive's factory setting for the protocol).
    #[arg(long, value_enum)]
    pub parity: Option<ParityArg>,
    /// Data bits per character, 7 or 8 (default: the drive's factory setting for the
    /// protocol; the DV1 speaks Modbus RTU at 8E1, Eaton at 8N1).
    #[arg(long, value_name = "BITS", value_parser = clap::value_parser!(u8).range(7..=8))]
    pub data_bits: Option<u8>,
    /// Stop bits, 1 or 2 (default: the drive's factory setting for the protocol).
    #[arg(long, value_name = "BITS", value_parser = clap::value_parser!(u8).range(1..=2))]
    pub stop_bits: Option<u8>,
    /// Station address (default: none where the protocol allows it, else its lowest station, at least 1).
    #[arg(long, value_name = "N")]
    pub address: Option<u8>,
    /// Time the drive may take to answer, in milliseconds, added to both frames' wire time and the 50 ms host latency (default: the drive's manual).
    #[arg(long, value_name = "MS")]
    pub timeout: Option<u64>,
    /// The drive's port the line is on, for drives with several (`vfd info DRIVE` lists
    /// them): registers that exist once per port are read and written on this port's copy.
    #[arg(long, value_name = "PORT")]
    pub port_kind: Option<String>,
    /// The protocol's variant the drive is set to, for protocols with several (`vfd info
    /// DRIVE` lists them; Eaton: `cr` or `cr_lf`, the terminator 07-06 selects); default:
    /// the protocol's first.
    #[arg(long, value_name = "VARIANT")]
    pub variant: Option<String>,
    /// Print each frame sent and received, in hex and decoded, with the milliseconds since
    /// the command started, and the master's retries and resyncs, on standard error.
    #[arg(long)]
    pub trace: bool,
    /// Repeat a read up to N more times after a lost or garbled reply (reads only: a write
    /// is never repeated, it may have been carried out). Default: 0.
    #[arg(long, value_name = "N")]
    pub retries: Option<u8>,
    /// Keep at least this many milliseconds of silence between frames, for a slow gateway
    /// or USB adapter (never shorter than the protocol's own gap).
    #[arg(long, value_name = "MS")]
    pub gap_ms: Option<u64>,
    /// Milliseconds added to every reply timeout for the adapter and the host (default:
    /// 50), e.g. for a USB adapter that buffers or a loaded machine.
    #[arg(long, value_name = "MS")]
    pub host_latency_ms: Option<u64>,
}

/// The character format given on the command line (`--baud`, `--parity`, `--data-bits`,
/// `--stop-bits`); each left out is the drive's factory setting for the protocol.
#[derive(Debug, Clone, Copy, Default)]
pub struct LineFormat {
    /// `--baud`.
    pub baud: Option<u32>,
    /// `--parity`.
    pub parity: Option<ParityArg>,
    /// `--data-bits`.
    pub data_bits: Option<u8>,
    /// `--stop-bits`.
    pub stop_bits: Option<u8>,
}

impl LineArgs {
    /// The character format these options give.
    pub fn format(&self) -> LineFormat {
        LineFormat {
            baud: self.baud,
            parity: self.parity,
            data_bits: self.data_bits,
            stop_bits: self.stop_bits,
        }
    }
}

/// The drive's factory serial settings for `protocol` (its own character format where a
/// setting chooses one: the DV1's Modbus RTU at 8E1), with what the command line gives;
/// data and stop bits the drive cannot be set to are refused.
pub fn line_settings(
    drive: &DriveInfo,
    protocol: &str,
    given: LineFormat,
) -> Result<SerialSettings, Failure> {
    let serial = drive.serial;
    let mut settings = serial.default_for(protocol);
    if let Some(baud) = given.baud {
        settings.baud = baud;
    }
    if let Some(parity) = given.parity {
        settings.parity = parity.into();
    }
    let list = |bits: &[u8]| {
        bits.iter()
            .map(u8::to_string)
            .collect::<Vec<_>>()
            .join(" or ")
    };
    if let Some(bits) = given.data_bits {
        if !serial.data_bits.contains(&bits) {
            return Err(Failure::new(format!(
                "{} cannot use {bits} data bits: its description gives {}",
                drive.id,
                list(serial.data_bits)
            ))
            .hint(format!(
                "leave --data-bits out for its factory setting over {protocol} ({})",
                settings.data_bits
            )));
        }
        settings.data_bits = bits;
    }
    if let Some(bits) = given.stop_bits {
        let choices = serial.stop_bits_choices();
        if !choices.contains(&bits) {
            return Err(Failure::new(format!(
                "{} cannot use {bits} stop bits: its description gives {}",
                drive.id,
                list(choices)
            ))
            .hint(format!(
                "leave --stop-bits out for its factory setting over {protocol} ({})",
                settings.stop_bits
            )));
        }
        settings.stop_bits = bits;
    }
    // A protocol whose format a setting chooses speaks only the formats it offers (the
    // DV1's Modbus ASCII: 7N2, 7E1, 7O1).
    let offered: Vec<_> = serial.formats_for(protocol).collect();
    if !offered.is_empty() && !offered.iter().any(|l| l.fits(&settings)) {
        let labels: Vec<String> = offered.iter().map(|l| l.label()).collect();
        return Err(Failure::new(format!(
            "{} cannot speak {protocol} at {}: its setting offers {}",
            drive.id,
            settings.format_label(),
            labels.join(", ")
        ))
        .hint("give --data-bits, --parity and --stop-bits of one of those formats, or leave them out for the factory setting"));
    }
    Ok(settings)
}
