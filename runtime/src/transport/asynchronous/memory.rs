//! The asynchronous in-memory pair for tests: two connected endpoints, as
//! [`crate::transport::memory_pair`] but waiting on tokio's [`Notify`] instead of a
//! condition variable.
//!
//! Each send is one burst on the simulated line: a receive returns bytes of one burst at
//! most, and [`AsyncTransport::last_gap`] tells the silence between bursts (the same
//! queue as the blocking pair keeps them).

use std::io;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::sync::Notify;

use super::AsyncTransport;
use crate::transport::memory::{lock, Queue};

/// One direction of a pair: the queued bytes and a notification raised whenever bytes
/// are added (its stored permit means a send between a look at the queue and the wait
/// that follows is not missed).
#[derive(Debug, Default)]
struct Channel {
    queue: Mutex<Queue>,
    added: Notify,
}

/// One end of an asynchronous in-memory byte pipe created by [`async_memory_pair`].
///
/// Bytes sent on one endpoint are received, in order, on the other. Endpoints are
/// [`Send`]. When the peer endpoint has been dropped, sending fails with
/// [`io::ErrorKind::BrokenPipe`] and receiving returns bytes still buffered, then `Ok(0)`
/// at its deadline.
#[derive(Debug)]
pub struct AsyncMemoryTransport {
    incoming: Arc<Channel>,
    outgoing: Arc<Channel>,
    last_gap: Option<Duration>,
}

/// Creates two connected asynchronous in-memory endpoints: bytes sent on either are
/// received on the other. Needs no runtime to be made; receiving needs tokio's timer.
pub fn async_memory_pair() -> (AsyncMemoryTransport, AsyncMemoryTransport) {
    let a_to_b = Arc::new(Channel::default());
    let b_to_a = Arc::new(Channel::default());
    let a = AsyncMemoryTransport {
        incoming: Arc::clone(&b_to_a),
        outgoing: Arc::clone(&a_to_b),
        last_gap: None,
    };
    let b = AsyncMemoryTransport {
        incoming: a_to_b,
        outgoing: b_to_a,
        last_gap: None,
    };
    (a, b)
}

impl AsyncMemoryTransport {
    /// Number of bytes received from the peer and not yet read.
    pub fn pending(&self) -> usize {
        lock(&self.incoming.queue).len()
    }

    /// Whether the peer endpoint has been dropped (each channel is shared by exactly the
    /// two endpoints of a pair).
    fn peer_dropped(&self) -> bool {
        Arc::strong_count(&self.outgoing) < 2
    }
}

impl AsyncTransport for AsyncMemoryTransport {
    async fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.peer_dropped() {
            return Err(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "memory transport: the peer endpoint was dropped",
            ));
        }
        if bytes.is_empty() {
            return Ok(());
        }
        lock(&self.outgoing.queue).push(bytes);
        self.outgoing.added.notify_one();
        Ok(())
    }

    async fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        let deadline = tokio::time::Instant::from_std(deadline);
        loop {
            // The guard is dropped before the wait, so the future stays `Send`.
            let taken = lock(&self.incoming.queue).take(buf);
            if let Some((count, gap)) = taken {
                self.last_gap = gap;
                return Ok(count);
            }
            let added = self.incoming.added.notified();
            if tokio::time::timeout_at(deadline, added).await.is_err() {
                return Ok(0);
            }
        }
    }

    async fn clear_input(&mut self) -> io::Result<()> {
        lock(&self.incoming.queue).clear();
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

    fn soon() -> Instant {
        Instant::now() + Duration::from_secs(5)
    }

    /// Reads exactly `len` bytes, failing the test if the deadline passes first.
    async fn receive_exact(transport: &mut AsyncMemoryTransport, len: usize) -> Vec<u8> {
        let deadline = soon();
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        while out.len() < len {
            let n = transport.receive(&mut buf, deadline).await.unwrap();
            assert!(n > 0, "timed out after {} of {len} bytes", out.len());
            out.extend_from_slice(&buf[..n]);
        }
        out
    }

    #[tokio::test]
    async fn round_trip_both_directions() {
        let (mut a, mut b) = async_memory_pair();
        a.send(b"hello").await.unwrap();
        assert_eq!(b.pending(), 5);
        assert_eq!(a.pending(), 0);
        assert_eq!(receive_exact(&mut b, 5).await, b"hello");
        b.send(&[0x00, 0x0D, 0xFF]).await.unwrap();
        assert_eq!(receive_exact(&mut a, 3).await, [0x00, 0x0D, 0xFF]);
    }

    #[tokio::test]
    async fn receive_wakes_when_another_task_sends() {
        let (mut a, mut b) = async_memory_pair();
        let sender = async move {
            tokio::time::sleep(Duration::from_millis(10)).await;
            a.send(b"late").await.unwrap();
            a
        };
        let (a, received) = tokio::join!(sender, receive_exact(&mut b, 4));
        assert_eq!(received, b"late");
        drop(a);
    }

    #[tokio::test]
    async fn receive_wakes_when_another_thread_sends() {
        let (mut a, mut b) = async_memory_pair();
        let sender = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(10));
            block_on(a.send(b"thread"));
            a
        });
        assert_eq!(receive_exact(&mut b, 6).await, b"thread");
        drop(sender.join().unwrap());
    }

    /// Runs a future that never waits (a memory send) to its end on this thread.
    fn block_on<F: std::future::Future<Output = io::Result<()>>>(future: F) {
        tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap()
            .block_on(future)
            .unwrap();
    }

    #[tokio::test]
    async fn receive_with_a_silent_peer_returns_zero_at_the_deadline() {
        let (_a, mut b) = async_memory_pair();
        let mut buf = [0u8; 8];
        let start = Instant::now();
        let deadline = start + Duration::from_millis(50);
        assert_eq!(b.receive(&mut buf, deadline).await.unwrap(), 0);
        let took = start.elapsed();
        assert!(
            took >= Duration::from_millis(45),
            "returned early: {took:?}"
        );
        assert!(took < Duration::from_secs(2), "returned late: {took:?}");
    }

    #[tokio::test]
    async fn receive_with_past_deadline_still_returns_buffered_bytes() {
        let (mut a, mut b) = async_memory_pair();
        a.send(b"x").await.unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(b.receive(&mut buf, Instant::now()).await.unwrap(), 1);
        assert_eq!(buf[0], b'x');
    }

    #[tokio::test]
    async fn clear_input_drops_stale_bytes() {
        let (mut a, mut b) = async_memory_pair();
        a.send(b"stale").await.unwrap();
        b.clear_input().await.unwrap();
        assert_eq!(b.pending(), 0);
        let mut buf = [0u8; 8];
        let deadline = Instant::now() + Duration::from_millis(20);
        assert_eq!(b.receive(&mut buf, deadline).await.unwrap(), 0);
        a.send(b"fresh").await.unwrap();
        assert_eq!(receive_exact(&mut b, 5).await, b"fresh");
    }

    #[tokio::test]
    async fn peer_dropped_send_fails_receive_drains_then_times_out() {
        let (mut a, mut b) = async_memory_pair();
        b.send(b"bye").await.unwrap();
        drop(b);
        let err = a.send(b"anyone?").await.unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::BrokenPipe);
        assert_eq!(receive_exact(&mut a, 3).await, b"bye");
        let mut buf = [0u8; 8];
        let deadline = Instant::now() + Duration::from_millis(20);
        assert_eq!(a.receive(&mut buf, deadline).await.unwrap(), 0);
    }

    #[tokio::test]
    async fn a_receive_returns_one_burst_at_most_and_tells_the_gap_before_it() {
        let (mut a, mut b) = async_memory_pair();
        a.send(b"one").await.unwrap();
        tokio::time::sleep(Duration::from_millis(20)).await;
        a.send(b"two").await.unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(b.receive(&mut buf, soon()).await.unwrap(), 3);
        assert_eq!(&buf[..3], b"one");
        assert_eq!(b.last_gap(), None, "nothing came before the first burst");
        let mut small = [0u8; 2];
        assert_eq!(b.receive(&mut small, soon()).await.unwrap(), 2);
        assert!(b.last_gap().unwrap() >= Duration::from_millis(20));
        assert_eq!(b.receive(&mut small, soon()).await.unwrap(), 1);
        assert_eq!(b.last_gap(), Some(Duration::ZERO));
    }

    #[test]
    fn endpoints_and_their_futures_are_send() {
        fn assert_send<T: Send>(_: &T) {}
        let (mut a, _b) = async_memory_pair();
        let mut buf = [0u8; 4];
        assert_send(&a.receive(&mut buf, Instant::now()));
        assert_send(&a);
    }
}
