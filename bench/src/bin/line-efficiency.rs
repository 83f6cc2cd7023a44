//! Line efficiency: our master against our virtual drive over a paced line (two
//! pseudo-terminals joined by relays that deliver bytes at the character rate of the
//! described line format), for every protocol of every described drive, at 9600 and
//! 115200 baud. Prints, as Markdown tables, the transactions a second reached against the
//! theoretical maximum of the exchange, the master thread's CPU time per transaction against
//! the exchange's wire time, and where the time beyond the model went.
//!
//! `cargo run --release -p vfd-bench --bin line-efficiency [-- SECONDS [BAUD...]]`
//! (SECONDS per run, default 4; baud rates default 9600 115200).
//!
//! The theoretical maximum of one exchange comes from the same description the master and
//! the drive use: the wire time of every frame (request, reply and any follow-up, as the
//! protocol encodes them for the register read), one frame gap after each frame (the
//! protocol's gap in characters or the drive's floor in milliseconds, whichever is longer;
//! none where the protocol states none) and the drive's reply delay at its factory setting
//! (the manual's minimum, 0, where the drive has one).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use vfd_bench::paced::{
    set_realtime, set_timer_slack, thread_cpu_time, thread_wakeups, PacedLine, RelayStats,
    DRIVE_PRIORITY,
};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{Direction, Recording, Transport};
use vfd_runtime::virtual_drive::{serve, Simulator};
use vfd_runtime::{Access, CommandKind, DataType, DriveInfo, Protocol, Request, Space};

/// One drive and protocol (variant) with the read the bench repeats.
struct Subject {
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    request: Request,
    code: &'static str,
}

impl Subject {
    fn label(&self) -> String {
        match self.protocol.variant_id() {
            Some(variant) => format!("{} ({variant})", self.protocol.id),
            None => self.protocol.id.to_string(),
        }
    }

    fn simulator(&self) -> Simulator {
        let sim = Simulator::new(self.drive);
        sim.lock().select_variant(self.protocol);
        sim
    }

    fn master<T: Transport>(
        &self,
        transport: T,
        settings: SerialSettings,
        sim: &Simulator,
    ) -> Master<T> {
        let address = sim.lock().address();
        Master::for_protocol(transport, self.protocol, settings, self.drive.serial.timing)
            .with_address(Some(address))
    }
}

/// The frames of one exchange as the description encodes them, and the model's time.
struct Model {
    /// Lengths of the master's frames (request, then any follow-up).
    sent: Vec<usize>,
    /// Length of the reply.
    reply: usize,
    /// The silence kept after every frame.
    gap: Duration,
    /// The drive's wait before replying, at its factory setting.
    reply_delay: Duration,
    /// Wire time of all frames.
    wire: Duration,
    /// Wire time, gaps and reply delay: the shortest an exchange can take.
    exchange: Duration,
}

impl Model {
    fn of(subject: &Subject, settings: SerialSettings) -> Result<Model, String> {
        let sim = subject.simulator();
        let mut master = subject.master(Recording::new(sim.link(subject.protocol)), settings, &sim);
        // Twice: the first read may need steps (a page switch) that later reads do not.
        for _ in 0..2 {
            master.transport_mut().clear();
            master
                .transact(&subject.request)
                .map_err(|e| format!("{} {}: {e}", subject.drive.id, subject.label()))?;
        }
        let mut sent = Vec::new();
        let mut reply = 0;
        for (direction, bytes) in master.transport().log() {
            match direction {
                Direction::Sent => sent.push(bytes.len()),
                Direction::Received => reply += bytes.len(),
            }
        }
        let gap = master.frame_gap();
        let reply_delay = sim.lock().reply_delay(subject.protocol) + master.reply_wait();
        let frames = sent.len() + 1;
        let wire = settings.wire_time(sent.iter().sum::<usize>() + reply);
        let exchange = wire + gap * u32::try_from(frames).unwrap_or(u32::MAX) + reply_delay;
        Ok(Model {
            sent,
            reply,
            gap,
            reply_delay,
            wire,
            exchange,
        })
    }

    fn frames(&self) -> String {
        let mut parts: Vec<String> = Vec::new();
        if let Some(first) = self.sent.first() {
            parts.push(first.to_string());
        }
        parts.push(self.reply.to_string());
        parts.extend(self.sent.iter().skip(1).map(|n| n.to_string()));
        parts.join(" + ")
    }
}

/// When things happened on the master's end during one exchange.
#[derive(Debug, Clone, Copy, Default)]
struct Marks {
    request_sent: Option<Instant>,
    first_byte: Option<Instant>,
    last_byte: Option<Instant>,
    follow_up_sent: Option<Instant>,
}

/// The master's end of the line, noting when frames go out and bytes come in.
struct Timed<T> {
    inner: T,
    marks: Marks,
}

impl<T: Transport> Transport for Timed<T> {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        let result = self.inner.send(bytes);
        let now = Instant::now();
        if self.marks.request_sent.is_none() {
            self.marks.request_sent = Some(now);
        } else {
            self.marks.follow_up_sent = Some(now);
        }
        result
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if got > 0 {
            let now = Instant::now();
            self.marks.first_byte.get_or_insert(now);
            self.marks.last_byte = Some(now);
        }
        Ok(got)
    }
    fn clear_input(&mut self) -> std::io::Result<()> {
        self.inner.clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }
}

/// Sums of the time each phase of an exchange took beyond the model.
#[derive(Debug, Default, Clone, Copy)]
struct Phases {
    exchanges: u32,
    /// From the request written to the reply's first byte, beyond request + gap + delay + 1
    /// character.
    turnaround: Duration,
    /// From the reply's first byte to its last, beyond the remaining characters.
    reply: Duration,
    /// From the reply's last byte to the next request (follow-up included), beyond the
    /// gaps and the follow-up's wire time.
    master: Duration,
}

struct Row {
    subject: String,
    drive: &'static str,
    line: String,
    model: Model,
    count: u32,
    errors: u32,
    first_error: Option<String>,
    /// Time the successful exchanges after a successful one took (each from the start of
    /// its `transact`, which keeps the gap after the exchange before, to its end), and
    /// their number: an exchange after a failed one first waits out the failed one's late
    /// reply, by design.
    ok_time: Duration,
    ok_count: u32,
    elapsed: Duration,
    cpu: Option<Duration>,
    /// Times the master's thread went to sleep (voluntary context switches) in the run.
    wakeups: Option<u64>,
    phases: Phases,
    to_drive: RelayStats,
    to_master: RelayStats,
}

impl Row {
    fn rate(&self) -> f64 {
        f64::from(self.count) / self.elapsed.as_secs_f64()
    }
    /// The rate of the successful exchanges that follow a successful one (the time failed
    /// ones and the recovery after them took left out).
    fn ok_rate(&self) -> f64 {
        f64::from(self.ok_count) / self.ok_time.as_secs_f64()
    }
    fn max_rate(&self) -> f64 {
        1.0 / self.model.exchange.as_secs_f64()
    }
    fn cpu_per_exchange(&self) -> Option<Duration> {
        self.cpu.map(|cpu| cpu / self.count.max(1))
    }
    fn wakeups_per_exchange(&self) -> Option<f64> {
        self.wakeups
            .map(|wakeups| wakeups as f64 / f64::from(self.count.max(1)))
    }
}

fn main() {
    let (seconds, bauds) = vfd_bench::first_and_bauds::<f64>(
        "line-efficiency [SECONDS [BAUD...]] (default 4 s per run at 9600 and 115200)",
        4.0,
        &[9600, 115_200],
    );
    if !seconds.is_finite() || seconds > 3600.0 {
        eprintln!("line-efficiency: {seconds} s per run is not a duration to run");
        std::process::exit(2);
    }
    // LINE_COARSE_TIMERS=1: the relays and the drive keep the default timer slack and
    // scheduling class.
    let fine = std::env::var_os("LINE_COARSE_TIMERS").is_none();
    if let Err(message) = run(Duration::from_secs_f64(seconds), &bauds, fine) {
        eprintln!("line-efficiency: {message}");
        std::process::exit(1);
    }
}

/// Every protocol (and variant) of every described drive, each with a read of one word.
fn subjects() -> Vec<Subject> {
    let mut subjects = Vec::new();
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols.iter().flat_map(|p| p.all_variants()) {
            let found = drive.registers.iter().copied().find_map(|info| {
                if info.space != Space::Parameter
                    || info.access == Access::WriteOnly
                    || info.data_type != DataType::Word
                    || info.array_len != 0
                    || protocol.page_of(info.address).is_some()
                {
                    return None;
                }
                let subject = Subject {
                    drive,
                    protocol,
                    request: Request::for_register(CommandKind::Read, info, 0),
                    code: info.code,
                };
                let settings = drive.serial.default;
                let sim = subject.simulator();
                let mut master = subject.master(sim.link(protocol), settings, &sim);
                master.transact(&subject.request).ok().map(|_| subject)
            });
            match found {
                Some(subject) => subjects.push(subject),
                None => eprintln!(
                    "{} {}: no readable word register, left out",
                    drive.id, protocol.id
                ),
            }
        }
    }
    subjects
}

fn run(duration: Duration, bauds: &[u32], fine: bool) -> Result<(), String> {
    let mut subjects = subjects();
    // LINE_ONLY="fc51 modbus": only the subjects whose drive and protocol label contain it.
    if let Some(only) = std::env::var_os("LINE_ONLY") {
        let only = only.to_string_lossy().into_owned();
        subjects.retain(|s| format!("{} {}", s.drive.id, s.label()).contains(&only));
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "Paced line, {} s per run; relays and drive: {}; master timer slack: {}; load average before: {}",
        duration.as_secs_f64(),
        if !fine {
            "default timer slack and scheduling"
        } else if realtime_granted() {
            "1 µs timer slack, real-time FIFO class (the master: normal class)"
        } else {
            "1 µs timer slack (real-time class refused)"
        },
        if std::env::var_os("LINE_MASTER_SLACK").is_some() {
            "1 µs"
        } else {
            "default (50 µs)"
        },
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    let mut all = Vec::new();
    for &baud in bauds {
        let mut rows = Vec::new();
        for subject in &subjects {
            let row = measure(subject, baud, duration, fine)?;
            eprintln!(
                "{baud} {} {}: {:.1}/s of {:.1}/s{}",
                row.drive,
                row.subject,
                row.rate(),
                row.max_rate(),
                row.first_error.as_ref().map_or(String::new(), |e| format!(
                    "; {} errors, the first: {e}",
                    row.errors
                ))
            );
            rows.push(row);
        }
        print_rates(baud, &rows);
        all.push((baud, rows));
    }
    for (baud, rows) in &all {
        print_phases(*baud, rows);
    }
    print_wake_costs().map_err(|e| format!("wake-up probe: {e}"))?;
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "Load average after: {}",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    Ok(())
}

fn measure(subject: &Subject, baud: u32, duration: Duration, fine: bool) -> Result<Row, String> {
    let io = |e: std::io::Error| format!("{} {}: {e}", subject.drive.id, subject.label());
    let settings = SerialSettings {
        baud,
        ..subject.drive.serial.default
    };
    let model = Model::of(subject, settings)?;
    let (master_end, mut drive_end, line) = PacedLine::open(settings, fine).map_err(io)?;
    let sim = subject.simulator();
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let (sim, stop, protocol) = (sim.clone(), Arc::clone(&stop), subject.protocol);
        std::thread::spawn(move || {
            if fine {
                set_timer_slack(Duration::from_micros(1));
                set_realtime(DRIVE_PRIORITY);
            }
            serve(&sim, protocol, &mut drive_end, settings, &stop)
        })
    };
    let transport = Timed {
        inner: master_end,
        marks: Marks::default(),
    };
    let mut master = subject.master(transport, settings, &sim);
    // LINE_MASTER_SLACK=1: the master's thread asks for 1 µs timer slack too (an
    // application's choice; the default is 50 µs).
    if std::env::var_os("LINE_MASTER_SLACK").is_some() {
        set_timer_slack(Duration::from_micros(1));
    }
    // Warm up: the page switch, if any, and the caches. A failure here (a relay late by
    // more than the drive's inner-gap limit) is counted like one in the run.
    let mut warm = 0;
    let mut warm_errors = 0;
    while warm < 5 {
        match master.transact(&subject.request) {
            Ok(_) => warm += 1,
            Err(error) if warm_errors < 5 => {
                warm_errors += 1;
                eprintln!("{} {} warm-up: {error}", subject.drive.id, subject.label());
            }
            Err(error) => {
                return Err(format!(
                    "{} {} warm-up: {error}",
                    subject.drive.id,
                    subject.label()
                ))
            }
        }
    }
    let char_time = settings.char_time();
    let mut phases = Phases::default();
    let mut count = 0u32;
    let mut errors = 0u32;
    let mut first_error = None;
    let mut ok_time = Duration::ZERO;
    let mut ok_count = 0u32;
    let mut previous: Option<Marks> = None;
    let cpu_before = thread_cpu_time();
    let wakeups_before = thread_wakeups();
    let start = Instant::now();
    while start.elapsed() < duration {
        master.transport_mut().marks = Marks::default();
        let began = Instant::now();
        match master.transact(&subject.request) {
            Ok(_) => {
                count += 1;
                if previous.is_some() {
                    ok_time += began.elapsed();
                    ok_count += 1;
                }
            }
            Err(error) => {
                errors += 1;
                first_error.get_or_insert_with(|| error.to_string());
                previous = None;
                continue;
            }
        }
        let marks = master.transport().marks;
        if let (Some(sent), Some(first), Some(last)) =
            (marks.request_sent, marks.first_byte, marks.last_byte)
        {
            let request_wire = settings.wire_time(model.sent[0]);
            let expected_turnaround = request_wire + model.gap + model.reply_delay + char_time;
            phases.turnaround += (first - sent).saturating_sub(expected_turnaround);
            phases.reply += (last - first).saturating_sub(char_time * (model.reply as u32 - 1));
            if let Some(before) = previous {
                let before_last = before.last_byte.unwrap_or(sent);
                let follow_ups: usize = model.sent.iter().skip(1).sum();
                let expected = settings.wire_time(follow_ups)
                    + model.gap * u32::try_from(model.sent.len()).unwrap_or(1);
                phases.master += (sent - before_last).saturating_sub(expected);
                phases.exchanges += 1;
            }
            previous = Some(marks);
        }
    }
    let elapsed = start.elapsed();
    let cpu = cpu_before.and_then(|before| Some(thread_cpu_time()? - before));
    let wakeups = wakeups_before.and_then(|before| Some(thread_wakeups()? - before));
    stop.store(true, Ordering::Relaxed);
    server
        .join()
        .map_err(|_| "the serve loop panicked".to_owned())?
        .map_err(io)?;
    let (to_drive, to_master) = line.stop().map_err(io)?;
    drop(master);
    Ok(Row {
        subject: format!("{} {}", subject.label(), subject.code),
        drive: subject.drive.id,
        line: format!(
            "{}{}{}",
            settings.data_bits,
            match settings.parity {
                vfd_runtime::serial::Parity::None => "N",
                vfd_runtime::serial::Parity::Even => "E",
                vfd_runtime::serial::Parity::Odd => "O",
            },
            settings.stop_bits
        ),
        model,
        count,
        errors,
        first_error,
        ok_time,
        ok_count,
        elapsed,
        cpu,
        wakeups,
        phases,
        to_drive,
        to_master,
    })
}

/// Whether this process may use the real-time class (tried on a scratch thread).
fn realtime_granted() -> bool {
    std::thread::spawn(|| set_realtime(DRIVE_PRIORITY))
        .join()
        .unwrap_or(false)
}

fn ms(d: Duration) -> String {
    format!("{:.2}", d.as_secs_f64() * 1e3)
}

fn us(d: Duration) -> String {
    format!("{:.0}", d.as_secs_f64() * 1e6)
}

fn print_rates(baud: u32, rows: &[Row]) {
    println!();
    println!("### {baud} baud");
    println!();
    println!("| Drive | Protocol, register read | Format | Frames (bytes) | Gap after each frame | Exchange in theory | Max/s | Measured/s | Efficiency | Failed exchanges | Without failures and recoveries: /s, efficiency | Master CPU per exchange | CPU / wire time | Master wake-ups per exchange |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for row in rows {
        let cpu = row.cpu_per_exchange();
        println!(
            "| {} | {} | {} | {} | {} ms | {} ms | {:.1} | {:.1} | {:.1} % | {} | {:.1}, {:.1} % | {} | {} | {} |",
            row.drive,
            row.subject,
            row.line,
            row.model.frames(),
            ms(row.model.gap),
            ms(row.model.exchange),
            row.max_rate(),
            row.rate(),
            100.0 * row.rate() / row.max_rate(),
            row.errors,
            row.ok_rate(),
            100.0 * row.ok_rate() / row.max_rate(),
            cpu.map_or("n/a".to_owned(), |c| format!("{} µs", us(c))),
            cpu.map_or("n/a".to_owned(), |c| format!(
                "{:.2} %",
                100.0 * c.as_secs_f64() / row.model.wire.as_secs_f64()
            )),
            row.wakeups_per_exchange()
                .map_or("n/a".to_owned(), |w| format!("{w:.2}")),
        );
    }
}

fn print_phases(baud: u32, rows: &[Row]) {
    println!();
    println!("### Where the time beyond the model goes, {baud} baud (mean per exchange, µs)");
    println!();
    println!("| Drive | Protocol | Exchange in theory | Measured exchange | Request to first reply byte | First to last reply byte | Last reply byte to next request | Relay lateness to drive: mean / p99 | to master: mean / p99 | Bytes over ½ character late |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for row in rows {
        let n = row.phases.exchanges.max(1);
        let measured = row.elapsed / row.count.max(1);
        println!(
            "| {} | {} | {} | {} | +{} | +{} | +{} | {} / {} | {} / {} | {} |",
            row.drive,
            row.subject,
            us(row.model.exchange),
            us(measured),
            us(row.phases.turnaround / row.count.max(1)),
            us(row.phases.reply / row.count.max(1)),
            us(row.phases.master / n),
            us(row.to_drive.late_mean()),
            us(row.to_drive.late_percentile(99.0)),
            us(row.to_master.late_mean()),
            us(row.to_master.late_percentile(99.0)),
            row.to_drive.late_over_half_char + row.to_master.late_over_half_char,
        );
    }
}

/// What one wake-up costs a thread of normal priority on this machine, the unit the
/// master's CPU per exchange is made of, and how late it comes: a sleep (overshoot past the
/// time asked), and a blocking pseudo-terminal read that one byte ends (from the write on
/// the other side to the read's return).
fn print_wake_costs() -> std::io::Result<()> {
    use vfd_runtime::transport::PseudoTerminal;
    const ROUNDS: u32 = 2000;
    println!();
    println!("### One wake-up of a normal thread on this machine");
    println!();
    println!("| Wait | Thread CPU per wake-up | Late: mean / p99 |");
    println!("|---|---|---|");
    for pause in [Duration::from_micros(100), Duration::from_millis(1)] {
        let mut late = Vec::with_capacity(ROUNDS as usize);
        let before = thread_cpu_time();
        for _ in 0..ROUNDS {
            let asked = Instant::now();
            std::thread::sleep(pause);
            late.push(asked.elapsed().saturating_sub(pause));
        }
        if let (Some(before), Some(after)) = (before, thread_cpu_time()) {
            println!(
                "| `thread::sleep({} µs)` | {:.1} µs | {} |",
                pause.as_micros(),
                (after - before).as_secs_f64() * 1e6 / f64::from(ROUNDS),
                lateness(&mut late)
            );
        }
        let (mut reader, mut writer) = PseudoTerminal::open()?.into_transports()?;
        let (sent_at, sent) = std::sync::mpsc::channel();
        let sender = std::thread::spawn(move || -> std::io::Result<()> {
            for _ in 0..ROUNDS {
                std::thread::sleep(pause);
                let now = Instant::now();
                writer.send(&[0x55])?;
                if sent_at.send(now).is_err() {
                    break;
                }
            }
            Ok(())
        });
        let mut buf = [0u8; 16];
        let mut received = 0u32;
        let mut late = Vec::with_capacity(ROUNDS as usize);
        let before = thread_cpu_time();
        let deadline = Instant::now() + Duration::from_secs(60);
        while received < ROUNDS {
            let got = reader.receive(&mut buf, deadline)?;
            if got == 0 {
                break;
            }
            let now = Instant::now();
            for _ in 0..got {
                if let Ok(at) = sent.recv() {
                    late.push(now.saturating_duration_since(at));
                }
            }
            received += u32::try_from(got).unwrap_or(1);
        }
        if let (Some(before), Some(after)) = (before, thread_cpu_time()) {
            println!(
                "| pseudo-terminal read woken by a byte every {} µs | {:.1} µs | {} |",
                pause.as_micros(),
                (after - before).as_secs_f64() * 1e6 / f64::from(received.max(1)),
                lateness(&mut late)
            );
        }
        drop(sent);
        sender.join().unwrap_or(Ok(()))?;
    }
    Ok(())
}

/// `mean / p99` of durations, in µs.
fn lateness(late: &mut [Duration]) -> String {
    late.sort();
    let mean = late.iter().sum::<Duration>() / u32::try_from(late.len().max(1)).unwrap_or(1);
    format!(
        "{} / {} µs",
        us(mean),
        us(vfd_bench::percentile(late, 99.0))
    )
}
