//! In-memory transport pairs for tests and simulations: two connected endpoints that
//! pass bytes between threads without any operating-system device.
//!
//! Each [`Transport::send`] is one burst on the simulated line: a receive returns bytes of
//! one burst at most, and [`Transport::last_gap`] tells the silence between bursts, so
//! tests can script a drive that pauses.

use std::collections::VecDeque;
use std::io;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use super::Transport;

/// Bytes sent in one direction and not yet read, with the bursts they were sent in (shared
/// with the asynchronous memory pair, feature `tokio`, so both keep the same semantics).
#[derive(Debug, Default)]
pub(crate) struct Queue {
    /// The bytes, oldest first.
    bytes: VecDeque<u8>,
    /// One entry per send still (partly) unread: bytes left of it, when it was sent, and
    /// whether a receive already returned some of it.
    bursts: VecDeque<Burst>,
    /// When the burst read before the current one was sent (`None`: none since the pair
    /// was made or the input was cleared).
    previous: Option<Instant>,
}

#[derive(Debug, Clone, Copy)]
struct Burst {
    left: usize,
    sent: Instant,
    started: bool,
}

impl Queue {
    /// Adds the bytes of one send as a burst of its own.
    pub(crate) fn push(&mut self, bytes: &[u8]) {
        self.bytes.extend(bytes.iter().copied());
        self.bursts.push_back(Burst {
            left: bytes.len(),
            sent: Instant::now(),
            started: false,
        });
    }

    /// Moves bytes of the oldest unread burst into `buf` (at most one burst, at most
    /// `buf.len()` bytes). Returns how many and the silence before them (as
    /// [`Transport::last_gap`] tells it), or `None` when nothing is queued.
    pub(crate) fn take(&mut self, buf: &mut [u8]) -> Option<(usize, Option<Duration>)> {
        let burst = self.bursts.front_mut()?;
        let count = buf.len().min(burst.left).min(self.bytes.len());
        for (slot, byte) in buf.iter_mut().zip(self.bytes.drain(..count)) {
            *slot = byte;
        }
        let gap = if burst.started {
            Some(Duration::ZERO)
        } else {
            let gap = self
                .previous
                .map(|previous| burst.sent.saturating_duration_since(previous));
            self.previous = Some(burst.sent);
            burst.started = true;
            gap
        };
        burst.left -= count;
        if burst.left == 0 {
            self.bursts.pop_front();
        }
        Some((count, gap))
    }

    /// Drops everything queued and forgets the previous burst.
    pub(crate) fn clear(&mut self) {
        self.bytes.clear();
        self.bursts.clear();
        self.previous = None;
    }

    /// Number of bytes queued.
    pub(crate) fn len(&self) -> usize {
        self.bytes.len()
    }
}

/// One direction of a memory pair: the queued bytes and a condition variable signalled
/// whenever bytes are added.
type Channel = Arc<(Mutex<Queue>, Condvar)>;

/// One end of an in-memory byte pipe created by [`memory_pair`].
///
/// Bytes sent on one endpoint are received, in order, on the other. Endpoints are
/// [`Send`], so each can live on its own thread. When the peer endpoint has been
/// dropped, [`Transport::send`] fails with [`io::ErrorKind::BrokenPipe`] and
/// [`Transport::receive`] returns bytes still buffered, then `Ok(0)` at its deadline.
#[derive(Debug)]
pub struct MemoryTransport {
    incoming: Channel,
    outgoing: Channel,
    last_gap: Option<Duration>,
}

/// Creates two connected in-memory endpoints: bytes sent on either are received on
/// the other.
pub fn memory_pair() -> (MemoryTransport, MemoryTransport) {
    let a_to_b: Channel = Arc::new((Mutex::new(Queue::default()), Condvar::new()));
    let b_to_a: Channel = Arc::new((Mutex::new(Queue::default()), Condvar::new()));
    let a = MemoryTransport {
        incoming: Arc::clone(&b_to_a),
        outgoing: Arc::clone(&a_to_b),
        last_gap: None,
    };
    let b = MemoryTransport {
        incoming: a_to_b,
        outgoing: b_to_a,
        last_gap: None,
    };
    (a, b)
}

/// Locks a queue. A poisoned lock only means another thread panicked while holding it;
/// a byte queue has no invariant that could be broken, so the data is used as is.
pub(crate) fn lock(queue: &Mutex<Queue>) -> MutexGuard<'_, Queue> {
    queue.lock().unwrap_or_else(PoisonError::into_inner)
}

impl MemoryTransport {
    /// Number of bytes received from the peer and not yet read.
    pub fn pending(&self) -> usize {
        lock(&self.incoming.0).len()
    }

    /// Whether the peer endpoint has been dropped. Each channel is shared by exactly
    /// the two endpoints of a pair, so a single owner means the peer is gone.
    fn peer_dropped(&self) -> bool {
        Arc::strong_count(&self.outgoing) < 2
    }
}

impl Transport for MemoryTransport {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.peer_dropped() {
            return Err(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "memory transport: the peer endpoint was dropped",
            ));
        }
        if bytes.is_empty() {
            return Ok(());
        }
        let (queue, ready) = &*self.outgoing;
        lock(queue).push(bytes);
        ready.notify_all();
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        let (queue, ready) = &*self.incoming;
        let mut pending = lock(queue);
        loop {
            if let Some((count, gap)) = pending.take(buf) {
                self.last_gap = gap;
                return Ok(count);
            }
            let remaining = deadline.saturating_duration_since(Instant::now());
            if remaining.is_zero() {
                return Ok(0);
            }
            pending = ready
                .wait_timeout(pending, remaining)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
    }

    fn clear_input(&mut self) -> io::Result<()> {
        lock(&self.incoming.0).clear();
        self.last_gap = None;
        Ok(())
    }

    /// The time between the sends of the burst the last receive read from and of the
    /// burst before it (the pipe itself takes no time).
    fn last_gap(&self) -> Option<Duration> {
        self.last_gap
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::thread;
    use std::time::Duration;

    fn soon() -> Instant {
        Instant::now() + Duration::from_secs(5)
    }

    fn short_deadline() -> Instant {
        Instant::now() + Duration::from_millis(20)
    }

    /// Reads exactly `len` bytes, failing the test if the deadline passes first.
    fn receive_exact(transport: &mut MemoryTransport, len: usize) -> Vec<u8> {
        let deadline = soon();
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
    fn round_trip_both_directions() {
        let (mut a, mut b) = memory_pair();
        a.send(b"hello").unwrap();
        assert_eq!(b.pending(), 5);
        assert_eq!(a.pending(), 0);
        assert_eq!(receive_exact(&mut b, 5), b"hello");
        assert_eq!(b.pending(), 0);

        b.send(&[0x00, 0x0D, 0xFF]).unwrap();
        assert_eq!(receive_exact(&mut a, 3), [0x00, 0x0D, 0xFF]);
    }

    #[test]
    fn receive_respects_small_buffer() {
        let (mut a, mut b) = memory_pair();
        a.send(&[1, 2, 3, 4, 5]).unwrap();
        let mut buf = [0u8; 2];
        assert_eq!(b.receive(&mut buf, soon()).unwrap(), 2);
        assert_eq!(buf, [1, 2]);
        assert_eq!(b.pending(), 3);
        assert_eq!(receive_exact(&mut b, 3), [3, 4, 5]);
    }

    #[test]
    fn receive_wakes_when_other_thread_sends() {
        let (mut a, mut b) = memory_pair();
        let sender = thread::spawn(move || {
            thread::sleep(Duration::from_millis(10));
            a.send(b"late").unwrap();
            a
        });
        assert_eq!(receive_exact(&mut b, 4), b"late");
        drop(sender.join().unwrap());
    }

    #[test]
    fn receive_times_out_with_zero() {
        let (_a, mut b) = memory_pair();
        let mut buf = [0u8; 8];
        assert_eq!(b.receive(&mut buf, short_deadline()).unwrap(), 0);
    }

    #[test]
    fn receive_with_past_deadline_still_returns_buffered_bytes() {
        let (mut a, mut b) = memory_pair();
        a.send(b"x").unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(b.receive(&mut buf, Instant::now()).unwrap(), 1);
        assert_eq!(buf[0], b'x');
    }

    #[test]
    fn clear_input_drops_pending_bytes() {
        let (mut a, mut b) = memory_pair();
        a.send(b"stale").unwrap();
        assert_eq!(b.pending(), 5);
        b.clear_input().unwrap();
        assert_eq!(b.pending(), 0);
        let mut buf = [0u8; 8];
        assert_eq!(b.receive(&mut buf, short_deadline()).unwrap(), 0);

        a.send(b"fresh").unwrap();
        assert_eq!(receive_exact(&mut b, 5), b"fresh");
    }

    #[test]
    fn send_fails_with_broken_pipe_after_peer_drops() {
        let (mut a, b) = memory_pair();
        drop(b);
        let err = a.send(b"anyone?").unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::BrokenPipe);
    }

    #[test]
    fn receive_after_peer_drops_returns_buffered_then_zero() {
        let (mut a, mut b) = memory_pair();
        b.send(b"bye").unwrap();
        drop(b);
        assert_eq!(receive_exact(&mut a, 3), b"bye");
        let mut buf = [0u8; 8];
        assert_eq!(a.receive(&mut buf, short_deadline()).unwrap(), 0);
    }

    #[test]
    fn a_receive_returns_one_burst_at_most_and_tells_the_gap_before_it() {
        let (mut a, mut b) = memory_pair();
        a.send(b"one").unwrap();
        thread::sleep(Duration::from_millis(20));
        a.send(b"two").unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(b.receive(&mut buf, soon()).unwrap(), 3);
        assert_eq!(&buf[..3], b"one");
        assert_eq!(b.last_gap(), None, "nothing came before the first burst");
        let mut small = [0u8; 2];
        assert_eq!(b.receive(&mut small, soon()).unwrap(), 2);
        assert!(b.last_gap().unwrap() >= Duration::from_millis(20));
        assert_eq!(b.receive(&mut small, soon()).unwrap(), 1);
        assert_eq!(
            b.last_gap(),
            Some(Duration::ZERO),
            "the rest of the same burst"
        );
    }

    #[test]
    fn endpoints_are_send() {
        fn assert_send<T: Send>() {}
        assert_send::<MemoryTransport>();
    }
}
