//! The queue between the bus workers and the broker connection: bounded, and never a reason
//! for a bus worker to wait.
//!
//! Retained states are kept in a map (topic -> last payload, one entry per register,
//! station and the service), which is also what is republished after a reconnect. A state
//! waits in the queue at most once: a newer reading of a queued topic only replaces the
//! payload that will be sent. Beyond [`Outbox::reading_cap`] queued readings the oldest
//! queued *reading* is dropped (its topic gets the next reading, or the republish after a
//! reconnect); availability, write outcomes and acknowledgements are never dropped.

use rumqttc::Publish;
use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// Queued readings beyond which the oldest is dropped.
pub const READING_CAP: usize = 4096;

/// Something for the connection to send.
#[derive(Debug)]
pub enum Item {
    /// A retained state: the topic's latest payload.
    State {
        /// The topic.
        topic: String,
        /// Its latest payload.
        payload: Vec<u8>,
    },
    /// A message that is not retained (a write outcome), QoS 1.
    Message {
        /// The topic.
        topic: String,
        /// The payload.
        payload: Vec<u8>,
    },
    /// Acknowledge a `set` message (after its outcome was queued).
    Ack(Box<Publish>),
    /// The connection was (re)established: subscribe and republish every state.
    Resync,
}

/// What a queued state is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A register's reading: may be dropped from the queue (not from the map).
    Reading,
    /// Availability, the service's status, discovery: never dropped.
    Kept,
}

#[derive(Default)]
struct Inner {
    queue: VecDeque<Queued>,
    states: HashMap<String, Vec<u8>>,
    queued: HashSet<String>,
    queued_readings: usize,
    dropped: u64,
    closed: bool,
}

enum Queued {
    State(String, Kind),
    Other(Item),
}

/// The bounded queue (see the module documentation).
pub struct Outbox {
    inner: Mutex<Inner>,
    ready: Condvar,
    /// Queued readings beyond which the oldest is dropped.
    pub reading_cap: usize,
}

impl Outbox {
    /// An empty outbox.
    pub fn new(reading_cap: usize) -> Outbox {
        Outbox {
            inner: Mutex::new(Inner::default()),
            ready: Condvar::new(),
            reading_cap: reading_cap.max(1),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Sets a retained state and queues it (once).
    pub fn state(&self, topic: String, payload: Vec<u8>, kind: Kind) {
        let mut inner = self.lock();
        if inner.closed {
            return;
        }
        inner.states.insert(topic.clone(), payload);
        if inner.queued.insert(topic.clone()) {
            inner.queue.push_back(Queued::State(topic, kind));
            if kind == Kind::Reading {
                inner.queued_readings += 1;
                if inner.queued_readings > self.reading_cap {
                    let oldest = inner
                        .queue
                        .iter()
                        .position(|q| matches!(q, Queued::State(_, Kind::Reading)));
                    if let Some(Queued::State(topic, _)) =
                        oldest.and_then(|at| inner.queue.remove(at))
                    {
                        inner.queued.remove(&topic);
                        inner.queued_readings -= 1;
                        inner.dropped += 1;
                        if inner.dropped.is_power_of_two() {
                            log::warn!(
                                "MQTT: the broker connection is behind; {} reading(s) not sent so far (the latest state of each register is kept and sent)",
                                inner.dropped
                            );
                        }
                    }
                }
            }
        }
        self.ready.notify_one();
    }

    /// Queues anything else (never dropped).
    pub fn push(&self, item: Item) {
        let mut inner = self.lock();
        if inner.closed {
            return;
        }
        inner.queue.push_back(Queued::Other(item));
        self.ready.notify_one();
    }

    /// Queues a republish of every state; the subscription is renewed first.
    pub fn resync(&self) {
        self.push(Item::Resync);
    }

    /// Every retained state now (for a republish).
    pub fn snapshot(&self) -> Vec<(String, Vec<u8>)> {
        let mut states: Vec<_> = self
            .lock()
            .states
            .iter()
            .map(|(t, p)| (t.clone(), p.clone()))
            .collect();
        states.sort();
        states
    }

    /// Readings dropped from the queue so far.
    pub fn dropped(&self) -> u64 {
        self.lock().dropped
    }

    /// The next item, waiting at most `wait`; `None` when there is none (or it is closed and
    /// empty).
    pub fn next(&self, wait: Duration) -> Option<Item> {
        let mut inner = self.lock();
        if inner.queue.is_empty() && !inner.closed {
            inner = self
                .ready
                .wait_timeout(inner, wait)
                .map(|(guard, _)| guard)
                .unwrap_or_else(|e| e.into_inner().0);
        }
        match inner.queue.pop_front()? {
            Queued::State(topic, kind) => {
                inner.queued.remove(&topic);
                if kind == Kind::Reading {
                    inner.queued_readings -= 1;
                }
                let payload = inner.states.get(&topic).cloned().unwrap_or_default();
                Some(Item::State { topic, payload })
            }
            Queued::Other(item) => Some(item),
        }
    }

    /// Accepts nothing more; what is queued can still be taken.
    pub fn close(&self) {
        self.lock().closed = true;
        self.ready.notify_all();
    }

    /// Whether nothing is queued.
    pub fn is_empty(&self) -> bool {
        self.lock().queue.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn topics(outbox: &Outbox) -> Vec<String> {
        std::iter::from_fn(|| outbox.next(Duration::ZERO))
            .map(|item| match item {
                Item::State { topic, payload } => {
                    format!("{topic}={}", String::from_utf8_lossy(&payload))
                }
                Item::Message { topic, .. } => format!("message {topic}"),
                Item::Ack(_) => "ack".into(),
                Item::Resync => "resync".into(),
            })
            .collect()
    }

    #[test]
    fn a_queued_state_is_sent_once_with_its_latest_payload() {
        let outbox = Outbox::new(10);
        outbox.state("a".into(), b"1".to_vec(), Kind::Reading);
        outbox.state("b".into(), b"1".to_vec(), Kind::Reading);
        outbox.state("a".into(), b"2".to_vec(), Kind::Reading);
        assert_eq!(topics(&outbox), ["a=2", "b=1"]);
    }

    #[test]
    fn a_full_queue_drops_the_oldest_reading_never_availability_or_outcomes() {
        let outbox = Outbox::new(2);
        outbox.state("avail".into(), b"online".to_vec(), Kind::Kept);
        outbox.state("r1".into(), b"1".to_vec(), Kind::Reading);
        outbox.push(Item::Message {
            topic: "result".into(),
            payload: vec![],
        });
        outbox.state("r2".into(), b"2".to_vec(), Kind::Reading);
        outbox.state("r3".into(), b"3".to_vec(), Kind::Reading);
        assert_eq!(outbox.dropped(), 1);
        assert_eq!(
            topics(&outbox),
            ["avail=online", "message result", "r2=2", "r3=3"]
        );
        // The dropped reading's state is still kept for the republish.
        assert!(outbox
            .snapshot()
            .contains(&("r1".to_string(), b"1".to_vec())));
    }
}
