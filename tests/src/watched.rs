//! A transport wrapper that counts the master's reads of the line after its first send, so
//! a test can show that a command nobody answers is not waited for without timing anything.

use std::io;
use std::time::{Duration, Instant};
use vfd_runtime::transport::Transport;

/// Passes everything to `inner`, counting [`Transport::receive`] calls made after a send.
#[derive(Debug)]
pub struct Watched<T> {
    inner: T,
    sends: usize,
    receives_after_send: usize,
}

impl<T: Transport> Watched<T> {
    /// Watches `inner`.
    pub fn new(inner: T) -> Watched<T> {
        Watched {
            inner,
            sends: 0,
            receives_after_send: 0,
        }
    }

    /// How many frames were sent.
    pub fn sends(&self) -> usize {
        self.sends
    }

    /// How many times the line was read (waited on) after the first frame was sent.
    pub fn receives_after_send(&self) -> usize {
        self.receives_after_send
    }
}

impl<T: Transport> Transport for Watched<T> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.sends += 1;
        self.inner.send(bytes)
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if self.sends > 0 {
            self.receives_after_send += 1;
        }
        self.inner.receive(buf, deadline)
    }

    fn clear_input(&mut self) -> io::Result<()> {
        self.inner.clear_input()
    }

    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }

    fn allowance(&self) -> Duration {
        self.inner.allowance()
    }
}
