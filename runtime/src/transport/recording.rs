//! A transport wrapper that keeps a log of the line: every frame sent and every chunk
//! received, in order, so a test (or `vfd`'s trace) can compare a whole exchange, page
//! switches and follow-ups included, with a manual's sequence of frames.

use super::Transport;
use std::io;
use std::time::{Duration, Instant};

/// Which way bytes went on the line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// From the master to the drive.
    Sent,
    /// From the drive to the master.
    Received,
}

/// A [`Transport`] that passes everything through to `inner` and logs it.
#[derive(Debug)]
pub struct Recording<T> {
    inner: T,
    log: Vec<(Direction, Vec<u8>)>,
}

impl<T: Transport> Recording<T> {
    /// Logs what goes through `inner`.
    pub fn new(inner: T) -> Recording<T> {
        Recording {
            inner,
            log: Vec::new(),
        }
    }

    /// The frames sent and the bytes received so far, in order; consecutive chunks received
    /// are joined, so each entry is what one side said before the other spoke.
    pub fn log(&self) -> &[(Direction, Vec<u8>)] {
        &self.log
    }

    /// Empties the log.
    pub fn clear(&mut self) {
        self.log.clear();
    }

    /// The wrapped transport.
    pub fn into_inner(self) -> T {
        self.inner
    }
}

impl<T: Transport> Transport for Recording<T> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.inner.send(bytes)?;
        self.log.push((Direction::Sent, bytes.to_vec()));
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if got > 0 {
            match self.log.last_mut() {
                Some((Direction::Received, bytes)) => bytes.extend_from_slice(&buf[..got]),
                _ => self.log.push((Direction::Received, buf[..got].to_vec())),
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::memory_pair;

    /// A transport that adds a network's time to every reply, as TCP does.
    struct Distant(crate::transport::MemoryTransport);

    impl Transport for Distant {
        fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
            self.0.send(bytes)
        }
        fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
            self.0.receive(buf, deadline)
        }
        fn allowance(&self) -> Duration {
            Duration::from_millis(50)
        }
    }

    #[test]
    fn a_recording_keeps_the_allowance_of_what_it_records() {
        let (near, _far) = memory_pair();
        let recording = Recording::new(Distant(near));
        assert_eq!(recording.allowance(), Duration::from_millis(50));
    }
}
