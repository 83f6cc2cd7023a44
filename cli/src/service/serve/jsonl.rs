//! `--jsonl`: every event as one JSON object per line on standard output (the fields of
//! [`vfd_bus::service::event`]; docs/serve.md lists them), written a batch at a time (one
//! write for what the outputs' thread took together, [`super::output`]), so a pipe reader sees
//! each line at most one batch period after it happened. A closed standard output (the
//! reader went away) ends the service quietly.

use super::output::Output;
use std::io::Write;
use vfd_bus::service::event::Event;

/// JSON lines on standard output: the lines of a batch, not yet written.
#[derive(Default)]
pub struct JsonLines {
    pending: Vec<u8>,
}

impl Output for JsonLines {
    fn event(&mut self, event: &Event) -> Result<(), String> {
        serde_json::to_writer(&mut self.pending, event).map_err(|e| e.to_string())?;
        self.pending.push(b'\n');
        Ok(())
    }

    fn flush(&mut self) -> Result<(), String> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let mut out = std::io::stdout().lock();
        let written = out
            .write_all(&self.pending)
            .and_then(|()| out.flush())
            .map_err(|e| format!("standard output: {e}"));
        self.pending.clear();
        written
    }

    fn finish(mut self: Box<Self>) {
        let _ = self.flush();
    }
}
