//! How bus workers hand events to the outputs: a bounded queue, so a stalled output (a
//! full pipe, a slow broker) never holds the buses and memory stays flat. A reading that
//! finds the queue full is dropped (the next poll brings a newer one) and counted; a
//! change of availability or a write's outcome waits for room, because it is not repeated.

use super::event::{Event, Reading};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, TrySendError};
use std::sync::Arc;

/// Events queued for the outputs, at most.
pub const QUEUE: usize = 4096;

/// A bus worker's end of the event queue.
#[derive(Clone)]
pub struct Reporter {
    queue: SyncSender<Event>,
    dropped: Arc<AtomicU64>,
}

impl Reporter {
    /// A queue of [`QUEUE`] events: the workers' end and the outputs' end.
    pub fn queue() -> (Reporter, Receiver<Event>) {
        let (queue, events) = std::sync::mpsc::sync_channel(QUEUE);
        (
            Reporter {
                queue,
                dropped: Arc::new(AtomicU64::new(0)),
            },
            events,
        )
    }

    /// Queues a reading, or drops it when the outputs are behind.
    pub fn reading(&self, reading: Reading) {
        match self.queue.try_send(Event::Reading(reading)) {
            Ok(()) | Err(TrySendError::Disconnected(_)) => {}
            Err(TrySendError::Full(_)) => {
                let dropped = self.dropped.fetch_add(1, Ordering::Relaxed) + 1;
                if dropped == 1 || dropped.is_multiple_of(10_000) {
                    log::warn!(
                        target: super::LOG_TARGET,
                        "the outputs fall behind: {dropped} reading(s) dropped so far"
                    );
                }
            }
        }
    }

    /// Queues an event that must not be lost, waiting for room.
    pub fn event(&self, event: Event) {
        let _ = self.queue.send(event);
    }
}
