//! Byte transports a transaction runs over: real serial ports, pseudo-terminals and
//! in-memory pipes.

use std::io;
use std::time::Instant;

mod memory;
mod pty;
mod serial_port;

pub use memory::{memory_pair, MemoryTransport};
pub use pty::{PseudoTerminal, PtyTransport};
pub use serial_port::SerialTransport;

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
}
