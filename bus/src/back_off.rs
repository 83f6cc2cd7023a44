//! The wait before trying again after a failure: `first`, doubling after each failed try up
//! to `cap`, and back to `first` once something succeeds. One type for every place that
//! tries again: a port that failed (the watch and the service's bus workers reopen it), an
//! offline station (tried with one exchange), a broker connection. Sans I/O: it says how
//! long to wait; the caller waits.

use std::time::Duration;

/// The first wait before reopening a port that failed (an unplugged adapter, a lost
/// connection to a device server).
pub const REOPEN_FIRST: Duration = Duration::from_millis(100);
/// The longest wait between attempts to reopen a port.
pub const REOPEN_CAP: Duration = Duration::from_secs(5);

/// Waits that double from `first` to `cap`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BackOff {
    first: Duration,
    cap: Duration,
    next: Duration,
}

impl BackOff {
    /// Waits from `first` doubling to `cap` (`first` itself when it is above `cap`: the
    /// cap bounds every wait).
    pub fn new(first: Duration, cap: Duration) -> BackOff {
        let first = first.min(cap);
        BackOff {
            first,
            cap,
            next: first,
        }
    }

    /// The waits before reopening a port: [`REOPEN_FIRST`] doubling to [`REOPEN_CAP`].
    pub fn reopening() -> BackOff {
        BackOff::new(REOPEN_FIRST, REOPEN_CAP)
    }

    /// The wait before the next try; the one after it will be twice as long, up to the cap.
    pub fn next_wait(&mut self) -> Duration {
        let wait = self.next;
        self.next = (wait * 2).min(self.cap);
        wait
    }

    /// The wait [`BackOff::next_wait`] will give next, without taking it.
    pub fn peek(&self) -> Duration {
        self.next
    }

    /// Something succeeded: the next wait is the first again.
    pub fn reset(&mut self) {
        self.next = self.first;
    }

    /// The first wait.
    pub fn first(&self) -> Duration {
        self.first
    }

    /// The longest wait.
    pub fn cap(&self) -> Duration {
        self.cap
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waits_double_up_to_the_cap_and_start_again_after_a_reset() {
        let mut back_off = BackOff::new(Duration::from_millis(100), Duration::from_millis(500));
        let waits: Vec<u128> = (0..5).map(|_| back_off.next_wait().as_millis()).collect();
        assert_eq!(waits, [100, 200, 400, 500, 500]);
        back_off.reset();
        assert_eq!(back_off.peek(), Duration::from_millis(100));
        assert_eq!(back_off.next_wait(), Duration::from_millis(100));
    }

    #[test]
    fn the_cap_bounds_the_first_wait_too() {
        let mut back_off = BackOff::new(Duration::from_secs(5), Duration::from_secs(1));
        assert_eq!(back_off.next_wait(), Duration::from_secs(1));
        assert_eq!(back_off.next_wait(), Duration::from_secs(1));
    }
}
