//! The outputs' side of the event queue: one thread hands every event to each output
//! (`--jsonl`, MQTT) in the order the workers reported them, and at the end lets each
//! output finish (the broker is told the service is offline).

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

    /// The service is stopping: the last events were given; finish within a bounded time.
    fn finish(self: Box<Self>);
}

/// How often the outputs' thread looks whether the workers are done.
const DONE_CHECK: Duration = Duration::from_millis(50);

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
                let event = match events.recv_timeout(DONE_CHECK) {
                    Ok(event) => event,
                    Err(RecvTimeoutError::Timeout) if done.load(Ordering::SeqCst) => break,
                    Err(RecvTimeoutError::Timeout) => continue,
                    Err(RecvTimeoutError::Disconnected) => break,
                };
                if failed.is_some() {
                    // Drain, so no worker waits for room on the way out.
                    continue;
                }
                for output in &mut outputs {
                    if let Err(why) = output.event(&event) {
                        failed = Some(why);
                        stop.store(true, Ordering::SeqCst);
                        break;
                    }
                }
            }
            for output in outputs {
                output.finish();
            }
            failed
        })
}
