//! Whether a station answers, as a bus worker sees it (sans I/O: the caller brings the
//! clock): unknown until its first exchange, online after an answer, offline after
//! `offline_after` failed exchanges in a row. An offline station is tried again, with one
//! exchange, after a back-off that starts at `first` and doubles after each failed try up
//! to `cap`, so a dead station costs its bus at most one reply timeout per back-off period.

use crate::BackOff;
use std::time::{Duration, Instant};

/// How failures turn into offline, and how often an offline station is tried.
#[derive(Debug, Clone, Copy)]
pub struct Rules {
    /// Failed exchanges in a row that mark a station offline (at least 1).
    pub offline_after: u32,
    /// The first wait before an offline station is tried again.
    pub first: Duration,
    /// The longest wait between tries.
    pub cap: Duration,
}

/// What the worker may do with a station now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Turn {
    /// Poll what is due.
    Poll,
    /// Try it with one exchange: it is offline and its back-off has passed.
    Probe,
    /// Leave it alone until then.
    WaitUntil(Instant),
}

/// A change the outputs are told about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Change {
    /// It answers (first answer, or again after being offline).
    Online,
    /// It stopped answering.
    Offline,
}

/// One station's health.
#[derive(Debug, Clone)]
pub struct Health {
    rules: Rules,
    /// Failed exchanges in a row.
    failures: u32,
    /// What the outputs were last told (`None`: nothing yet).
    reported: Option<Change>,
    /// While offline: the waits between tries, the last one taken, and when the next try
    /// is due.
    back_off: BackOff,
    wait: Duration,
    next_try: Option<Instant>,
}

impl Health {
    /// A station not yet tried.
    pub fn new(rules: Rules) -> Health {
        Health {
            rules: Rules {
                offline_after: rules.offline_after.max(1),
                ..rules
            },
            failures: 0,
            reported: None,
            back_off: BackOff::new(rules.first, rules.cap),
            wait: rules.first,
            next_try: None,
        }
    }

    /// The rules it follows.
    pub fn rules(&self) -> Rules {
        self.rules
    }

    /// Whether the station is offline.
    pub fn is_offline(&self) -> bool {
        self.reported == Some(Change::Offline)
    }

    /// What the worker may do with the station at `now`.
    pub fn turn(&self, now: Instant) -> Turn {
        match self.next_try {
            Some(at) if self.is_offline() && now < at => Turn::WaitUntil(at),
            _ if self.is_offline() => Turn::Probe,
            _ => Turn::Poll,
        }
    }

    /// The station answered; returns the change to report, if any.
    pub fn answered(&mut self) -> Option<Change> {
        self.failures = 0;
        self.back_off.reset();
        self.next_try = None;
        self.report(Change::Online)
    }

    /// An exchange with the station failed at `now` (no answer, a damaged one); returns
    /// the change to report, if any.
    pub fn failed(&mut self, now: Instant) -> Option<Change> {
        self.failures = self.failures.saturating_add(1);
        if self.is_offline() {
            // A failed try: wait twice as long before the next, up to the cap.
            self.wait = self.back_off.next_wait();
            self.next_try = Some(now + self.wait);
            return None;
        }
        if self.failures < self.rules.offline_after {
            return None;
        }
        self.back_off.reset();
        self.wait = self.back_off.next_wait();
        self.next_try = Some(now + self.wait);
        self.report(Change::Offline)
    }

    /// The station cannot be reached at all (its bus's port failed): offline at once,
    /// tried again when the port is back. Returns the change to report, if any.
    pub fn unreachable(&mut self) -> Option<Change> {
        self.failures = self.rules.offline_after;
        // As if it had been tried once: a failed try after this waits twice the first.
        self.back_off.reset();
        self.wait = self.back_off.next_wait();
        self.next_try = None;
        self.report(Change::Offline)
    }

    /// The current wait between tries (while offline).
    #[cfg(test)]
    pub fn backoff(&self) -> Duration {
        self.wait
    }

    fn report(&mut self, change: Change) -> Option<Change> {
        if self.reported == Some(change) {
            return None;
        }
        self.reported = Some(change);
        Some(change)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RULES: Rules = Rules {
        offline_after: 3,
        first: Duration::from_secs(1),
        cap: Duration::from_secs(8),
    };

    #[test]
    fn the_first_answer_reports_online_once() {
        let mut health = Health::new(RULES);
        assert_eq!(health.turn(Instant::now()), Turn::Poll);
        assert_eq!(health.answered(), Some(Change::Online));
        assert_eq!(health.answered(), None);
    }

    #[test]
    fn offline_after_the_stated_failures_in_a_row() {
        let t = Instant::now();
        let mut health = Health::new(RULES);
        assert_eq!(health.failed(t), None);
        assert_eq!(health.failed(t), None);
        // An answer in between starts the count again.
        assert_eq!(health.answered(), Some(Change::Online));
        assert_eq!(health.failed(t), None);
        assert_eq!(health.failed(t), None);
        assert_eq!(health.turn(t), Turn::Poll);
        assert_eq!(health.failed(t), Some(Change::Offline));
        assert!(health.is_offline());
        assert_eq!(health.turn(t), Turn::WaitUntil(t + RULES.first));
        assert_eq!(health.turn(t + RULES.first), Turn::Probe);
    }

    #[test]
    fn the_back_off_doubles_up_to_the_cap_and_resets_on_an_answer() {
        let mut t = Instant::now();
        let mut health = Health::new(RULES);
        for _ in 0..3 {
            health.failed(t);
        }
        let mut waits = Vec::new();
        for _ in 0..6 {
            let Turn::WaitUntil(at) = health.turn(t) else {
                panic!("an offline station waits")
            };
            waits.push((at - t).as_secs());
            t = at;
            assert_eq!(health.turn(t), Turn::Probe);
            assert_eq!(health.failed(t), None, "offline is reported once");
        }
        assert_eq!(waits, [1, 2, 4, 8, 8, 8]);
        assert_eq!(health.answered(), Some(Change::Online));
        assert_eq!(health.turn(t), Turn::Poll);
        for _ in 0..3 {
            health.failed(t);
        }
        assert_eq!(health.backoff(), RULES.first, "a new outage starts short");
    }

    #[test]
    fn an_unreachable_station_is_offline_at_once_and_tried_when_asked() {
        let t = Instant::now();
        let mut health = Health::new(RULES);
        assert_eq!(health.unreachable(), Some(Change::Offline));
        assert_eq!(health.unreachable(), None);
        assert_eq!(health.turn(t), Turn::Probe);
    }
}
