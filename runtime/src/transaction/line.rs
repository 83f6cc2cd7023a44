//! The line as the masters' shared engine sees it: send, receive until a deadline, drop
//! stale input, sleep. The blocking master's [`Blocking`] line does each at once, so its
//! exchanges run to completion in one poll ([`finish`]); the asynchronous master's line
//! waits on the runtime. One engine, written once, drives both.

use crate::transport::Transport;
use std::future::Future;
use std::io;
use std::pin::pin;
use std::task::{Context, Poll, Waker};
use std::time::{Duration, Instant};

/// The `log` target of what the masters report about the line: frames sent and received
/// at trace level; retries, resyncs, input dropped before a request, the echo learned and
/// page switches at debug level. The runtime never prints; an application collects these
/// records with any `log` implementation.
pub const LOG_TARGET: &str = "vfd_runtime::line";

/// What the exchange engine needs of a line (see [`crate::transport::Transport`] for what
/// each operation means).
pub(crate) trait Line {
    /// Sends all of `bytes`.
    fn send(&mut self, bytes: &[u8]) -> impl Future<Output = io::Result<()>>;
    /// Receives what is available, waiting for at least a byte until `deadline`.
    fn receive(
        &mut self,
        buf: &mut [u8],
        deadline: Instant,
    ) -> impl Future<Output = io::Result<usize>>;
    /// Drops what was received and not read.
    fn clear_input(&mut self) -> impl Future<Output = io::Result<()>>;
    /// Waits `duration`, no less (the silence between frames).
    fn sleep(&mut self, duration: Duration) -> impl Future<Output = ()>;
    /// Waits about `duration` where that saves wake-ups (while a reply crosses the line);
    /// a line whose timer is coarser than the wait may return at once.
    fn nap(&mut self, duration: Duration) -> impl Future<Output = ()>;
    /// The silence before the last bytes received, where the transport can tell.
    fn last_gap(&self) -> Option<Duration>;
    /// The time the transport adds to every reply beyond the line's.
    fn allowance(&self) -> Duration;
}

/// A blocking [`Transport`] as a [`Line`]: every operation is done when its future is
/// first polled.
pub(crate) struct Blocking<'t, T: ?Sized>(pub &'t mut T);

impl<T: Transport + ?Sized> Line for Blocking<'_, T> {
    async fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.0.send(bytes)
    }

    async fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        self.0.receive(buf, deadline)
    }

    async fn clear_input(&mut self) -> io::Result<()> {
        self.0.clear_input()
    }

    async fn sleep(&mut self, duration: Duration) {
        std::thread::sleep(duration);
    }

    async fn nap(&mut self, duration: Duration) {
        std::thread::sleep(duration);
    }

    fn last_gap(&self) -> Option<Duration> {
        self.0.last_gap()
    }

    fn allowance(&self) -> Duration {
        self.0.allowance()
    }
}

/// Runs `future` to its end on this thread. Meant for the engine over a [`Blocking`] line,
/// which never waits on anything but the thread itself, so the future is ready at the first
/// poll; should it not be, it is polled again until it is.
pub(crate) fn finish<F: Future>(future: F) -> F::Output {
    let mut future = pin!(future);
    let mut context = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(output) = future.as_mut().poll(&mut context) {
            return output;
        }
        std::thread::yield_now();
    }
}
