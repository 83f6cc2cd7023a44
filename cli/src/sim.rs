//! `vfd sim`: the virtual drive of any described drive, served on a pseudo-terminal (or,
//! with `--listen HOST:PORT`, over TCP as a serial device server would: raw frames, one
//! client at a time) until SIGINT or SIGTERM. The device path (`tcp://HOST:PORT` with the
//! bound port) is the first line of output, so scripts and tests can read it; `--verbose`
//! logs each exchange (hex and decoded) on standard error.

use crate::bus::ParityArg;
use crate::frame_text::frame_text;
use crate::out::say;
use crate::{lookup, Failure};
use std::io::Write;
use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use vfd_runtime::meaning::Direction;
use vfd_runtime::serial::SerialSettings;
#[cfg(all(unix, feature = "pty"))]
use vfd_runtime::transport::PseudoTerminal;
use vfd_runtime::transport::{TcpTransport, Transport};
use vfd_runtime::virtual_drive::{serve, Fault, Simulator};
use vfd_runtime::Protocol;

/// Options of `vfd sim`.
#[derive(Debug, Clone, clap::Args)]
pub struct SimArgs {
    /// Drive id (`vfd list`) or the path of a drive file (./my_drive.yaml).
    #[arg(long, short = 'd')]
    pub drive: String,
    /// Protocol id (default: the drive's first protocol).
    #[arg(long, short = 'p')]
    pub protocol: Option<String>,
    /// Station address the drive answers (default: the protocol's lowest, at least 1).
    #[arg(long, value_name = "N")]
    pub address: Option<u8>,
    /// Baud rate the timing follows (default: the drive's factory setting).
    #[arg(long)]
    pub baud: Option<u32>,
    /// Parity the timing follows (default: the drive's factory setting).
    #[arg(long, value_enum)]
    pub parity: Option<ParityArg>,
    /// Log each exchange, in hex and decoded, on standard error.
    #[arg(long, short = 'v')]
    pub verbose: bool,
    /// Misbehave: each fault spoils the next reply (noise: every reply), in the order given.
    #[arg(long, value_enum, value_name = "FAULT")]
    pub fault: Vec<FaultArg>,
    /// Start tripped with this trip code.
    #[arg(long, value_name = "CODE")]
    pub trip: Option<u16>,
    /// The drive's port it serves, for drives with several: that port's command word and
    /// frequency command act (default: the registers as the behaviour model names them).
    #[arg(long, value_name = "PORT")]
    pub port_kind: Option<String>,
    /// The protocol's variant the drive is set to, for protocols with several (Eaton:
    /// `cr_lf`): the register that selects it is set so (07-06 = 2), as if on the panel
    /// before power-on. Default: the drive's factory setting.
    #[arg(long, value_name = "VARIANT")]
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

/// Serves the virtual drive until SIGINT or SIGTERM.
pub fn run(args: &SimArgs) -> Result<(), Failure> {
    let drive = lookup::drive(&args.drive)?;
    let protocol = lookup::protocol(drive, args.protocol.as_deref())?;
    let settings = crate::bus::line_settings(drive, args.baud, args.parity);
    let sim = Simulator::new(drive);
    let address = args
        .address
        .unwrap_or_else(|| protocol.address_range.0.max(1));
    sim.lock().set_address(address);
    if let Some(port) = lookup::port(drive, args.port_kind.as_deref())? {
        sim.lock().set_port(port.id);
    }
    let protocol = lookup::variant(protocol, args.variant.as_deref())?;
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
    let stop = crate::watch::stop_flag()?;
    let banner = |place: &str| {
        eprintln!(
            "vfd sim: virtual {} ({}) speaking {}{} as station {address} on {place}, {} baud; Ctrl-C stops",
            drive.id,
            drive.model,
            protocol.id,
            args.variant
                .as_deref()
                .map_or_else(String::new, |id| format!(" ({id})")),
            settings.baud
        );
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
        let serving = Serving {
            sim: &sim,
            drive,
            protocol,
            settings,
            verbose: args.verbose,
            stop: &stop,
        };
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
    serve_on_pty(&sim, drive, protocol, settings, args.verbose, &stop, banner)
}

/// Serves the virtual drive on a new pseudo-terminal until the stop flag is set.
#[cfg(all(unix, feature = "pty"))]
fn serve_on_pty(
    sim: &Simulator,
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static Protocol,
    settings: SerialSettings,
    verbose: bool,
    stop: &AtomicBool,
    banner: impl Fn(&str),
) -> Result<(), Failure> {
    let pty = PseudoTerminal::open()
        .map_err(|e| Failure::new(format!("cannot open a pseudo-terminal: {e}")))?;
    let path = pty.slave_path().display().to_string();
    let transport = pty
        .master()
        .map_err(|e| Failure::new(format!("cannot use the pseudo-terminal: {e}")))?;
    say!("{path}");
    banner(&path);
    let mut logged = Logged {
        inner: transport,
        drive,
        protocol,
        verbose,
        received: Vec::new(),
        start: Instant::now(),
    };
    serve(sim, protocol, &mut logged, settings, stop)
        .map_err(|e| Failure::new(format!("the virtual drive stopped: {e}")))?;
    eprintln!("vfd sim: stopped");
    Ok(())
}

/// How long the listening loop waits between looks for a client and at the stop flag.
const ACCEPT_POLL: Duration = Duration::from_millis(20);

/// What serving over TCP needs: the virtual drive, how it speaks, and when to stop.
struct Serving<'a> {
    sim: &'a Simulator,
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static Protocol,
    settings: SerialSettings,
    verbose: bool,
    stop: &'a AtomicBool,
}

impl Serving<'_> {
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
            let mut logged = Logged {
                inner: transport,
                drive: self.drive,
                protocol: self.protocol,
                verbose: self.verbose,
                received: Vec::new(),
                start: Instant::now(),
            };
            match serve(
                self.sim,
                self.protocol,
                &mut logged,
                self.settings,
                self.stop,
            ) {
                Ok(()) => break,
                Err(e) => eprintln!("vfd sim: client {peer} left ({e})"),
            }
        }
        Ok(())
    }
}

/// A transport that logs what it carries: the bytes received since the last reply as the
/// request, and each reply, in hex and decoded.
struct Logged<T> {
    inner: T,
    drive: &'static vfd_runtime::DriveInfo,
    protocol: &'static Protocol,
    verbose: bool,
    received: Vec<u8>,
    start: Instant,
}

impl<T: Transport> Logged<T> {
    fn log(&self, direction: Direction, bytes: &[u8]) {
        let _ = writeln!(
            std::io::stderr(),
            "{:>8.3}s {:<7} {}  {}",
            self.start.elapsed().as_secs_f64(),
            direction.as_str(),
            vfd_runtime::error::hex(bytes),
            frame_text(self.drive, self.protocol, direction, bytes)
        );
    }
}

/// The master's follow-up to a reply at the start of `bytes` (`true`: acknowledged), with
/// the station it names and its length.
fn follow_up_at(protocol: &Protocol, bytes: &[u8]) -> Option<(bool, Option<u8>, usize)> {
    protocol
        .commands
        .iter()
        .filter_map(|c| c.follow_up.as_ref())
        .find_map(|f| f.recognise(bytes))
}

impl<T: Transport> Transport for Logged<T> {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        if self.verbose {
            let mut request = std::mem::take(&mut self.received);
            // The master's follow-ups to earlier replies (C, F) come before its request.
            while let Some((sound, address, len)) = follow_up_at(self.protocol, &request) {
                let _ = writeln!(
                    std::io::stderr(),
                    "{:>8.3}s {:<7} {}  {}{}",
                    self.start.elapsed().as_secs_f64(),
                    "follow",
                    vfd_runtime::error::hex(&request[..len]),
                    if sound {
                        "the master acknowledges the reply"
                    } else {
                        "the master asks for the reply again"
                    },
                    address.map_or_else(String::new, |a| format!(", station {a}")),
                );
                request.drain(..len);
            }
            if !request.is_empty() {
                self.log(Direction::Request, &request);
            }
            self.log(Direction::Reply, bytes);
        }
        self.inner.send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if self.verbose {
            self.received.extend_from_slice(&buf[..got]);
            if self.received.len() > 4096 {
                self.received.clear();
            }
        }
        Ok(got)
    }
    fn clear_input(&mut self) -> std::io::Result<()> {
        self.inner.clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }
    fn allowance(&self) -> Duration {
        self.inner.allowance()
    }
}
