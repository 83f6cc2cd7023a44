//! `vfd sim`: the virtual drive of any described drive, served on a pseudo-terminal (or,
//! with `--listen HOST:PORT`, over TCP as a serial device server would: raw frames, one
//! client at a time) until SIGINT or SIGTERM. The device path (`tcp://HOST:PORT` with the
//! bound port) is the first line of output, so scripts and tests can read it; `--verbose`
//! logs each exchange (hex and decoded) on standard error. Several stations can share the
//! line (`--station DRIVE[:PROTOCOL][@ADDRESS]`, repeated: a multi-drop bus, each answering
//! its own address), and standard input controls it while it runs ([`crate::sim::control`]).

//!
//! The simulator wing of `vfd`: the virtual drive served (`vfd sim`), its stations and
//! control from standard input, and the demos (`vfd demo`, `vfd demo --plant`).

pub mod control;
#[cfg(all(unix, feature = "pty"))]
pub mod demo;
#[cfg(all(unix, feature = "pty"))]
pub mod demo_plant;
pub mod log;
#[cfg(all(unix, feature = "pty"))]
pub mod plant;
pub mod station;

use crate::line_args::ParityArg;
use crate::out::say;
use crate::sim::log::Logged;
use crate::Failure;
use station::SimStation;
use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use vfd_bus::{lookup, Catalogue};
use vfd_runtime::serial::SerialSettings;
#[cfg(all(unix, feature = "pty"))]
use vfd_runtime::transport::PseudoTerminal;
use vfd_runtime::transport::TcpTransport;
use vfd_runtime::virtual_drive::{serve_bus, BusStation, Fault};

/// Options of `vfd sim`.
#[derive(Debug, Clone, clap::Args)]
pub struct SimArgs {
    /// Drive id (`vfd list`) or the path of a drive file (./my_drive.yaml): one station.
    #[arg(
        long,
        short = 'd',
        required_unless_present = "station",
        conflicts_with = "station"
    )]
    pub drive: Option<String>,
    /// A station of a multi-drop line, `DRIVE[:PROTOCOL][@ADDRESS]` (default protocol: the
    /// drive's first; default address: the protocol's lowest); repeat for each station,
    /// e.g. --station fc51:modbus@1 --station fc51:modbus@2 --station vf-as1:modbus@3. Their protocols
    /// must share a framing, their addresses must differ.
    #[arg(long, value_name = "DRIVE[:PROTOCOL][@ADDRESS]")]
    pub station: Vec<String>,
    /// Protocol id (default: the drive's first protocol).
    #[arg(long, short = 'p', conflicts_with = "station")]
    pub protocol: Option<String>,
    /// Station address the drive answers (default: the protocol's lowest, at least 1).
    #[arg(long, value_name = "N", conflicts_with = "station")]
    pub address: Option<u8>,
    /// Baud rate the timing follows (default: the drive's factory setting).
    #[arg(long)]
    pub baud: Option<u32>,
    /// Parity the timing follows (default: the drive's factory setting for the protocol).
    #[arg(long, value_enum)]
    pub parity: Option<ParityArg>,
    /// Data bits the timing follows, 7 or 8 (default: the drive's factory setting for the
    /// protocol).
    #[arg(long, value_name = "BITS", value_parser = clap::value_parser!(u8).range(7..=8))]
    pub data_bits: Option<u8>,
    /// Stop bits the timing follows, 1 or 2 (default: the drive's factory setting for the
    /// protocol).
    #[arg(long, value_name = "BITS", value_parser = clap::value_parser!(u8).range(1..=2))]
    pub stop_bits: Option<u8>,
    /// Log each exchange, in hex and decoded, on standard error.
    #[arg(long, short = 'v')]
    pub verbose: bool,
    /// Misbehave: each fault spoils the next reply (noise: every reply), in the order given.
    #[arg(long, value_enum, value_name = "FAULT", conflicts_with = "station")]
    pub fault: Vec<FaultArg>,
    /// Start tripped with this trip code.
    #[arg(long, value_name = "CODE", conflicts_with = "station")]
    pub trip: Option<u16>,
    /// The drive's port it serves, for drives with several: that port's command word and
    /// frequency command act (default: the registers as the behaviour model names them).
    #[arg(long, value_name = "PORT", conflicts_with = "station")]
    pub port_kind: Option<String>,
    /// The protocol's variant the drive is set to, for protocols with several (Eaton:
    /// `cr_lf`): the register that selects it is set so (07-06 = 2), as if on the panel
    /// before power-on. Default: the drive's factory setting.
    #[arg(long, value_name = "VARIANT", conflicts_with = "station")]
    pub variant: Option<String>,
    /// Serve over TCP on this address instead of a pseudo-terminal, as a serial device server
    /// does (raw frames, no Modbus TCP header; one client at a time, the next accepted when it
    /// leaves). Port 0 picks a free one; the first line of output is tcp://HOST:PORT.
    #[arg(long, value_name = "HOST:PORT")]
    pub listen: Option<String>,
}

/// Faults the virtual drive can commit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FaultArg {
    /// Do not answer.
    DropReply,
    /// Answer with a wrong checksum.
    CorruptChecksum,
    /// Answer after the master's timeout.
    Delay,
    /// Send garbage bytes before the reply.
    Garbage,
    /// Answer as another station.
    WrongStation,
    /// Echo the request before the reply.
    EchoRequest,
    /// Send the reply a byte at a time.
    SplitBytes,
    /// Jam the line with noise.
    Noise,
    /// Answer a request for any station.
    AnswerBroadcast,
}

impl From<FaultArg> for Fault {
    fn from(fault: FaultArg) -> Fault {
        match fault {
            FaultArg::DropReply => Fault::DropReply,
            FaultArg::CorruptChecksum => Fault::CorruptChecksum,
            FaultArg::Delay => Fault::Delay,
            FaultArg::Garbage => Fault::GarbageBefore(vec![0x00, 0xFF, 0x13]),
            FaultArg::WrongStation => Fault::WrongStation,
            FaultArg::EchoRequest => Fault::EchoRequest,
            FaultArg::SplitBytes => Fault::SplitBytes(2),
            FaultArg::Noise => Fault::Noise,
            FaultArg::AnswerBroadcast => Fault::AnswerBroadcast,
        }
    }
}

/// Serves the virtual drive (or the stations of a line) until SIGINT or SIGTERM.
pub fn run(catalogue: &Catalogue, args: &SimArgs) -> Result<(), Failure> {
    let (stations, banner_one) = match args.drive.as_deref() {
        Some(drive) => {
            let (station, banner) = one_station(catalogue, args, drive)?;
            (vec![station], Some(banner))
        }
        None => (
            args.station
                .iter()
                .map(|spec| station::parse(catalogue, spec))
                .collect::<Result<Vec<_>, _>>()?,
            None,
        ),
    };
    let first = stations
        .first()
        .ok_or_else(|| Failure::new("vfd sim: no station to serve"))?;
    let settings = crate::line_args::line_settings(
        first.drive,
        &first.bus.protocol.id,
        crate::line_args::LineFormat {
            baud: args.baud,
            parity: args.parity,
            data_bits: args.data_bits,
            stop_bits: args.stop_bits,
        },
    )?;
    if banner_one.is_none() {
        station::check_line(&stations, &settings)?;
    }
    let stop = crate::stop_flag::stop_flag()?;
    let banner = |place: &str| match &banner_one {
        Some(banner) => eprintln!(
            "vfd sim: virtual {banner} on {place}, {} baud {}; Ctrl-C stops",
            settings.baud,
            settings.format_label()
        ),
        None => {
            eprintln!(
                "vfd sim: {} virtual stations on {place}, {} baud {}; Ctrl-C stops",
                stations.len(),
                settings.baud,
                settings.format_label()
            );
            for station in &stations {
                eprintln!("  station {}: {}", station.address, station.describe());
            }
            eprintln!("  standard input takes: unplug N, plug N, status");
        }
    };
    crate::sim::control::spawn(stations.clone());
    let serving = Serving {
        stations: &stations,
        settings,
        verbose: args.verbose,
        stop: &stop,
    };
    if let Some(listen) = args.listen.as_deref() {
        let listener = TcpListener::bind(listen).map_err(|e| {
            Failure::new(format!("cannot listen on {listen}: {e}"))
                .hint("give HOST:PORT, e.g. 127.0.0.1:5020 (port 0 picks a free port)")
        })?;
        let bound = listener
            .local_addr()
            .map_err(|e| Failure::new(format!("cannot read the address listened on: {e}")))?;
        let place = format!("tcp://{bound}");
        say!("{place}");
        banner(&place);
        serving.listen(&listener)?;
        eprintln!("vfd sim: stopped");
        return Ok(());
    }
    #[cfg(not(all(unix, feature = "pty")))]
    return Err(crate::needs_pty(
        "sim",
        "; serve over TCP instead: vfd sim --listen 127.0.0.1:0",
    ));
    #[cfg(all(unix, feature = "pty"))]
    serving.on_pty(banner)
}

/// The one station `--drive` gives, with its faults, trip, port and variant, and how the
/// banner names it.
fn one_station(
    catalogue: &Catalogue,
    args: &SimArgs,
    drive: &str,
) -> Result<(SimStation, String), Failure> {
    let drive = catalogue.drive(drive)?;
    let protocol = lookup::protocol(drive, args.protocol.as_deref())?;
    let address = args
        .address
        .unwrap_or_else(|| protocol.address_range.0.max(1));
    let mut station = station::station(drive, protocol, address);
    let sim = station.bus.simulator.clone();
    if let Some(port) = lookup::port(drive, args.port_kind.as_deref())? {
        sim.lock().set_port(port.id);
    }
    let protocol = lookup::variant(protocol, args.variant.as_deref())?;
    station.bus.protocol = protocol;
    if let Some(id) = args.variant.as_deref() {
        if !sim.lock().select_variant(protocol) {
            return Err(Failure::new(format!(
                "no register of drive {} selects variant `{id}` of protocol {}",
                drive.id, protocol.id
            ))
            .hint("the drive's protocol entry names the selecting register with `variant:`"));
        }
    }
    for fault in &args.fault {
        sim.inject((*fault).into());
    }
    if let Some(code) = args.trip {
        sim.inject_trip(code);
    }
    let banner = format!(
        "{} ({}) speaking {}{} as station {address}",
        drive.id,
        drive.model,
        protocol.id,
        args.variant
            .as_deref()
            .map_or_else(String::new, |id| format!(" ({id})")),
    );
    Ok((station, banner))
}

/// How long the listening loop waits between looks for a client and at the stop flag.
const ACCEPT_POLL: Duration = Duration::from_millis(20);

/// What serving needs: the stations, the line, and when to stop.
struct Serving<'a> {
    stations: &'a [SimStation],
    settings: SerialSettings,
    verbose: bool,
    stop: &'a AtomicBool,
}

impl Serving<'_> {
    /// The stations as the bus server takes them.
    fn bus(&self) -> Vec<BusStation> {
        self.stations.iter().map(|s| s.bus.clone()).collect()
    }

    /// Serves the line on a new pseudo-terminal until the stop flag is set.
    #[cfg(all(unix, feature = "pty"))]
    fn on_pty(&self, banner: impl Fn(&str)) -> Result<(), Failure> {
        let pty = PseudoTerminal::open()
            .map_err(|e| Failure::new(format!("cannot open a pseudo-terminal: {e}")))?;
        let path = pty.slave_path().display().to_string();
        let transport = pty
            .master()
            .map_err(|e| Failure::new(format!("cannot use the pseudo-terminal: {e}")))?;
        say!("{path}");
        banner(&path);
        let mut logged = Logged::new(transport, self.stations, self.verbose);
        serve_bus(&self.bus(), &mut logged, self.settings, self.stop)
            .map_err(|e| Failure::new(format!("the virtual drive stopped: {e}")))?;
        eprintln!("vfd sim: stopped");
        Ok(())
    }

    /// Serves one client at a time (a device server's line has one master), accepting the
    /// next when it leaves, until the stop flag is set. The drive keeps its state across
    /// clients, as a real drive behind a device server does.
    fn listen(&self, listener: &TcpListener) -> Result<(), Failure> {
        listener
            .set_nonblocking(true)
            .map_err(|e| Failure::new(format!("cannot poll the listening socket: {e}")))?;
        while !self.stop.load(Ordering::Relaxed) {
            let (stream, peer) = match listener.accept() {
                Ok(accepted) => accepted,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    std::thread::sleep(ACCEPT_POLL);
                    continue;
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(Failure::new(format!("cannot accept a client: {e}"))),
            };
            let transport = match TcpTransport::from_stream(stream) {
                Ok(transport) => transport,
                Err(e) => {
                    eprintln!("vfd sim: client {peer} could not be served: {e}");
                    continue;
                }
            };
            eprintln!("vfd sim: client {peer} connected");
            let mut logged = Logged::new(transport, self.stations, self.verbose);
            match serve_bus(&self.bus(), &mut logged, self.settings, self.stop) {
                Ok(()) => break,
                Err(e) => eprintln!("vfd sim: client {peer} left ({e})"),
            }
        }
        Ok(())
    }
}
