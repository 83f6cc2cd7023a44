//! Raw serial-over-TCP transport for serial device servers ("RTU over TCP"): the same
//! frames as on the serial line, with no header added (not Modbus TCP's MBAP).
//!
//! A serial device server (a "serial-to-Ethernet converter") puts the bytes a TCP client
//! sends on its RS-485 line and sends back what arrives from the line. The line's settings
//! (baud rate, parity) are configured in the device server; the master still uses them for
//! its timing, and adds a network allowance ([`NETWORK_ALLOWANCE`]) to every reply timeout.

use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

use super::Transport;

/// What the network between the master and a device server adds to every reply: the
/// round trip plus the device server's own buffering of the serial line (most gather
/// bytes for a few milliseconds before sending a packet). Adjust it with
/// [`TcpTransport::with_allowance`] for slow links (a VPN, a mobile network).
pub const NETWORK_ALLOWANCE: Duration = Duration::from_millis(50);

/// How long [`TcpTransport::connect`] (and each reconnection) waits for the device server
/// to accept the connection. Adjust it with [`TcpTransport::with_connect_timeout`].
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// How long a `send` may wait for the operating system to accept the bytes.
const SEND_TIMEOUT: Duration = Duration::from_secs(2);

/// The URL scheme a TCP line is written with (`tcp://HOST:PORT`).
pub const SCHEME: &str = "tcp://";

/// A [`Transport`] over a TCP connection carrying the serial line's bytes unchanged.
///
/// `receive` waits at most until its deadline (`set_read_timeout`); `clear_input` drains
/// what has arrived without blocking. When the device server closes the connection (end of
/// stream, a reset, a broken pipe) the call that notices it fails with an [`io::Error`]
/// naming the address (kind [`io::ErrorKind::ConnectionAborted`] for a close), the line is
/// silent (`receive` returns nothing at its deadline) and the next `send` connects again. A connection found closed while idle (device servers drop idle
/// clients) is reopened by that `send` without an error. A transport made from an accepted
/// stream ([`TcpTransport::from_stream`], the serving side) cannot reconnect.
#[derive(Debug)]
pub struct TcpTransport {
    /// `tcp://HOST:PORT`, for messages.
    name: String,
    /// Where to reconnect to; empty for an accepted stream.
    addrs: Vec<SocketAddr>,
    /// The open connection; `None` after it was found closed.
    stream: Option<TcpStream>,
    connect_timeout: Duration,
    allowance: Duration,
}

impl TcpTransport {
    /// Connects to the device server at `addr`, written `HOST:PORT` or `tcp://HOST:PORT`
    /// (`192.168.1.50:4001`, `tcp://[::1]:5020`, `tcp://gateway.local:4001`), waiting at most
    /// [`CONNECT_TIMEOUT`] for each address the name resolves to.
    ///
    /// Fails with [`io::ErrorKind::InvalidInput`] for an address that is not `HOST:PORT`
    /// or does not resolve, and with the connection's error (e.g.
    /// [`io::ErrorKind::ConnectionRefused`]: nothing listens there) naming the address.
    pub fn connect(addr: &str) -> io::Result<TcpTransport> {
        TcpTransport::connect_timeout(addr, CONNECT_TIMEOUT)
    }

    /// [`TcpTransport::connect`] waiting at most `timeout` for the connection.
    pub fn connect_timeout(addr: &str, timeout: Duration) -> io::Result<TcpTransport> {
        let (name, addrs) = resolve(addr)?;
        let mut transport = TcpTransport {
            name,
            addrs,
            stream: None,
            connect_timeout: timeout,
            allowance: NETWORK_ALLOWANCE,
        };
        transport.reconnect()?;
        Ok(transport)
    }

    /// Serves over a connection already made (the serving side: a client accepted by a
    /// listener). It cannot reconnect: once the client leaves, every call fails.
    pub fn from_stream(stream: TcpStream) -> io::Result<TcpTransport> {
        let name = match stream.peer_addr() {
            Ok(peer) => format!("{SCHEME}{peer}"),
            Err(_) => format!("{SCHEME}<unknown peer>"),
        };
        stream.set_nonblocking(false)?;
        stream.set_nodelay(true)?;
        stream.set_write_timeout(Some(SEND_TIMEOUT))?;
        Ok(TcpTransport {
            name,
            addrs: Vec::new(),
            stream: Some(stream),
            connect_timeout: CONNECT_TIMEOUT,
            allowance: NETWORK_ALLOWANCE,
        })
    }

    /// The same transport adding `allowance` to every reply timeout instead of
    /// [`NETWORK_ALLOWANCE`].
    #[must_use]
    pub fn with_allowance(mut self, allowance: Duration) -> TcpTransport {
        self.allowance = allowance;
        self
    }

    /// The same transport waiting at most `timeout` when it reconnects.
    #[must_use]
    pub fn with_connect_timeout(mut self, timeout: Duration) -> TcpTransport {
        self.connect_timeout = timeout;
        self
    }

    /// `tcp://HOST:PORT` of the other end, as messages name it.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether a connection is open (`false` after one was found closed, until the next
    /// `send` reconnects).
    pub fn is_connected(&self) -> bool {
        self.stream.is_some()
    }

    /// Opens a new connection to the first address that accepts one.
    fn reconnect(&mut self) -> io::Result<()> {
        self.stream = None;
        if self.addrs.is_empty() {
            return Err(io::Error::new(
                io::ErrorKind::NotConnected,
                format!(
                    "{}: the client left; a connection accepted from it cannot be reopened",
                    self.name
                ),
            ));
        }
        let mut last = None;
        for addr in &self.addrs {
            match TcpStream::connect_timeout(addr, self.connect_timeout) {
                Ok(stream) => {
                    stream
                        .set_nodelay(true)
                        .map_err(|e| self.wrap("TCP_NODELAY", e))?;
                    stream
                        .set_write_timeout(Some(SEND_TIMEOUT))
                        .map_err(|e| self.wrap("write timeout", e))?;
                    self.stream = Some(stream);
                    return Ok(());
                }
                Err(err) => last = Some(err),
            }
        }
        let err = last.unwrap_or_else(|| io::Error::from(io::ErrorKind::NotConnected));
        Err(connect_error(&self.name, err, self.connect_timeout))
    }

    /// Adds the address and the failed action to an I/O error.
    fn wrap(&self, action: &str, err: io::Error) -> io::Error {
        io::Error::new(err.kind(), format!("{}: {action}: {err}", self.name))
    }

    /// Forgets the connection after `err` ended it, and says so.
    fn dropped(&mut self, err: io::Error) -> io::Error {
        self.stream = None;
        self.wrap("the connection was lost", err)
    }

    /// Forgets the connection the other end closed, and says so.
    fn closed(&mut self) -> io::Error {
        self.stream = None;
        let who = if self.addrs.is_empty() {
            "the client"
        } else {
            "the device server"
        };
        io::Error::new(
            io::ErrorKind::ConnectionAborted,
            format!("{}: the connection was closed by {who}", self.name),
        )
    }

    fn not_connected(&self) -> io::Error {
        io::Error::new(
            io::ErrorKind::NotConnected,
            format!(
                "{}: not connected (the connection was closed; the next send reconnects)",
                self.name
            ),
        )
    }
}

/// `tcp://HOST:PORT` for `addr` (written with or without the scheme), and the addresses it
/// resolves to; an [`io::ErrorKind::InvalidInput`] error naming it when it is not an
/// address or resolves to none.
pub(crate) fn resolve(addr: &str) -> io::Result<(String, Vec<SocketAddr>)> {
    let host_port = addr.strip_prefix(SCHEME).unwrap_or(addr);
    let name = format!("{SCHEME}{host_port}");
    let addrs: Vec<SocketAddr> = host_port
        .to_socket_addrs()
        .map_err(|err| {
            io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{name}: not a reachable HOST:PORT address: {err}"),
            )
        })?
        .collect();
    if addrs.is_empty() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{name}: the host name resolves to no address"),
        ));
    }
    Ok((name, addrs))
}

/// The error for a connection to `name` that failed with `err`, saying why in words.
pub(crate) fn connect_error(name: &str, err: io::Error, timeout: Duration) -> io::Error {
    let why = match err.kind() {
        io::ErrorKind::ConnectionRefused => {
            "the connection was refused (nothing listens on that port)".to_owned()
        }
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock => format!(
            "no answer within {} ms (is the device server on and reachable?)",
            timeout.as_millis()
        ),
        _ => err.to_string(),
    };
    io::Error::new(err.kind(), format!("{name}: cannot connect: {why}"))
}

/// Reads what is there now from `stream`, without waiting.
fn read_now(stream: &mut TcpStream, buf: &mut [u8]) -> io::Result<usize> {
    stream.set_nonblocking(true)?;
    let result = stream.read(buf);
    stream.set_nonblocking(false)?;
    result
}

impl Transport for TcpTransport {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.stream.is_none() {
            self.reconnect()?;
        }
        let Some(stream) = self.stream.as_mut() else {
            return Err(self.not_connected());
        };
        match stream.write_all(bytes).and_then(|()| stream.flush()) {
            Ok(()) => Ok(()),
            Err(err) => Err(self.dropped(err)),
        }
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        loop {
            let Some(stream) = self.stream.as_mut() else {
                if self.addrs.is_empty() {
                    return Err(self.not_connected());
                }
                // Closed, and reopened by the next send: nothing can arrive until then, so
                // the line is silent (the master looks at it before it sends).
                let remaining = deadline.saturating_duration_since(Instant::now());
                std::thread::sleep(remaining);
                return Ok(0);
            };
            let remaining = deadline.saturating_duration_since(Instant::now());
            let result = if remaining.is_zero() {
                read_now(stream, buf)
            } else {
                match stream.set_read_timeout(Some(remaining)) {
                    Ok(()) => stream.read(buf),
                    Err(err) => Err(err),
                }
            };
            match result {
                Ok(0) => return Err(self.closed()),
                Ok(count) => return Ok(count),
                Err(err)
                    if matches!(
                        err.kind(),
                        io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                    ) =>
                {
                    if remaining.is_zero() {
                        return Ok(0);
                    }
                    // Woke at (or a hair before) the deadline: one look without waiting.
                }
                Err(err) if err.kind() == io::ErrorKind::Interrupted => {}
                Err(err) => return Err(self.dropped(err)),
            }
        }
    }

    fn clear_input(&mut self) -> io::Result<()> {
        let mut scratch = [0u8; 512];
        while let Some(stream) = self.stream.as_mut() {
            match read_now(stream, &mut scratch) {
                Ok(0) => {
                    // Closed while idle: the next send reconnects (the serving side has
                    // nothing to reconnect to and says so).
                    return if self.addrs.is_empty() {
                        Err(self.closed())
                    } else {
                        self.stream = None;
                        Ok(())
                    };
                }
                Ok(_) => {}
                Err(err) if err.kind() == io::ErrorKind::WouldBlock => return Ok(()),
                Err(err) if err.kind() == io::ErrorKind::Interrupted => {}
                Err(err) => {
                    return if self.addrs.is_empty() {
                        Err(self.dropped(err))
                    } else {
                        self.stream = None;
                        Ok(())
                    };
                }
            }
        }
        Ok(())
    }

    fn allowance(&self) -> Duration {
        self.allowance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;
    use std::thread;

    fn listener() -> (TcpListener, String) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = format!("tcp://{}", listener.local_addr().unwrap());
        (listener, addr)
    }

    /// Reads until `len` bytes arrived or a second passed.
    fn receive_exact(transport: &mut TcpTransport, len: usize) -> Vec<u8> {
        let deadline = Instant::now() + Duration::from_secs(2);
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        while out.len() < len {
            let n = transport.receive(&mut buf, deadline).unwrap();
            assert!(n > 0, "timed out after {} of {len} bytes", out.len());
            out.extend_from_slice(&buf[..n]);
        }
        out
    }

    #[test]
    fn a_round_trip_carries_the_bytes_unchanged() {
        let (listener, addr) = listener();
        let peer = thread::spawn(move || {
            let (mut stream, _) = listener.accept().unwrap();
            let mut request = [0u8; 8];
            stream.read_exact(&mut request).unwrap();
            // An echo with every byte value after it: no header, no escaping.
            stream.write_all(&request).unwrap();
            stream.write_all(&(0u8..=255).collect::<Vec<_>>()).unwrap();
            request
        });
        let mut transport = TcpTransport::connect(&addr).unwrap();
        let request = [0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A];
        transport.send(&request).unwrap();
        let got = receive_exact(&mut transport, 8 + 256);
        assert_eq!(got[..8], request);
        assert_eq!(got[8..], (0u8..=255).collect::<Vec<_>>()[..]);
        assert_eq!(peer.join().unwrap(), request);
        assert_eq!(transport.allowance(), NETWORK_ALLOWANCE);
        let slower = transport.with_allowance(Duration::from_millis(200));
        assert_eq!(slower.allowance(), Duration::from_millis(200));
    }

    #[test]
    fn receive_keeps_its_deadline_when_the_peer_is_silent() {
        let (listener, addr) = listener();
        let mut transport = TcpTransport::connect(&addr).unwrap();
        let (_silent, _) = listener.accept().unwrap();
        transport.send(&[0x01]).unwrap();
        let start = Instant::now();
        let mut buf = [0u8; 16];
        let got = transport
            .receive(&mut buf, start + Duration::from_millis(80))
            .unwrap();
        let waited = start.elapsed();
        assert_eq!(got, 0);
        assert!(
            waited >= Duration::from_millis(75),
            "returned early: {waited:?}"
        );
        assert!(waited < Duration::from_millis(400), "overran: {waited:?}");
        // A deadline already passed looks without waiting.
        let start = Instant::now();
        assert_eq!(transport.receive(&mut buf, start).unwrap(), 0);
        assert!(start.elapsed() < Duration::from_millis(50));
        assert!(transport.is_connected());
    }

    #[test]
    fn clear_input_drops_what_arrived_without_blocking() {
        let (listener, addr) = listener();
        let mut transport = TcpTransport::connect(&addr).unwrap();
        let (mut peer, _) = listener.accept().unwrap();
        peer.write_all(b"stale reply").unwrap();
        thread::sleep(Duration::from_millis(50));
        let start = Instant::now();
        transport.clear_input().unwrap();
        assert!(start.elapsed() < Duration::from_millis(50));
        peer.write_all(b"fresh").unwrap();
        assert_eq!(receive_exact(&mut transport, 5), b"fresh");
    }

    #[test]
    fn a_dropped_connection_is_an_error_naming_the_address_and_the_next_send_reconnects() {
        let (listener, addr) = listener();
        let mut transport = TcpTransport::connect(&addr).unwrap();
        // The device server takes the request and hangs up.
        let (mut first, _) = listener.accept().unwrap();
        transport.send(b"ping").unwrap();
        let mut request = [0u8; 4];
        first.read_exact(&mut request).unwrap();
        drop(first);
        let mut buf = [0u8; 16];
        let err = transport
            .receive(&mut buf, Instant::now() + Duration::from_secs(2))
            .unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::ConnectionAborted, "{err}");
        assert_eq!(
            err.to_string(),
            format!("{addr}: the connection was closed by the device server")
        );
        assert!(!transport.is_connected());
        // Until the next send, the line is silent until the deadline.
        let start = Instant::now();
        let got = transport
            .receive(&mut buf, start + Duration::from_millis(30))
            .unwrap();
        assert_eq!(got, 0);
        assert!(start.elapsed() >= Duration::from_millis(25));
        // The next exchange connects again.
        let peer = thread::spawn(move || {
            let (mut second, _) = listener.accept().unwrap();
            let mut request = [0u8; 4];
            second.read_exact(&mut request).unwrap();
            second.write_all(b"pong").unwrap();
            request
        });
        transport.send(b"ping").unwrap();
        assert_eq!(receive_exact(&mut transport, 4), b"pong");
        assert_eq!(&peer.join().unwrap(), b"ping");
    }

    #[test]
    fn a_connection_closed_while_idle_is_reopened_by_the_next_send() {
        let (listener, addr) = listener();
        let mut transport = TcpTransport::connect(&addr).unwrap();
        drop(listener.accept().unwrap());
        thread::sleep(Duration::from_millis(50));
        transport.clear_input().unwrap();
        assert!(!transport.is_connected());
        let peer = thread::spawn(move || {
            let (mut again, _) = listener.accept().unwrap();
            let mut request = [0u8; 2];
            again.read_exact(&mut request).unwrap();
            request
        });
        transport.send(b"hi").unwrap();
        assert_eq!(&peer.join().unwrap(), b"hi");
    }

    #[test]
    fn a_refused_connection_names_the_address() {
        let (listener, addr) = listener();
        drop(listener);
        let err = TcpTransport::connect(&addr).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::ConnectionRefused, "{err}");
        assert_eq!(
            err.to_string(),
            format!(
                "{addr}: cannot connect: the connection was refused (nothing listens on that port)"
            )
        );
    }

    #[test]
    fn an_address_without_a_port_is_invalid_input() {
        let err = TcpTransport::connect("tcp://127.0.0.1").unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput, "{err}");
        assert!(
            err.to_string()
                .starts_with("tcp://127.0.0.1: not a reachable HOST:PORT address"),
            "{err}"
        );
    }

    #[test]
    fn an_accepted_stream_cannot_reconnect() {
        let (listener, addr) = listener();
        let client = TcpTransport::connect(&addr).unwrap();
        let (stream, _) = listener.accept().unwrap();
        let mut served = TcpTransport::from_stream(stream).unwrap();
        drop(client);
        let mut buf = [0u8; 4];
        let err = served
            .receive(&mut buf, Instant::now() + Duration::from_secs(2))
            .unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::ConnectionAborted, "{err}");
        assert!(
            err.to_string()
                .ends_with("the connection was closed by the client"),
            "{err}"
        );
        let err = served.send(b"x").unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::NotConnected, "{err}");
    }
}
