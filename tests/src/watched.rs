//! A transport wrapper that counts the master's reads of the line after its first send, and
//! those that came back empty (a deadline passed), so a test can show that a command nobody
//! answers is not waited for, or a reply is found before its timeout, without timing
//! anything.

use std::io;
use std::time::{Duration, Instant};
use vfd_runtime::transport::Transport;

/// Passes everything to `inner`, counting [`Transport::receive`] calls made after a send.
#[derive(Debug)]
pub struct Watched<T> {
    inner: T,
    sends: usize,
    receives_after_send: usize,
    empty_after_send: usize,
}

impl<T: Transport> Watched<T> {
    /// Watches `inner`.
    pub fn new(inner: T) -> Watched<T> {
        Watched {
            inner,
            sends: 0,
            receives_after_send: 0,
            empty_after_send: 0,
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

    /// How many of those reads returned nothing: a read of the line returns empty only once
    /// its deadline has passed, so none means the master never waited one out.
    pub fn empty_receives_after_send(&self) -> usize {
        self.empty_after_send
    }
}

impl<T: Transport> Transport for Watched<T> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.sends += 1;
        self.inner.send(bytes)
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        let after_send = self.sends > 0;
        if after_send {
            self.receives_after_send += 1;
        }
        let got = self.inner.receive(buf, deadline)?;
        if after_send && got == 0 {
            self.empty_after_send += 1;
        }
        Ok(got)
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
