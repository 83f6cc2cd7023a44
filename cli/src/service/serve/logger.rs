//! What the service says about itself on standard error, one line per record, stamped
//! with the UTC time: a port that failed or came back, a station offline or online again,
//! each write, the broker's connection. `--verbose` adds debug records (registers a drive
//! refused to read, and the runtime's retries and resyncs).

use std::io::Write;

/// Prints records of `vfd` and its runtime at the level set by [`start`].
struct ServiceLogger;

static LOGGER: ServiceLogger = ServiceLogger;

impl log::Log for ServiceLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::max_level() && metadata.target().starts_with("vfd")
    }

    fn log(&self, record: &log::Record<'_>) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let (time, _) = vfd_bus::record::now();
        let level = match record.level() {
            log::Level::Error => "error",
            log::Level::Warn => "warning",
            log::Level::Info => "info",
            log::Level::Debug => "debug",
            log::Level::Trace => "trace",
        };
        let _ = writeln!(
            std::io::stderr().lock(),
            "{time} vfd serve: {level}: {}",
            record.args()
        );
    }

    fn flush(&self) {}
}

/// Installs the logger (once per process): info and above, or debug with `verbose`.
pub fn start(verbose: bool) {
    let level = if verbose {
        log::LevelFilter::Debug
    } else {
        log::LevelFilter::Info
    };
    if log::set_logger(&LOGGER).is_ok() {
        log::set_max_level(level);
    }
}
