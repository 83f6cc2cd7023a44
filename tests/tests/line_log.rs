//! The runtime reports what it does on the line through the `log` facade, and never
//! prints: frames sent and received at trace level (hex), a retry, input dropped before a
//! request and the echo learned at debug level. A test logger collects the records of the
//! thread that runs each exchange (tests run in parallel in one process).

use std::cell::RefCell;
use std::time::Duration;
use vfd_drives::fc51::{self, protocols, registers};
use vfd_runtime::serial::DriveTiming;
use vfd_runtime::transaction::{Master, LOG_TARGET};
use vfd_runtime::transport::{memory_pair, Transport};
use vfd_tests::scripted_peer::answer;

thread_local! {
    static RECORDS: RefCell<Vec<(log::Level, String)>> = const { RefCell::new(Vec::new()) };
}

/// Keeps every record of the line's target, per thread.
struct TestLogger;

impl log::Log for TestLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.target() == LOG_TARGET
    }
    fn log(&self, record: &log::Record<'_>) {
        if self.enabled(record.metadata()) {
            RECORDS.with(|r| {
                r.borrow_mut()
                    .push((record.level(), record.args().to_string()))
            });
        }
    }
    fn flush(&self) {}
}

static LOGGER: TestLogger = TestLogger;

/// The records this thread's exchanges have logged so far (the logger is installed once).
fn take_records() -> Vec<(log::Level, String)> {
    let _ = log::set_logger(&LOGGER);
    log::set_max_level(log::LevelFilter::Trace);
    RECORDS.with(|r| std::mem::take(&mut *r.borrow_mut()))
}

fn timing() -> DriveTiming {
    DriveTiming {
        processing_allowance: Duration::from_millis(50),
        ..fc51::SERIAL.timing
    }
}

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("hex"))
        .collect()
}

#[test]
fn frames_are_logged_at_trace_level_and_a_retry_at_debug_level() {
    take_records();
    let reply = hex("01 03 04 00 00 EA 60 B5 7B");
    let (ours, theirs) = memory_pair();
    // The first request is not answered, the second is.
    let drive = answer(
        theirs,
        protocols::MODBUS.protocol(),
        vec![Vec::new(), reply],
    );
    let mut modbus = Master::new(ours, &protocols::MODBUS, fc51::SERIAL.default, timing())
        .with_address(Some(1))
        .with_local_echo(Some(false))
        .with_retries(1);
    assert_eq!(modbus.read::<registers::MaximumReference>().unwrap(), 60.0);
    drive.join().unwrap();
    let records = take_records();
    let sent: Vec<_> = records
        .iter()
        .filter(|(level, text)| *level == log::Level::Trace && text.starts_with("sent 01 03 "))
        .collect();
    assert_eq!(sent.len(), 2, "the read and its retry: {records:#?}");
    assert!(
        records
            .iter()
            .any(|(level, text)| *level == log::Level::Trace
                && text.starts_with("received 01 03 04 00 00 EA 60 B5 7B (+")),
        "{records:#?}"
    );
    assert!(
        records
            .iter()
            .any(|(level, text)| *level == log::Level::Debug
                && text.starts_with("retrying register")
                && text.contains("0 retries left")),
        "{records:#?}"
    );
    assert!(
        records.iter().all(|(level, _)| *level >= log::Level::Debug),
        "nothing above debug on a retried read: {records:#?}"
    );
}

#[test]
fn stale_input_and_the_echo_learned_are_logged_at_debug_level() {
    take_records();
    let (ours, mut theirs) = memory_pair();
    theirs.send(&hex("55 AA")).expect("the pipe is open");
    let reply = hex("01 03 04 00 00 EA 60 B5 7B");
    let drive = answer(theirs, protocols::MODBUS.protocol(), vec![reply]);
    let mut modbus =
        Master::new(ours, &protocols::MODBUS, fc51::SERIAL.default, timing()).with_address(Some(1));
    assert_eq!(modbus.read::<registers::MaximumReference>().unwrap(), 60.0);
    drive.join().unwrap();
    let records = take_records();
    assert!(
        records
            .iter()
            .any(|(level, text)| *level == log::Level::Debug
                && text == "the line does not echo the master's requests"),
        "{records:#?}"
    );
    // The memory transport clears its input itself; what it dropped is not seen, so only
    // the clear is certain: the stale bytes are never taken for the reply.
    assert!(
        !records
            .iter()
            .any(|(_, text)| text.starts_with("received 55 AA")),
        "{records:#?}"
    );
}
