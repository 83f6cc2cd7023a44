//! Soak: our master against our virtual drive over pseudo-terminals (the `serve` loop, one
//! line per described protocol, all at once), with random faults from a seeded generator.
//! Every exchange must either succeed with the value the simulator holds or fail with the
//! typed error the fault injected for it explains; nothing may hang (a watchdog ends the
//! run) and memory must stay flat (resident set size after a warm-up quarter of the run and
//! at its end). After a faulted exchange the line is drained until quiet, so that each
//! error is its own fault's; late replies crossing into the next exchange are the fault
//! matrix's resync runs.
//!
//! In CI it runs for a few seconds. The long run, with the figures in RELIABILITY.md:
//! `SOAK_SECONDS=600 cargo test --release -p vfd-tests --test soak -- --nocapture`
//! (`SOAK_SEED` picks another sequence of requests and faults).

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::thread;
use std::time::{Duration, Instant};
use vfd_runtime::transaction::Master;
use vfd_runtime::virtual_drive::Fault;
use vfd_runtime::{CommandKind, Request};
use vfd_tests::fault_cases::{
    expected_for_write, faults, subjects, CountingLine, Kind, Served, Subject,
};
use vfd_tests::slack::LOADED_MACHINE;

/// Retries the master is configured with.
const RETRIES: u8 = 1;

/// One fault in this many exchanges, on average.
const FAULT_ONE_IN: u64 = 3;

/// Seconds the run lasts unless `SOAK_SECONDS` says otherwise.
const DEFAULT_SECONDS: u64 = 3;

/// Exchanges every line makes, past the end of the run when it has not made them yet: the
/// soak asserts work done, not a rate (a loaded machine makes fewer exchanges a second).
const MIN_EXCHANGES: u64 = 3;

/// A small seeded generator (SplitMix64): the same seed, the same requests and faults.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// What one line's run came to.
#[derive(Debug, Default)]
struct Tally {
    exchanges: u64,
    faults: BTreeMap<&'static str, u64>,
    outcomes: BTreeMap<String, u64>,
    /// Exchanges the fault injected for them does not explain (the first few, described).
    violations: Vec<String>,
    violation_count: u64,
    /// Writes that timed out as the master took their reply for the echo of a line that
    /// no longer echoes (allowed; see `Master::with_local_echo`).
    echo_timeouts: u64,
}

impl Tally {
    fn violation(&mut self, message: String) {
        self.violation_count += 1;
        if self.violations.len() < 10 {
            self.violations.push(message);
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Op {
    Read,
    ReadOther,
    Write(u32),
}

/// The resident set size of this process, in KiB (`VmRSS` in /proc/self/status).
fn rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Runs exchanges on one line until `stop` and [`MIN_EXCHANGES`] are reached, checking each.
fn run_line(subject: Subject, seed: u64, stop: &AtomicBool) -> Tally {
    let mut tally = Tally::default();
    let sim = subject.simulator();
    let (line, served) = match Served::start_with_slack(&sim, subject.protocol, LOADED_MACHINE) {
        Ok(started) => started,
        Err(error) => {
            tally.violation(format!("no pseudo-terminal: {error}"));
            return tally;
        }
    };
    let serial = subject.drive.serial;
    let own = sim.lock().address();
    let (low, high) = subject.protocol.address_range;
    let other = if own < high { own + 1 } else { low.max(1) };
    let (line, handle) = CountingLine::new(line, subject.protocol);
    let mut master = Master::for_protocol(line, subject.protocol, serial.default, serial.timing)
        .with_address(Some(own))
        .with_retries(RETRIES);
    // Frames a write takes (steps included), fault-free.
    let first = Request::for_register(subject.write_kind, subject.write, subject.value(0));
    if master.transact(&first).is_err() {
        tally.violation("the first, fault-free write failed".into());
    }
    let write_frames = handle.sent();
    // The line has echoed since the last fault-free read.
    let mut echo_learned = false;
    let mut rng = Rng(seed);
    let fault_list = faults();
    let mut n = 0u32;
    // The last exchanges, for messages.
    let mut recent = std::collections::VecDeque::new();
    while !stop.load(Ordering::Relaxed) || tally.exchanges < MIN_EXCHANGES {
        n += 1;
        let op = match rng.below(3) {
            0 => Op::Read,
            1 => Op::ReadOther,
            _ => Op::Write(subject.value(rng.below(1 << 16) as u32)),
        };
        let fault = (rng.below(FAULT_ONE_IN) == 0)
            .then(|| fault_list[rng.below(fault_list.len() as u64) as usize].clone());
        let (name, fault) = match fault {
            Some((name, fault)) => (name, Some(fault)),
            None => ("none", None),
        };
        *tally.faults.entry(name).or_default() += 1;
        let address = if fault == Some(Fault::AnswerBroadcast) {
            other
        } else {
            own
        };
        master = master.with_address(Some(address));
        if let Some(fault) = &fault {
            sim.inject(fault.clone());
        }
        let (request, info) = match op {
            Op::Read => (
                Request::for_register(CommandKind::Read, subject.read, 0),
                subject.read,
            ),
            Op::ReadOther => (
                Request::for_register(CommandKind::Read, subject.other, 0),
                subject.other,
            ),
            Op::Write(raw) => (
                Request::for_register(subject.write_kind, subject.write, raw),
                subject.write,
            ),
        };
        let result = master.transact(&request);
        sim.clear_faults();
        if fault.is_some() {
            // Each error must be the fault's own: what the fault leaves on the line (a late
            // reply, noise) is drained before the next exchange. Late replies crossing the
            // next exchange are the fault matrix's resync runs and the fault regressions.
            let limit = Duration::from_secs(5);
            if !handle.caught_up(&sim, limit)
                || !handle.drain_until_quiet(Duration::from_millis(100), limit)
            {
                tally.violation(format!("{}: the line does not settle", subject.name()));
                break;
            }
        }
        master = master.with_address(Some(own));
        tally.exchanges += 1;
        let kind = Kind::of(&result);
        *tally.outcomes.entry(kind.label()).or_default() += 1;
        let what = format!(
            "{} exchange {n} ({op:?}, fault {name}; before: {})",
            subject.name(),
            recent.iter().cloned().collect::<Vec<_>>().join(", ")
        );
        if recent.len() == 3 {
            recent.pop_front();
        }
        recent.push_back(format!("{op:?}/{name}/{}", kind.label()));
        // What the master owes: the value unless the fault explains an error; a read is
        // repeated after a fault of one reply, a write never.
        let owed = match (&fault, op) {
            (None, _) => Kind::Value,
            (Some(Fault::Noise), _) => Kind::Timeout,
            (Some(Fault::AnswerBroadcast), Op::Write(_)) if write_frames > 1 => Kind::Timeout,
            (Some(_), Op::Read | Op::ReadOther) => Kind::Value,
            (Some(fault), Op::Write(_)) => expected_for_write(fault, subject.protocol),
        };
        // Once the line has echoed, a reply identical to its request (a Modbus single
        // write, a Toshiba ASCII write) is taken for the echo until a read's reply shows
        // the line no longer echoes: the master chooses a timeout over a false success
        // (documented at `Master::with_local_echo`).
        let echo_taken = echo_learned && matches!(op, Op::Write(_)) && kind == Kind::Timeout;
        if fault == Some(Fault::EchoRequest) {
            echo_learned = true;
        } else if fault.is_none() && kind == Kind::Value && !matches!(op, Op::Write(_)) {
            echo_learned = false;
        }
        if kind != owed && echo_taken {
            tally.echo_timeouts += 1;
        }
        if kind != owed && !echo_taken {
            tally.violation(format!(
                "{what}: expected {}, got {}: {:?}",
                owed.label(),
                kind.label(),
                result.as_ref().err().map(ToString::to_string)
            ));
            continue;
        }
        if let Ok(answer) = result {
            let stored = sim.lock().raw(info.id);
            let right = match op {
                Op::Read | Op::ReadOther => answer.data == stored,
                Op::Write(raw) => stored == Some(raw) && answer.data.is_none_or(|echo| echo == raw),
            };
            if !right {
                tally.violation(format!(
                    "{what}: answered {:?}, the drive holds {stored:?}",
                    answer.data
                ));
            }
        }
    }
    // The serve loop stops before the master's end of the line closes.
    if let Err(error) = served.stop() {
        tally.violation(error);
    }
    drop(master);
    tally
}

#[test]
fn master_against_virtual_drive_with_random_faults() {
    let seconds = std::env::var("SOAK_SECONDS")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(DEFAULT_SECONDS);
    let seed = std::env::var("SOAK_SEED")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(0x5EED);
    let run = Duration::from_secs(seconds);
    let (subjects, left_out) = subjects();
    assert!(
        left_out.is_empty(),
        "protocols left out of the soak: {left_out:?}"
    );
    let stop = Arc::new(AtomicBool::new(false));
    let (done, results) = mpsc::channel();
    let started = Instant::now();
    for (i, subject) in subjects.iter().copied().enumerate() {
        let (stop, done) = (Arc::clone(&stop), done.clone());
        let seed = seed ^ (i as u64).wrapping_mul(0xA076_1D64_78BD_642F);
        thread::spawn(move || {
            let _ = done.send((subject.name(), run_line(subject, seed, &stop)));
        });
    }
    drop(done);
    thread::sleep(run / 4);
    let rss_warm = rss_kib();
    thread::sleep(run - run / 4);
    let rss_end = rss_kib();
    stop.store(true, Ordering::Relaxed);
    // An exchange lasts at most a few reply timeouts, and a line past the end of the run
    // makes at most MIN_EXCHANGES: far less than this.
    let limit = Duration::from_secs(30);
    let mut tallies = Vec::new();
    for _ in 0..subjects.len() {
        match results.recv_timeout(limit) {
            Ok(result) => tallies.push(result),
            Err(_) => panic!("a line still runs {limit:?} after the stop: it hangs"),
        }
    }
    let elapsed = started.elapsed();
    tallies.sort_by(|a, b| a.0.cmp(&b.0));

    let mut exchanges = 0;
    let mut faults_total: BTreeMap<&str, u64> = BTreeMap::new();
    let mut outcomes: BTreeMap<String, u64> = BTreeMap::new();
    let mut violations = Vec::new();
    let mut echo_timeouts = 0;
    eprintln!("\nsoak: {seconds} s, seed {seed}, {RETRIES} retry, one fault in {FAULT_ONE_IN}");
    for (name, tally) in &tallies {
        eprintln!(
            "  {name:<14} {:>7} exchanges, outcomes {:?}",
            tally.exchanges, tally.outcomes
        );
        exchanges += tally.exchanges;
        echo_timeouts += tally.echo_timeouts;
        for (fault, count) in &tally.faults {
            *faults_total.entry(fault).or_default() += count;
        }
        for (kind, count) in &tally.outcomes {
            *outcomes.entry(kind.clone()).or_default() += count;
        }
        if tally.violation_count > 0 {
            violations.push(format!(
                "{name}: {} violation(s), first: {}",
                tally.violation_count,
                tally.violations.join("\n    ")
            ));
        }
    }
    let faulted: u64 = faults_total
        .iter()
        .filter(|(name, _)| **name != "none")
        .map(|(_, n)| n)
        .sum();
    eprintln!("  total {exchanges} exchanges in {elapsed:.1?}, {faulted} with a fault");
    eprintln!("  faults injected: {faults_total:?}");
    eprintln!("  outcomes: {outcomes:?}");
    eprintln!(
        "  of which writes timed out after the line stopped echoing (allowed): {echo_timeouts}"
    );
    eprintln!(
        "  resident set: {} KiB after the first quarter, {} KiB at the end",
        rss_warm.map_or("?".into(), |k| k.to_string()),
        rss_end.map_or("?".into(), |k| k.to_string())
    );
    assert!(violations.is_empty(), "{}", violations.join("\n"));
    let short: Vec<String> = tallies
        .iter()
        .filter(|(_, tally)| tally.exchanges < MIN_EXCHANGES)
        .map(|(name, tally)| format!("{name}: {}", tally.exchanges))
        .collect();
    assert!(
        short.is_empty(),
        "lines with fewer than {MIN_EXCHANGES} exchanges: {short:?}"
    );
    if let (Some(warm), Some(end)) = (rss_warm, rss_end) {
        // Buffers are fixed or drained: the set may move by allocator noise, not grow with
        // the number of exchanges. 16 MiB is far above noise and far below a leak of a few
        // hundred bytes per exchange over a long run.
        assert!(
            end <= warm + 16 * 1024,
            "resident set grew from {warm} KiB to {end} KiB"
        );
    }
}
