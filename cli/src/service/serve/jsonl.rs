//! `--jsonl`: every event as one JSON object per line on standard output (the fields of
//! [`vfd_bus::service::event`]; docs/serve.md lists them), flushed line by line so a pipe reader sees
//! each as it happens. A closed standard output (the reader went away) ends the service
//! quietly.

use super::output::Output;
use std::io::Write;
use vfd_bus::service::event::Event;

/// JSON lines on standard output.
pub struct JsonLines;

impl Output for JsonLines {
    fn event(&mut self, event: &Event) -> Result<(), String> {
        let mut line = serde_json::to_vec(event).map_err(|e| e.to_string())?;
        line.push(b'\n');
        let mut out = std::io::stdout().lock();
        out.write_all(&line)
            .and_then(|()| out.flush())
            .map_err(|e| format!("standard output: {e}"))
    }

    fn finish(self: Box<Self>) {
        let _ = std::io::stdout().flush();
    }
}
