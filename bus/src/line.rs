//! A byte line to the drives as a program opens it: a serial port, a pseudo-terminal, a TCP
//! connection to a serial device server, or any other [`Transport`] (an in-memory pair, a
//! line that prints its frames). A [`crate::Bus`] owns one and lends it to the station that
//! speaks next; a station's master holds [`Line::Away`] meanwhile.

use crate::SetupError;
#[cfg(all(unix, feature = "pty"))]
use std::path::Path;
use std::time::{Duration, Instant};
use vfd_runtime::serial::SerialSettings;
#[cfg(all(unix, feature = "pty"))]
use vfd_runtime::transport::PtyTransport;
use vfd_runtime::transport::{SerialTransport, TcpTransport, Transport, TCP_SCHEME};

/// A byte line to the drives.
pub enum Line {
    /// A serial port.
    Serial(SerialTransport),
    /// A serial device server reached over TCP.
    Tcp(TcpTransport),
    /// A terminal device such as a pseudo-terminal.
    #[cfg(all(unix, feature = "pty"))]
    Pty(PtyTransport),
    /// Any other transport: an in-memory line, a virtual drive in-process, a line that
    /// prints what it carries.
    Other(Box<dyn Transport + Send>),
    /// No line: the bus that owns it has lent it to another station (or it is closed).
    /// Sending or receiving fails with [`std::io::ErrorKind::NotConnected`].
    Away,
}

impl std::fmt::Debug for Line {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Line::Serial(_) => "Line::Serial",
            Line::Tcp(_) => "Line::Tcp",
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(_) => "Line::Pty",
            Line::Other(_) => "Line::Other",
            Line::Away => "Line::Away",
        })
    }
}

impl Line {
    /// `transport` as a line.
    pub fn other(transport: impl Transport + Send + 'static) -> Line {
        Line::Other(Box::new(transport))
    }

    /// Whether this is a line (not [`Line::Away`]).
    pub fn is_here(&self) -> bool {
        !matches!(self, Line::Away)
    }
}

fn away() -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::NotConnected,
        "the line is not with this station (its bus has it)",
    )
}

impl Transport for Line {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match self {
            Line::Serial(t) => t.send(bytes),
            Line::Tcp(t) => t.send(bytes),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.send(bytes),
            Line::Other(t) => t.send(bytes),
            Line::Away => Err(away()),
        }
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        match self {
            Line::Serial(t) => t.receive(buf, deadline),
            Line::Tcp(t) => t.receive(buf, deadline),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.receive(buf, deadline),
            Line::Other(t) => t.receive(buf, deadline),
            Line::Away => Err(away()),
        }
    }
    fn clear_input(&mut self) -> std::io::Result<()> {
        match self {
            Line::Serial(t) => t.clear_input(),
            Line::Tcp(t) => t.clear_input(),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.clear_input(),
            Line::Other(t) => t.clear_input(),
            Line::Away => Err(away()),
        }
    }
    fn last_gap(&self) -> Option<Duration> {
        match self {
            Line::Serial(t) => t.last_gap(),
            Line::Tcp(t) => t.last_gap(),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.last_gap(),
            Line::Other(t) => t.last_gap(),
            Line::Away => None,
        }
    }
    fn allowance(&self) -> Duration {
        match self {
            Line::Serial(t) => t.allowance(),
            Line::Tcp(t) => t.allowance(),
            #[cfg(all(unix, feature = "pty"))]
            Line::Pty(t) => t.allowance(),
            Line::Other(t) => t.allowance(),
            Line::Away => Duration::ZERO,
        }
    }
}

/// Opens `port`: `tcp://HOST:PORT` as a connection to a serial device server, a
/// pseudo-terminal (`/dev/pts/N`) as a terminal device, anything else as a serial port at
/// `settings`.
pub fn open(port: &str, settings: &SerialSettings) -> Result<Line, SetupError> {
    if port.starts_with(TCP_SCHEME) {
        return TcpTransport::connect(port).map(Line::Tcp).map_err(|e| {
            // The error names the address already.
            let error = SetupError::new(e.to_string());
            if e.kind() == std::io::ErrorKind::InvalidInput {
                error.with_hint("write it as tcp://HOST:PORT, e.g. tcp://192.168.1.50:4001")
            } else {
                error.with_hint("is the device server (or `vfd sim --listen`) running, and is that its address and port?")
            }
        });
    }
    #[cfg(all(unix, feature = "pty"))]
    if is_pseudo_terminal(port) {
        return PtyTransport::open_path(Path::new(port))
            .map(Line::Pty)
            .map_err(|e| {
                SetupError::new(format!("cannot open {port}: {e}"))
                    .with_hint("is `vfd sim` still running? it prints the device to use")
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
            SetupError::new(format!("cannot open serial port {port}: {cause}"))
                .with_hint("check the device name (`vfd ports` lists them) and your permissions (on Linux, group dialout)")
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
            let Err(error) = open(name, &settings) else {
                // A machine that has this port: it opened as a serial port, which is the point.
                continue;
            };
            assert!(
                error
                    .message()
                    .starts_with(&format!("cannot open serial port {name}: ")),
                "{name}: {}",
                error.message()
            );
            // The port is named once, not again from the runtime's own message.
            assert_eq!(
                error.message().matches(name).count(),
                1,
                "{}",
                error.message()
            );
        }
        assert!(is_pseudo_terminal("/dev/pts/5"));
    }

    #[test]
    fn a_line_lent_away_refuses_to_carry_anything() {
        let mut line = Line::Away;
        assert!(!line.is_here());
        let error = line.send(&[1, 2, 3]).unwrap_err();
        assert_eq!(error.kind(), std::io::ErrorKind::NotConnected);
        let mut buf = [0u8; 4];
        assert!(line.receive(&mut buf, Instant::now()).is_err());
    }
}
