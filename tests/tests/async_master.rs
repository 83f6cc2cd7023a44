//! The asynchronous master against the virtual drive, on every protocol of every drive:
//! what it reads and writes is what the blocking master reads and writes on the same
//! drive, and under the faults a line commits most (a dropped, corrupted, late or echoed
//! reply, noise) it owes the fault matrix's outcome within the fault matrix's bound.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};
use vfd_runtime::transaction::{Async, Master};
use vfd_runtime::transport::{AsyncPtyTransport, PseudoTerminal};
use vfd_runtime::virtual_drive::{serve, Fault, Simulator};
use vfd_runtime::{CommandKind, Request};
use vfd_tests::fault_cases::{expected, subjects, Kind, Subject};
use vfd_tests::slack::{Slack, LOADED_MACHINE};

/// A current-thread tokio runtime, as a small application would run one.
fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("tokio runtime")
}

/// The asynchronous master of these tests, on a pseudo-terminal allowing for a loaded machine.
type AsyncPtyMaster = Master<Async<Slack<AsyncPtyTransport>>>;

/// An asynchronous master for `subject` on a pseudo-terminal whose other side a thread
/// serves `sim` on; stop the thread with the flag, then join it.
fn served_async(
    sim: &Simulator,
    subject: &Subject,
    retries: u8,
) -> (
    AsyncPtyMaster,
    Arc<AtomicBool>,
    thread::JoinHandle<std::io::Result<()>>,
) {
    let (line, drive_end) =
        AsyncPtyTransport::split(PseudoTerminal::open().expect("pty")).expect("split");
    // Both ends allow for a loaded machine (see vfd_tests::slack).
    let (line, mut drive_end) = (
        Slack::new(line, LOADED_MACHINE),
        Slack::new(drive_end, LOADED_MACHINE),
    );
    let stop = Arc::new(AtomicBool::new(false));
    let settings = subject.drive.serial.default;
    let server = {
        let (sim, stop, protocol) = (sim.clone(), Arc::clone(&stop), subject.protocol);
        thread::spawn(move || serve(&sim, protocol, &mut drive_end, settings, &stop))
    };
    let address = sim.lock().address();
    let master = Master::for_protocol(
        Async(line),
        subject.protocol,
        settings,
        subject.drive.serial.timing,
    )
    .with_address(Some(address))
    .with_retries(retries);
    (master, stop, server)
}

fn read_request(subject: &Subject) -> Request {
    Request::for_register(CommandKind::Read, subject.read, 0)
}

fn write_request(subject: &Subject, raw: u32) -> Request {
    Request::for_register(subject.write_kind, subject.write, raw)
}

fn write_read_back(subject: &Subject) -> Request {
    Request::for_register(CommandKind::Read, subject.write, 0)
}

#[test]
fn the_async_and_the_blocking_master_agree_on_every_protocol() {
    let (subjects, _) = subjects();
    assert!(subjects.len() >= 8, "{} subjects", subjects.len());
    let runtime = runtime();
    let mut failures = Vec::new();
    for subject in &subjects {
        let sim = subject.simulator();
        let mut blocking = vfd_tests::masters::untyped(&sim, subject.drive, subject.protocol);
        let name = subject.name();
        let outcome: Result<(), String> = runtime.block_on(async {
            let (mut master, stop, server) = served_async(&sim, subject, 0);
            let result = async {
                // The same read, both ways.
                let ours = master.transact(&read_request(subject)).await;
                let theirs = blocking.transact(&read_request(subject));
                match (&ours, &theirs) {
                    (Ok(a), Ok(b)) if a.data == b.data && a.tripped == b.tripped => {}
                    _ => return Err(format!("read: async {ours:?}, blocking {theirs:?}")),
                }
                // Written by one, read back by the other.
                let first = subject.value(0);
                master
                    .transact(&write_request(subject, first))
                    .await
                    .map_err(|e| format!("async write: {e}"))?;
                let back = blocking
                    .transact(&write_read_back(subject))
                    .map_err(|e| format!("blocking read-back: {e}"))?;
                if back.data != Some(first) {
                    return Err(format!(
                        "async wrote {first}, blocking read {:?}",
                        back.data
                    ));
                }
                let second = subject.value(1);
                blocking
                    .transact(&write_request(subject, second))
                    .map_err(|e| format!("blocking write: {e}"))?;
                let back = master
                    .transact(&write_read_back(subject))
                    .await
                    .map_err(|e| format!("async read-back: {e}"))?;
                if back.data != Some(second) {
                    return Err(format!(
                        "blocking wrote {second}, async read {:?}",
                        back.data
                    ));
                }
                Ok(())
            }
            .await;
            stop.store(true, Ordering::Relaxed);
            server
                .join()
                .expect("serve thread")
                .map_err(|e| e.to_string())?;
            result
        });
        if let Err(message) = outcome {
            failures.push(format!("{name}: {message}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_async_master_owes_the_fault_matrix_outcomes_within_its_bounds() {
    let (subjects, _) = subjects();
    let faults = [
        ("drop reply", Fault::DropReply),
        ("corrupt checksum", Fault::CorruptChecksum),
        ("delay", Fault::Delay),
        ("echo request", Fault::EchoRequest),
        ("noise", Fault::Noise),
    ];
    let runtime = runtime();
    let mut failures = Vec::new();
    let mut cells = 0;
    for subject in &subjects {
        let sim = subject.simulator();
        runtime.block_on(async {
            let (mut master, stop, server) = served_async(&sim, subject, 0);
            // The longest exchange of one frame the master allows, with the gap before
            // it: the fault matrix's bound.
            let one = master.reply_timeout(usize::from(subject.protocol.max_frame_len))
                + master.frame_gap();
            let bound = one * 3 / 2 + Duration::from_millis(300);
            for (name, fault) in &faults {
                cells += 1;
                // The line works before the fault.
                if master.transact(&read_request(subject)).await.is_err() {
                    failures.push(format!(
                        "{} {name}: the fault-free read failed",
                        subject.name()
                    ));
                    continue;
                }
                sim.inject(fault.clone());
                let started = Instant::now();
                let outcome = master.transact(&read_request(subject)).await;
                let elapsed = started.elapsed();
                sim.clear_faults();
                let kind = Kind::of(&outcome);
                if kind != expected(fault) {
                    failures.push(format!(
                        "{} {name}: expected {}, got {} ({outcome:?})",
                        subject.name(),
                        expected(fault).label(),
                        kind.label()
                    ));
                }
                if elapsed > bound {
                    failures.push(format!(
                        "{} {name}: took {elapsed:?}, more than {bound:?}",
                        subject.name()
                    ));
                }
                // Back to work: a read succeeds within two tries (the first may meet a late
                // reply's window, or the line that stopped echoing).
                let mut recovered = false;
                for _ in 0..2 {
                    if master.transact(&read_request(subject)).await.is_ok() {
                        recovered = true;
                        break;
                    }
                }
                if !recovered {
                    failures.push(format!(
                        "{} {name}: no read succeeded after it",
                        subject.name()
                    ));
                }
            }
            stop.store(true, Ordering::Relaxed);
            if let Ok(Err(error)) = server.join() {
                failures.push(format!("{}: serve loop: {error}", subject.name()));
            }
        });
    }
    assert!(cells >= 40, "{cells} cells");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
