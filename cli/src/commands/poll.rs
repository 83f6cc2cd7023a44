//! The watch loop (`vfd watch`, and the demo's): polls registers until `--count` samples,
//! Ctrl-C or a deadline, and outlives the line: a timeout, a bad reply or an error reply
//! leaves the value stale and counts an error; an I/O error (an unplugged adapter) reopens
//! the port with a back-off of 0.1 s doubling to 5 s. It fails only when no read ever
//! succeeded.

use crate::emit::{Emitter, Format};
use crate::line_args::LineArgs;
use crate::out::{is_terminal, print_raw, say};
use crate::Failure;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use vfd_bus::record::ValueRecord;
use vfd_bus::session::{Session, Value};
use vfd_bus::trip_flag::trip_flag;
use vfd_bus::values;
use vfd_bus::{BackOff, Catalogue, ErrorKind};
use vfd_runtime::units::raw_to_scaled;
use vfd_runtime::RegisterInfo;

/// What to watch and until when.
pub struct Poll<'a> {
    /// The registers, in the scale they are shown in.
    pub registers: &'a [&'static RegisterInfo],
    /// Time between samples.
    pub interval: Duration,
    /// Stop after this many samples.
    pub count: Option<u64>,
    /// Set by Ctrl-C.
    pub stop: &'a AtomicBool,
    /// Stop at this instant (the demo).
    pub deadline: Option<Instant>,
    /// How to print.
    pub format: Format,
    /// The line options to reopen the port with after an I/O error (`None`: never reopen).
    pub reopen: Option<(&'a LineArgs, &'a Catalogue)>,
}

/// Polls until the end `poll` sets; `Ok` once any read succeeded.
pub fn run(session: &mut Session, poll: &Poll<'_>) -> Result<(), Failure> {
    let registers = poll.registers;
    let terminal = poll.format.is_text() && is_terminal();
    let mut emitter = Emitter::new(poll.format);
    let start = Instant::now();
    let mut history: Vec<Vec<f64>> = vec![Vec::new(); registers.len()];
    let mut last: Vec<Option<ValueRecord>> = vec![None; registers.len()];
    let mut drawn = 0usize;
    let mut samples = 0u64;
    let mut errors = 0u64;
    let mut good = 0u64;
    let mut last_failure: Option<Failure> = None;
    let mut port_lost = false;
    let mut back_off = BackOff::reopening();
    while !poll.stop.load(Ordering::SeqCst)
        && poll.count.is_none_or(|n| samples < n)
        && poll.deadline.is_none_or(|d| Instant::now() < d)
    {
        let results = read_all(session, poll, &mut port_lost);
        samples += 1;
        let tripped = trip_flag(session, registers, &results);
        let mut lines = Vec::new();
        let mut stale_now = false;
        for (index, (info, result)) in registers.iter().zip(results).enumerate() {
            match result {
                Ok(value) => {
                    good += 1;
                    let record =
                        ValueRecord::new(session.drive.id, info, value.raw, value.text.clone());
                    last[index] = Some(record.clone());
                    let mut record = record.now();
                    record.tripped = tripped;
                    record.errors = errors;
                    record.sample = samples;
                    emitter.record(&record);
                    let (shown, number) = shown(info, &value);
                    if let Some(number) = number {
                        let past = &mut history[index];
                        past.push(number);
                        if past.len() > 40 {
                            past.remove(0);
                        }
                    }
                    let spark = number.map(|_| sparkline(&history[index]));
                    lines.push((*info, shown, spark));
                }
                Err(failure) => {
                    errors += 1;
                    stale_now = true;
                    let error = failure.error.clone().unwrap_or_else(|| {
                        vfd_bus::Error::new(ErrorKind::Other, failure.message.clone())
                    });
                    if error.kind().is_io() {
                        port_lost = true;
                    }
                    let base = last[index]
                        .clone()
                        .unwrap_or_else(|| ValueRecord::new(session.drive.id, info, None, None));
                    let mut record = base.now().failed(&error);
                    record.tripped = None;
                    record.errors = errors;
                    record.sample = samples;
                    emitter.record(&record);
                    if poll.format.is_text() {
                        eprintln!(
                            "vfd: sample {samples}: {}: {} ({})",
                            info.code,
                            failure.message,
                            error.kind()
                        );
                    }
                    let was = last[index]
                        .as_ref()
                        .and_then(|r| r.text.clone())
                        .unwrap_or_else(|| "(no data)".to_owned());
                    lines.push((*info, format!("{was} [stale: {}]", error.kind()), None));
                    last_failure = Some(failure);
                }
            }
        }
        if poll.format.is_text() {
            let elapsed = start.elapsed().as_secs_f64();
            let head = Head {
                session,
                elapsed,
                tripped: tripped == Some(true),
                errors,
            };
            if terminal {
                drawn = redraw(&head, &lines, drawn);
            } else {
                let parts: Vec<String> = lines
                    .iter()
                    .map(|(info, shown, _)| format!("{}={shown}", info.code))
                    .collect();
                say!("{elapsed:6.1}s  {}{}", parts.join("  "), head.flags());
            }
        }
        // After a failure the next sample waits at least the back-off (0.1 s doubling to
        // 5 s) while the port is gone; otherwise the interval.
        let wait = if port_lost {
            poll.interval.max(back_off.next_wait())
        } else {
            if !stale_now {
                back_off.reset();
            }
            poll.interval
        };
        let next = Instant::now() + wait;
        while Instant::now() < next
            && !poll.stop.load(Ordering::SeqCst)
            && poll.count.is_none_or(|n| samples < n)
        {
            std::thread::sleep(Duration::from_millis(20).min(wait));
        }
    }
    emitter.finish();
    if poll.format.is_text() && errors > 0 {
        let plural =
            |n: u64, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
        say!(
            "{}, {} (stale values marked)",
            plural(samples, "sample", "samples"),
            plural(errors, "failed read", "failed reads")
        );
    }
    match (good, last_failure) {
        (0, Some(failure)) => Err(Failure::new(format!(
            "no read succeeded in {samples} sample(s); the last error: {}",
            failure.message
        ))
        .hint(
            failure
                .hint
                .unwrap_or_else(|| "check the line with `vfd read` first".to_owned()),
        )),
        _ => Ok(()),
    }
}

/// One sample's reads: through the session, or, once the port was lost, after reopening
/// it (each register failing with an I/O error while it cannot be opened).
fn read_all(
    session: &mut Session,
    poll: &Poll<'_>,
    port_lost: &mut bool,
) -> Vec<Result<Value, Failure>> {
    if *port_lost {
        if let Some((line, catalogue)) = poll.reopen {
            match crate::open_session::open_session(line, catalogue) {
                Ok(mut fresh) => {
                    fresh.command = session.command;
                    *session = fresh;
                    *port_lost = false;
                }
                Err(failure) => {
                    let error = vfd_bus::Error::new(ErrorKind::Io, failure.message.clone());
                    return poll
                        .registers
                        .iter()
                        .map(|_| {
                            let mut failure = Failure::new(failure.message.clone());
                            failure.error = Some(error.clone());
                            Err(failure)
                        })
                        .collect();
                }
            }
        }
    }
    // Consecutive registers in one request where the protocol allows it.
    session
        .read_many(poll.registers)
        .into_iter()
        .map(|result| result.map_err(Failure::from))
        .collect()
}

/// The value as text shows it, and its number for the trend line.
fn shown(info: &RegisterInfo, value: &Value) -> (String, Option<f64>) {
    match (&value.text, value.raw) {
        (Some(text), _) => (format!("{text:?}"), None),
        (None, Some(raw)) => (
            values::short(info, raw),
            (info.bits.is_none() && info.codes.is_none()).then(|| raw_to_scaled(raw, info)),
        ),
        (None, None) => ("(no data)".to_owned(), None),
    }
}

/// The head line of a text sample.
struct Head<'a> {
    session: &'a Session,
    elapsed: f64,
    tripped: bool,
    errors: u64,
}

impl Head<'_> {
    /// `  TRIPPED`, `  errors=3`, as they apply.
    fn flags(&self) -> String {
        let mut flags = String::new();
        if self.tripped {
            flags.push_str("  TRIPPED");
        }
        if self.errors > 0 {
            flags.push_str(&format!("  errors={}", self.errors));
        }
        flags
    }
}

/// Redraws the sample in place on a terminal; returns the lines drawn.
fn redraw(
    head: &Head<'_>,
    lines: &[(&RegisterInfo, String, Option<String>)],
    drawn: usize,
) -> usize {
    let mut text = String::new();
    if drawn > 0 {
        text.push_str(&format!("\x1b[{drawn}A"));
    }
    text.push_str(&format!(
        "\x1b[2K{} {} — {:.1} s{}\n",
        head.session.drive.id,
        head.session.protocol.id,
        head.elapsed,
        head.flags()
    ));
    for (info, shown, spark) in lines {
        text.push_str(&format!(
            "\x1b[2K  {:<7} {:<28} {:>22}  {}\n",
            info.code,
            clip(info.name, 28),
            shown,
            spark.as_deref().unwrap_or("")
        ));
    }
    print_raw(&text);
    lines.len() + 1
}

const SPARKS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];

/// A trend line of the last values.
pub fn sparkline(history: &[f64]) -> String {
    let (low, high) = history
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
    history
        .iter()
        .map(|v| {
            if high - low < 1e-12 {
                if high.abs() < 1e-12 {
                    SPARKS[0]
                } else {
                    SPARKS[3]
                }
            } else {
                let step = ((v - low) / (high - low) * 7.0).round() as usize;
                SPARKS[step.min(7)]
            }
        })
        .collect()
}

fn clip(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        text.to_owned()
    } else {
        let mut clipped: String = text.chars().take(width - 1).collect();
        clipped.push('…');
        clipped
    }
}
