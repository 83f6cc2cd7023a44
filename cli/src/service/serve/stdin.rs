//! `--stdin-writes`: write requests as JSON lines on standard input, for scripts and
//! tools without a broker (`{"bus": "line1", "drive": "pump1", "register": "FA01",
//! "value": "50 Hz"}`), each answered by a `written` event. The end of standard input
//! ends only the requests, not the service. A line longer than [`MAX_LINE_BYTES`] is
//! refused without being kept (only its first bytes and its size are repeated).

use serde::Deserialize;
use std::io::BufRead;
use vfd_bus::service::event::{NotSent, Unroutable, WriteOutcome, WriteRequest, WriteRouter};
use vfd_bus::service::report::Reporter;
use vfd_bus::service::request_text::{echo_of, MAX_NAME_BYTES, MAX_VALUE_BYTES};

/// The longest request line taken: a value, three names and the JSON around them.
pub const MAX_LINE_BYTES: usize = MAX_VALUE_BYTES + 3 * MAX_NAME_BYTES + 256;

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
            let mut input = stdin.lock();
            let mut number = 0u64;
            while let Some((line, size)) = bounded_line(&mut input, MAX_LINE_BYTES) {
                number += 1;
                if size <= MAX_LINE_BYTES && line.trim_ascii().is_empty() {
                    continue;
                }
                let outcome = answer(&line, size, number, &router);
                if let Some(outcome) = outcome {
                    reporter.event(vfd_bus::service::event::Event::Written(outcome));
                }
            }
        })
        .map(|_| ())
}

/// Hands the request on `line` (of `size` bytes, kept only up to the limit) to its bus, or
/// says why not.
fn answer(line: &[u8], size: usize, number: u64, router: &WriteRouter) -> Option<WriteOutcome> {
    let id = vfd_bus::service::run_id::next();
    // What the result repeats of the line: its start and size when long.
    let refused = |error: String| {
        let empty = WriteRequest::new("", "", "", "", id);
        Some(WriteOutcome {
            request: echo_of(line, size),
            ..WriteOutcome::refused(&empty, error)
        })
    };
    if size > MAX_LINE_BYTES {
        return refused(format!(
            "line {number} of standard input is {size} bytes, more than a write request can be ({MAX_LINE_BYTES}); it was not read"
        ));
    }
    let text = match std::str::from_utf8(line) {
        Ok(text) => text,
        Err(_) => return refused(format!("line {number} of standard input is not UTF-8 text")),
    };
    match request(text, id) {
        Ok(request) if request.value.len() > MAX_VALUE_BYTES => {
            let error = format!(
                "the value on line {number} of standard input is {} bytes, more than any register's value ({MAX_VALUE_BYTES}); nothing was sent",
                request.value.len()
            );
            Some(WriteOutcome::refused(&request, error))
        }
        Ok(request) => match router.send(request) {
            Ok(()) => None,
            Err(NotSent {
                why: Unroutable::NoBus(known),
                request,
            }) => {
                let error = format!(
                    "there is no bus `{}` in the plant file (it names {}); nothing was sent",
                    vfd_bus::service::request_text::echo_text(&request.bus),
                    known.join(", ")
                );
                Some(WriteOutcome::refused(&request, error))
            }
            // The worker has ended: the service is stopping.
            Err(_) => None,
        },
        Err(error) => refused(format!(
            "line {number} of standard input is not a write request ({error}); write {{\"bus\": ..., \"drive\": ..., \"register\": ..., \"value\": ...}}"
        )),
    }
}

/// The next line of `input` without its end (`\n` or `\r\n`) and its whole size in bytes;
/// at most `limit` + 1 bytes of it are kept, the rest is read and dropped. `None` at the
/// end of the input (or when it fails).
fn bounded_line(input: &mut impl BufRead, limit: usize) -> Option<(Vec<u8>, usize)> {
    let mut kept = Vec::new();
    let mut size = 0usize;
    let mut any = false;
    loop {
        let buffer = match input.fill_buf() {
            Ok(buffer) => buffer,
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(_) => return any.then_some((kept, size)),
        };
        if buffer.is_empty() {
            return any.then_some((kept, size));
        }
        any = true;
        let (taken, ended) = match buffer.iter().position(|b| *b == b'\n') {
            Some(at) => (at, true),
            None => (buffer.len(), false),
        };
        let room = (limit + 1).saturating_sub(kept.len());
        kept.extend_from_slice(&buffer[..taken.min(room)]);
        size += taken;
        input.consume(taken + usize::from(ended));
        if ended {
            if kept.last() == Some(&b'\r') && size <= limit {
                kept.pop();
                size -= 1;
            }
            return Some((kept, size));
        }
    }
}

fn request(line: &str, id: u64) -> Result<WriteRequest, serde_json::Error> {
    let parsed: Line = serde_json::from_str(line)?;
    let value = match parsed.value {
        serde_json::Value::String(text) => text,
        other => other.to_string(),
    };
    Ok(WriteRequest::new(
        parsed.bus,
        parsed.drive,
        parsed.register,
        value,
        id,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_read_whole_up_to_the_limit_and_counted_beyond_it() {
        let text = format!("short\r\n{}\nlast", "x".repeat(100));
        let mut input = std::io::BufReader::with_capacity(8, text.as_bytes());
        assert_eq!(bounded_line(&mut input, 10), Some((b"short".to_vec(), 5)));
        let (kept, size) = bounded_line(&mut input, 10).unwrap();
        assert_eq!((kept.len(), size), (11, 100));
        assert_eq!(bounded_line(&mut input, 10), Some((b"last".to_vec(), 4)));
        assert_eq!(bounded_line(&mut input, 10), None);
    }

    #[test]
    fn a_long_line_is_refused_unread_with_a_short_echo() {
        let router = WriteRouter::default();
        let line = vec![b'{'; MAX_LINE_BYTES + 1];
        let outcome = answer(&line, 200 * 1024, 7, &router).expect("refused");
        let error = outcome.error.unwrap();
        assert!(
            error.contains("line 7 of standard input is 204800 bytes"),
            "{error}"
        );
        assert!(
            outcome.request.ends_with("… (204800 bytes)"),
            "{}",
            outcome.request
        );
        assert!(outcome.request.len() < 200, "{}", outcome.request);
    }
}
