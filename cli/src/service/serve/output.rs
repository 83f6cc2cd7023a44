//! The outputs' side of the event queue: one thread hands every event to each output
//! (`--jsonl`, MQTT) in the order the workers reported them, and at the end lets each
//! output finish (the broker is told the service is offline).
//!
//! Events are taken in batches: the thread wakes for the first event of a batch, takes
//! every event queued behind it, lets each output flush, and then rests for [`BATCH`]
//! before it looks again. A worker reporting meanwhile only queues its event (no thread to
//! wake), so a busy plant costs one wake-up of this thread and one write per batch, not per
//! reading; an event waits at most one batch period.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;
use vfd_bus::service::event::Event;

/// Where events go.
pub trait Output: Send {
    /// Takes one event. An error ends the service (standard output closed, say): the
    /// message says why.
    fn event(&mut self, event: &Event) -> Result<(), String>;

    /// The batch's events were given: send on what is held back. An error ends the
    /// service, as in [`Output::event`].
    fn flush(&mut self) -> Result<(), String> {
        Ok(())
    }

    /// The service is stopping: the last events were given; finish within a bounded time.
    fn finish(self: Box<Self>);
}

/// How often the outputs' thread looks whether the workers are done.
const DONE_CHECK: Duration = Duration::from_millis(50);

/// How long the outputs' thread rests after a batch (see the module).
pub const BATCH: Duration = Duration::from_millis(10);

/// Runs the outputs on their own thread until the queue is empty once `done` is set (the
/// workers have ended) or closes; sets `stop` when an output fails, so the workers end too.
pub fn spawn(
    events: Receiver<Event>,
    mut outputs: Vec<Box<dyn Output>>,
    stop: Arc<AtomicBool>,
    done: Arc<AtomicBool>,
) -> std::io::Result<JoinHandle<Option<String>>> {
    std::thread::Builder::new()
        .name("outputs".to_owned())
        .spawn(move || {
            let mut failed = None;
            loop {
                let first = match events.recv_timeout(DONE_CHECK) {
                    Ok(event) => event,
                    Err(RecvTimeoutError::Timeout) if done.load(Ordering::SeqCst) => break,
                    Err(RecvTimeoutError::Timeout) => continue,
                    Err(RecvTimeoutError::Disconnected) => break,
                };
                // The batch: the first event and every one queued behind it.
                for event in std::iter::once(first).chain(events.try_iter()) {
                    if failed.is_some() {
                        // Drain, so no worker waits for room on the way out.
                        continue;
                    }
                    failed = give(&mut outputs, |output| output.event(&event));
                }
                if failed.is_none() {
                    failed = give(&mut outputs, |output| output.flush());
                }
                if failed.is_some() {
                    stop.store(true, Ordering::SeqCst);
                } else if !done.load(Ordering::SeqCst) {
                    std::thread::sleep(BATCH);
                }
            }
            for output in outputs {
                output.finish();
            }
            failed
        })
}

/// Hands one thing to every output in turn; the first failure, which stops the rest.
fn give(
    outputs: &mut [Box<dyn Output>],
    mut what: impl FnMut(&mut Box<dyn Output>) -> Result<(), String>,
) -> Option<String> {
    outputs.iter_mut().find_map(|output| what(output).err())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::sync_channel;
    use std::sync::Mutex;
    use vfd_bus::service::event::Availability;

    /// Records what it was given: `e` for an event, `f` for a flush.
    struct Recorder(Arc<Mutex<String>>);

    impl Output for Recorder {
        fn event(&mut self, _: &Event) -> Result<(), String> {
            self.0.lock().unwrap().push('e');
            Ok(())
        }
        fn flush(&mut self) -> Result<(), String> {
            self.0.lock().unwrap().push('f');
            Ok(())
        }
        fn finish(self: Box<Self>) {
            self.0.lock().unwrap().push('.');
        }
    }

    fn event(n: usize) -> Event {
        Event::Availability(Availability {
            bus: "line1".into(),
            drive: format!("d{n}"),
            online: true,
            reason: None,
            time: String::new(),
        })
    }

    #[test]
    fn events_queued_together_reach_the_outputs_as_one_batch_with_one_flush() {
        let (send, events) = sync_channel(16);
        for n in 0..5 {
            send.send(event(n)).unwrap();
        }
        let seen = Arc::new(Mutex::new(String::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let done = Arc::new(AtomicBool::new(false));
        let outputs: Vec<Box<dyn Output>> = vec![Box::new(Recorder(Arc::clone(&seen)))];
        let thread = spawn(events, outputs, Arc::clone(&stop), Arc::clone(&done)).unwrap();
        // One more while the thread rests after the first batch: a batch of its own.
        let deadline = std::time::Instant::now() + Duration::from_secs(10);
        while !seen.lock().unwrap().contains('f') {
            assert!(std::time::Instant::now() < deadline, "no batch flushed");
            std::thread::sleep(Duration::from_millis(1));
        }
        send.send(event(5)).unwrap();
        drop(send);
        assert_eq!(thread.join().unwrap(), None);
        assert_eq!(*seen.lock().unwrap(), "eeeeefef.");
        assert!(!stop.load(Ordering::SeqCst));
    }

    /// Fails its second event.
    struct Failing(usize);

    impl Output for Failing {
        fn event(&mut self, _: &Event) -> Result<(), String> {
            self.0 += 1;
            if self.0 == 2 {
                Err("standard output: broken pipe".into())
            } else {
                Ok(())
            }
        }
        fn finish(self: Box<Self>) {}
    }

    #[test]
    fn a_failing_output_stops_the_workers_and_the_rest_is_drained() {
        let (send, events) = sync_channel(16);
        for n in 0..4 {
            send.send(event(n)).unwrap();
        }
        drop(send);
        let stop = Arc::new(AtomicBool::new(false));
        let done = Arc::new(AtomicBool::new(false));
        let thread = spawn(events, vec![Box::new(Failing(0))], Arc::clone(&stop), done).unwrap();
        assert_eq!(
            thread.join().unwrap().as_deref(),
            Some("standard output: broken pipe")
        );
        assert!(stop.load(Ordering::SeqCst));
    }
}
