//! Byte transports a transaction runs over: real serial ports, pseudo-terminals, TCP
//! connections to serial device servers and in-memory pipes.
//!
//! The in-memory pipe and TCP ([`TcpTransport`]: raw serial-over-TCP, "RTU over TCP", the
//! serial line's frames unchanged, for serial device servers) are always there. The serial
//! port needs the `serial` feature and the pseudo-terminal the `pty` feature on a Unix
//! system (both features are on by default). The `tokio` feature adds `AsyncTransport` and
//! asynchronous counterparts of the serial port, the pseudo-terminal, TCP and the pipe.

use std::io;
use std::time::{Duration, Instant};

#[cfg(feature = "tokio")]
mod asynchronous;
mod memory;
#[cfg(all(unix, feature = "pty"))]
mod pty;
mod recording;
#[cfg(feature = "serial")]
mod serial_port;
pub(crate) mod tcp;

#[cfg(all(feature = "tokio", unix, feature = "pty"))]
pub use asynchronous::AsyncPtyTransport;
#[cfg(all(feature = "tokio", feature = "serial"))]
pub use asynchronous::AsyncSerialTransport;
#[cfg(feature = "tokio")]
pub use asynchronous::{
    async_memory_pair, AsyncMemoryTransport, AsyncTcpTransport, AsyncTransport,
};
pub use memory::{memory_pair, MemoryTransport};
#[cfg(all(unix, feature = "pty"))]
pub use pty::{PseudoTerminal, PtyTransport};
pub use recording::{Direction, Recording};
#[cfg(feature = "serial")]
pub use serial_port::SerialTransport;
pub use tcp::{TcpTransport, CONNECT_TIMEOUT, NETWORK_ALLOWANCE, SCHEME as TCP_SCHEME};

/// A half-duplex byte pipe to one or more drives.
pub trait Transport {
    /// Sends all of `bytes`.
    fn send(&mut self, bytes: &[u8]) -> io::Result<()>;

    /// Reads whatever bytes are available into `buf`, waiting until at least one byte
    /// arrives or `deadline` passes. Returns `Ok(0)` when the deadline passed with nothing
    /// received. Never blocks past `deadline` by more than the operating system's timer slack.
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize>;

    /// Drops bytes already received and not yet read (stale replies, line noise).
    fn clear_input(&mut self) -> io::Result<()> {
        Ok(())
    }

    /// The silence on the line just before the first byte the last [`Transport::receive`]
    /// returned, when the transport can tell (`Some(Duration::ZERO)`: those bytes followed
    /// earlier ones without a pause). `None` (the default) when it cannot: operating-system
    /// buffers and USB adapters deliver bytes in chunks whose timing says little about the
    /// line. The master uses it to start a new frame after a silence longer than the
    /// protocol allows inside one.
    fn last_gap(&self) -> Option<Duration> {
        None
    }

    /// Time this transport adds to every reply beyond the line's: a network between the
    /// master and a serial device server (RTU over TCP). The master adds it to each reply
    /// timeout; a local port adds nothing (the default).
    fn allowance(&self) -> Duration {
        Duration::ZERO
    }
}

impl<T: Transport + ?Sized> Transport for &mut T {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        (**self).send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        (**self).receive(buf, deadline)
    }
    fn clear_input(&mut self) -> io::Result<()> {
        (**self).clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        (**self).last_gap()
    }
    fn allowance(&self) -> Duration {
        (**self).allowance()
    }
}
