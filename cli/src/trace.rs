//! `--trace`: each frame a bus command sends and receives, in hex and decoded, with the
//! milliseconds since the command started, on standard error; with it, what the runtime
//! reports about the line at debug level (retries, resyncs, dropped input, the echo
//! learned, page switches), through a small `log` implementation.
//!
//! The frames come from the traced line ([`crate::traced_line::Traced`]), which holds the bytes
//! and decodes them with the same code as `vfd decode`; the runtime's trace-level frame
//! records (text, in hex) are not printed a second time.

use std::io::Write;
use std::sync::OnceLock;
use std::time::Instant;

/// When the command started: the zero of every time printed.
static START: OnceLock<Instant> = OnceLock::new();

/// Milliseconds since the command started (the first call starts the clock).
pub fn elapsed_ms() -> f64 {
    START.get_or_init(Instant::now).elapsed().as_secs_f64() * 1000.0
}

/// Prints one trace line on standard error, stamped with the time since the start.
pub fn line(text: std::fmt::Arguments<'_>) {
    let stamp = elapsed_ms();
    let _ = writeln!(std::io::stderr().lock(), "[{stamp:9.1} ms] {text}");
}

/// Prints the runtime's line records at debug level and above.
struct LineLogger;

impl log::Log for LineLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.target() == vfd_runtime::transaction::LOG_TARGET
            && metadata.level() <= log::Level::Debug
    }

    fn log(&self, record: &log::Record<'_>) {
        if self.enabled(record.metadata()) {
            line(format_args!("   {}", record.args()));
        }
    }

    fn flush(&self) {}
}

static LOGGER: LineLogger = LineLogger;

/// Starts the clock and collects the runtime's debug records (once per process).
pub fn start() {
    elapsed_ms();
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(log::LevelFilter::Debug);
    }
}
