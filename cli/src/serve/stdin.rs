//! `--stdin-writes`: write requests as JSON lines on standard input, for scripts and
//! tools without a broker (`{"bus": "line1", "drive": "pump1", "register": "FA01",
//! "value": "50 Hz"}`), each answered by a `written` event. The end of standard input
//! ends only the requests, not the service.

use super::event::{WriteOutcome, WriteRequest, WriteRouter};
use super::report::Reporter;
use serde::Deserialize;
use std::io::BufRead;

/// One request line.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Line {
    bus: String,
    drive: String,
    register: String,
    value: serde_json::Value,
}

/// Reads requests from standard input on a thread of its own until it ends.
pub fn spawn(router: WriteRouter, reporter: Reporter) -> std::io::Result<()> {
    std::thread::Builder::new()
        .name("stdin writes".to_owned())
        .spawn(move || {
            let stdin = std::io::stdin();
            for (number, line) in stdin.lock().lines().enumerate() {
                let Ok(line) = line else { break };
                if line.trim().is_empty() {
                    continue;
                }
                let id = number as u64 + 1;
                match request(&line, id) {
                    Ok(request) => match router.buses.get(&request.bus) {
                        Some(queue) => {
                            let _ = queue.send(request);
                        }
                        None => {
                            let known: Vec<&str> = router.buses.keys().map(String::as_str).collect();
                            let error = format!(
                                "there is no bus `{}` in the plant file (it names {}); nothing was sent",
                                request.bus,
                                known.join(", ")
                            );
                            reporter.event(refusal(&request, id, error));
                        }
                    },
                    Err(error) => {
                        let empty = WriteRequest {
                            bus: String::new(),
                            drive: String::new(),
                            register: String::new(),
                            value: line.clone(),
                            id,
                        };
                        reporter.event(refusal(&empty, id, format!(
                            "line {id} of standard input is not a write request ({error}); write {{\"bus\": ..., \"drive\": ..., \"register\": ..., \"value\": ...}}"
                        )));
                    }
                }
            }
        })
        .map(|_| ())
}

fn request(line: &str, id: u64) -> Result<WriteRequest, serde_json::Error> {
    let parsed: Line = serde_json::from_str(line)?;
    let value = match parsed.value {
        serde_json::Value::String(text) => text,
        other => other.to_string(),
    };
    Ok(WriteRequest {
        bus: parsed.bus,
        drive: parsed.drive,
        register: parsed.register,
        value,
        id,
    })
}

fn refusal(request: &WriteRequest, id: u64, error: String) -> super::event::Event {
    super::event::Event::Written(WriteOutcome::refused(
        &WriteRequest {
            id,
            ..request.clone()
        },
        error,
    ))
}
