//! A byte line to a drive as the tool opens it: a serial port, a pseudo-terminal, a TCP
//! connection to a serial device server, traced or not, or shared by the masters of the
//! stations on one bus.

use crate::Failure;
use std::cell::RefCell;
#[cfg(all(unix, feature = "pty"))]
use std::path::Path;
use std::rc::Rc;
use std::time::{Duration, Instant};
use vfd_runtime::meaning::{decode_meaning, Direction};
use vfd_runtime::serial::SerialSettings;
#[cfg(all(unix, feature = "pty"))]
use vfd_runtime::transport::PtyTransport;
use vfd_runtime::transport::{SerialTransport, TcpTransport, Transport, TCP_SCHEME};
use vfd_runtime::{DriveInfo, Protocol};

/// A byte line to a drive: a serial port, a terminal device (pseudo-terminals) or a TCP
/// connection to a serial device server, traced or not.
pub enum Line {
    /// A serial port.
    Serial(SerialTransport),
    /// A serial device server reached over TCP.
    Tcp(TcpTransport),
    /// A terminal device such as a pseudo-terminal.
    #[cfg(all(unix, feature = "pty"))]
    Pty(PtyTransport),
    /// A line several masters share, one after the other (the stations of one bus in
    /// `vfd serve`, each with its own master).
    Shared(SharedLine),
    /// Another line, each frame on it printed (hex and decoded) as it passes.
    #[cfg_attr(not(all(unix, feature = "pty")), allow(dead_code))] // used by the demo only
    Traced(Box<Traced>),
}

/// A line that prints every frame it carries: each request as it is sent, each reply once
/// it is whole.
pub struct Traced {
    /// The line itself.
    pub inner: Line,
    /// The drive, to name registers.
    pub drive: &'static DriveInfo,
    /// The protocol, to decode frames.
    pub protocol: &'static Protocol,
    received: Vec<u8>,
    /// `--trace`: print on standard error with times (else, as the demo shows the line,
    /// on standard output).
    stderr: bool,
}

impl Traced {
    /// `inner`, traced.
    #[cfg_attr(not(all(unix, feature = "pty")), allow(dead_code))] // used by the demo only
    pub fn line(inner: Line, drive: &'static DriveInfo, protocol: &'static Protocol) -> Line {
        Line::Traced(Box::new(Traced {
            inner,
            drive,
            protocol,
            received: Vec::new(),
            stderr: false,
        }))
    }

    /// `inner`, traced on standard error with times (`--trace`).
    pub fn on_stderr(inner: Line, drive: &'static DriveInfo, protocol: &'static Protocol) -> Line {
        crate::trace::start();
        Line::Traced(Box::new(Traced {
            inner,
            drive,
            protocol,
            received: Vec::new(),
            stderr: true,
        }))
    }

    fn print(&self, arrow: &str, direction: Direction, bytes: &[u8]) {
        let hex = vfd_runtime::error::hex(bytes);
        let text = crate::frame_text::frame_text(self.drive, self.protocol, direction, bytes);
        if self.stderr {
            crate::trace::line(format_args!("{arrow} {hex}  [{text}]"));
        } else {
            crate::out::say!("    {arrow} {hex}  [{text}]");
        }
    }

    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        if self.stderr && !self.received.is_empty() {
            // Bytes that never made a whole reply (noise, a garbled or partial reply).
            let hex = vfd_runtime::error::hex(&self.received);
            crate::trace::line(format_args!("<- {hex}  [not a whole reply]"));
        }
        self.received.clear();
        self.print("->", Direction::Request, bytes);
        self.inner.send(bytes)
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        self.received.extend_from_slice(&buf[..got]);
        if got > 0 && decode_meaning(self.protocol, Direction::Reply, &self.received).is_ok() {
            let reply = std::mem::take(&mut self.received);
            self.print("<-", Direction::Reply, &reply);
        }
        Ok(got)
    }
}

impl Transport for Line {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match self {
            Line::Serial(t) => t.send(bytes),
            Line::Tcp(t) => t.send(bytes),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.send(bytes),
            Line::Traced(t) => t.send(bytes),
            Line::Shared(t) => t.0.borrow_mut().send(bytes),
        }
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        match self {
            Line::Serial(t) => t.receive(buf, deadline),
            Line::Tcp(t) => t.receive(buf, deadline),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.receive(buf, deadline),
            Line::Traced(t) => t.receive(buf, deadline),
            Line::Shared(t) => t.0.borrow_mut().receive(buf, deadline),
        }
    }
    fn clear_input(&mut self) -> std::io::Result<()> {
        match self {
            Line::Serial(t) => t.clear_input(),
            Line::Tcp(t) => t.clear_input(),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.clear_input(),
            Line::Traced(t) => t.inner.clear_input(),
            Line::Shared(t) => t.0.borrow_mut().clear_input(),
        }
    }
    fn last_gap(&self) -> Option<Duration> {
        match self {
            Line::Serial(t) => t.last_gap(),
            Line::Tcp(t) => t.last_gap(),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.last_gap(),
            Line::Traced(t) => t.inner.last_gap(),
            Line::Shared(t) => t.0.borrow().last_gap(),
        }
    }
    fn allowance(&self) -> Duration {
        match self {
            Line::Serial(t) => t.allowance(),
            Line::Tcp(t) => t.allowance(),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.allowance(),
            Line::Traced(t) => t.inner.allowance(),
            Line::Shared(t) => t.0.borrow().allowance(),
        }
    }
}

/// One line shared by several masters on one thread, one exchange at a time: each station
/// of a bus has its own master (its own protocol state), all sending on the same port.
#[derive(Clone)]
pub struct SharedLine(Rc<RefCell<Line>>);

impl SharedLine {
    /// `line`, to be shared.
    pub fn new(line: Line) -> SharedLine {
        SharedLine(Rc::new(RefCell::new(line)))
    }
}

/// Opens `port`: `tcp://HOST:PORT` as a connection to a serial device server, a
/// pseudo-terminal (`/dev/pts/N`) as a terminal device, anything else as a serial port at
/// `settings`.
pub fn open_line(port: &str, settings: &SerialSettings) -> Result<Line, Failure> {
    if port.starts_with(TCP_SCHEME) {
        return TcpTransport::connect(port).map(Line::Tcp).map_err(|e| {
            // The error names the address already.
            let failure = Failure::new(e.to_string());
            if e.kind() == std::io::ErrorKind::InvalidInput {
                failure.hint("write it as tcp://HOST:PORT, e.g. tcp://192.168.1.50:4001")
            } else {
                failure.hint("is the device server (or `vfd sim --listen`) running, and is that its address and port?")
            }
        });
    }
    #[cfg(all(unix, feature = "pty"))]
    if is_pseudo_terminal(port) {
        return PtyTransport::open_path(Path::new(port))
            .map(Line::Pty)
            .map_err(|e| {
                Failure::new(format!("cannot open {port}: {e}"))
                    .hint("is `vfd sim` still running? it prints the device to use")
            });
    }
    SerialTransport::open(port, settings)
        .map(Line::Serial)
        .map_err(|e| {
            // The runtime's message names the port already; say it once.
            let message = e.to_string();
            let cause = message
                .strip_prefix(&format!("serial port {port}: cannot open: "))
                .unwrap_or(&message);
            Failure::new(format!("cannot open serial port {port}: {cause}"))
                .hint("check the device name (`vfd ports` lists them) and your permissions (on Linux, group dialout)")
        })
}

/// A Unix pseudo-terminal (`/dev/pts/N`, BSD `/dev/ttypN`), opened as a terminal device;
/// every other name (`/dev/ttyUSB0`, `COM3`, `\\.\COM12`) is a serial port.
#[cfg_attr(not(all(unix, feature = "pty")), allow(dead_code))]
fn is_pseudo_terminal(port: &str) -> bool {
    let named = |name: &str| name.starts_with("/dev/pts/") || name.starts_with("/dev/ttyp");
    // A link to a pseudo-terminal (a stable name for `vfd sim`'s device) opens as one.
    named(port) || std::fs::canonicalize(port).is_ok_and(|target| named(&target.to_string_lossy()))
}

#[cfg(test)]
mod port_names {
    use super::*;

    /// Port names of every system are taken as they are: only Unix pseudo-terminals are
    /// told apart, everything else goes to the serial port (no Unix-path assumptions).
    #[test]
    fn other_systems_port_names_are_serial_ports() {
        for name in [
            "COM3",
            r"\\.\COM12",
            "/dev/ttyUSB0",
            "/dev/cu.usbserial-1420",
        ] {
            assert!(!is_pseudo_terminal(name), "{name}");
            let settings = SerialSettings {
                baud: 9600,
                data_bits: 8,
                parity: vfd_runtime::serial::Parity::Even,
                stop_bits: 1,
            };
            let Err(failure) = open_line(name, &settings) else {
                // A machine that has this port: it opened as a serial port, which is the point.
                continue;
            };
            assert!(
                failure
                    .message
                    .starts_with(&format!("cannot open serial port {name}: ")),
                "{name}: {}",
                failure.message
            );
            // The port is named once, not again from the runtime's own message.
            assert_eq!(
                failure.message.matches(name).count(),
                1,
                "{}",
                failure.message
            );
        }
        assert!(is_pseudo_terminal("/dev/pts/5"));
    }
}
