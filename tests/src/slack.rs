//! [`Slack`]: a transport that asks both ends of a test line to allow for a loaded machine.
//!
//! A pseudo-terminal between two threads of one test is as fast as the machine is idle: on a
//! shared machine with a dozen busy threads per core, a reply the drive's thread writes on
//! time can reach the master hundreds of milliseconds late. Wrapped in `Slack`, the master
//! adds the slack to every reply timeout ([`Transport::allowance`]), and the virtual drive's
//! serve loop, which delays a reply past the master's deadline for the `delay` fault, adds
//! it too. Outcomes then depend on the faults the test injects, not on the scheduler.

use std::future::Future;
use std::io;
use std::time::{Duration, Instant};
use vfd_runtime::transport::{AsyncTransport, Transport};

/// What a test on a pseudo-terminal allows for scheduling: far more than an idle machine
/// needs (a few milliseconds), enough for a 2-core machine running other builds and tests.
pub const LOADED_MACHINE: Duration = Duration::from_millis(1000);

/// `T` with `slack` added to what it adds to every reply.
pub struct Slack<T> {
    inner: T,
    slack: Duration,
}

impl<T> Slack<T> {
    /// Wraps `inner`.
    pub fn new(inner: T, slack: Duration) -> Self {
        Slack { inner, slack }
    }
}

impl<T: Transport> Transport for Slack<T> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.inner.send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        self.inner.receive(buf, deadline)
    }
    fn clear_input(&mut self) -> io::Result<()> {
        self.inner.clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }
    fn allowance(&self) -> Duration {
        self.inner.allowance() + self.slack
    }
}

impl<T: AsyncTransport> AsyncTransport for Slack<T> {
    fn send(&mut self, bytes: &[u8]) -> impl Future<Output = io::Result<()>> + Send {
        self.inner.send(bytes)
    }
    fn receive(
        &mut self,
        buf: &mut [u8],
        deadline: Instant,
    ) -> impl Future<Output = io::Result<usize>> + Send {
        self.inner.receive(buf, deadline)
    }
    fn clear_input(&mut self) -> impl Future<Output = io::Result<()>> + Send {
        self.inner.clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }
    fn allowance(&self) -> Duration {
        self.inner.allowance() + self.slack
    }
}
