//! The asynchronous byte transport (feature `tokio`): the same four operations as
//! [`super::Transport`], as futures, for the asynchronous master.
//!
//! A transport is a half-duplex pipe: the master sends a request, then receives until the
//! reply is whole or its deadline passes. Implementations wait without blocking the
//! executor's thread (readiness of a file descriptor or socket, a timer), never past the
//! deadline by more than the timer's resolution.
//!
//! The implementations: [`async_memory_pair`] always, `AsyncSerialTransport` with the
//! `serial` feature too, `AsyncPtyTransport` with the `pty` feature on a Unix system.
//! Those over a device must be made inside a tokio runtime (they register with its
//! reactor).

mod memory;
#[cfg(all(unix, feature = "pty"))]
mod pty;
#[cfg(feature = "serial")]
mod serial_port;
mod tcp;

pub use memory::{async_memory_pair, AsyncMemoryTransport};
#[cfg(all(unix, feature = "pty"))]
pub use pty::AsyncPtyTransport;
#[cfg(feature = "serial")]
pub use serial_port::AsyncSerialTransport;
pub use tcp::AsyncTcpTransport;

use std::future::Future;
use std::io;
use std::time::{Duration, Instant};

/// A half-duplex byte pipe to one or more drives, driven by an asynchronous runtime.
///
/// Its methods mean what those of [`super::Transport`] mean; only the waiting differs.
pub trait AsyncTransport: Send {
    /// Sends all of `bytes`.
    fn send(&mut self, bytes: &[u8]) -> impl Future<Output = io::Result<()>> + Send;

    /// Reads whatever bytes are available into `buf`, waiting until at least one byte
    /// arrives or `deadline` passes. Returns `Ok(0)` when the deadline passed with nothing
    /// received.
    fn receive(
        &mut self,
        buf: &mut [u8],
        deadline: Instant,
    ) -> impl Future<Output = io::Result<usize>> + Send;

    /// Drops bytes already received and not yet read (stale replies, line noise).
    fn clear_input(&mut self) -> impl Future<Output = io::Result<()>> + Send {
        async { Ok(()) }
    }

    /// The silence on the line before the first byte the last receive returned, where the
    /// transport can tell (see [`super::Transport::last_gap`]).
    fn last_gap(&self) -> Option<Duration> {
        None
    }

    /// Time this transport adds to every reply beyond the line's (a network between the
    /// master and a serial device server): the master adds it to each reply timeout (see
    /// [`super::Transport::allowance`]).
    fn allowance(&self) -> Duration {
        Duration::ZERO
    }
}
