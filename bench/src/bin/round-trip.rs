//! Round trip through pseudo-terminals against peers, in one run: our master and two Python
//! clients (pymodbus, minimalmodbus) doing the same Modbus RTU reads, first against our
//! virtual drive (no Python on the serving side), then against our virtual drive and a
//! pymodbus server in turn through a relay that times each server's turnaround.
//!
//! `pip install -r bench/python/requirements.txt`, then, from the workspace root (the
//! Python scripts are found by relative path),
//! `cargo run --release -p vfd-bench --bin round-trip [-- COUNT [BAUD...]]` (default 2000
//! reads per client at 115200 and 921600 baud).
//!
//! Pseudo-terminals do not pace bytes: the baud rate only sets the 3.5-character frame gap
//! that our master keeps before each request and our virtual drive keeps before each reply
//! (FC 51 describes no reply-delay register, so the virtual drive adds no other wait).
//!
//! Prints markdown tables ready to paste into BENCHMARKS.md.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use vfd_bench::percentile;
use vfd_drives::fc51;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{PseudoTerminal, PtyTransport, Transport};
use vfd_runtime::virtual_drive::{serve, Simulator};
use vfd_runtime::{CommandKind, DataType, Request, Space};

/// The register read: FC 51 parameter 303 (maximum reference), a double word in two
/// holding registers.
const REGISTER: &str = "maximum_reference";
/// Its value in both servers: 100.000, so both words are non-zero (0001h, 86A0h).
const VALUE: u32 = 100_000;
/// Reads before the measured ones, by every client.
const WARM_UP: usize = 20;

fn io(error: std::io::Error) -> String {
    error.to_string()
}

fn ms(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1000.0
}

/// The register's wire address (holding register = parameter x 10 - 1 on FC 51's Modbus),
/// from the protocol's own address map.
fn wire_address() -> Result<u16, String> {
    let info = fc51::DRIVE.register(REGISTER).ok_or("no register 303")?;
    let command = fc51::protocols::MODBUS
        .commands
        .iter()
        .find(|c| c.space == Space::Parameter)
        .ok_or("no parameter command")?;
    command
        .address_map
        .to_wire(info.address)
        .ok_or_else(|| "parameter 303 has no wire address".to_owned())
}

/// The one-minute load average, from /proc/loadavg.
fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|text| text.split_whitespace().next().map(str::to_owned))
        .unwrap_or_else(|| "?".to_owned())
}

/// Latencies of one client's reads, and (through the relay) each server turnaround.
struct Summary {
    latencies: Vec<Duration>,
    turnarounds: Vec<Duration>,
}

impl Summary {
    fn sorted(&self) -> Vec<Duration> {
        let mut sorted = self.latencies.clone();
        sorted.sort();
        sorted
    }

    fn rate(&self) -> f64 {
        let total: Duration = self.latencies.iter().sum();
        self.latencies.len() as f64 / total.as_secs_f64()
    }

    fn p(&self, p: f64) -> f64 {
        ms(percentile(&self.sorted(), p))
    }

    fn max(&self) -> f64 {
        ms(self.sorted().last().copied().unwrap_or_default())
    }

    fn turnaround(&self, p: f64) -> f64 {
        let mut sorted = self.turnarounds.clone();
        sorted.sort();
        ms(percentile(&sorted, p))
    }
}

/// What the master's transport saw of one transaction: when the request went out and when
/// the reply's first and last bytes came in.
#[derive(Default, Clone, Copy)]
struct Marks {
    send: Option<Instant>,
    first: Option<Instant>,
    last: Option<Instant>,
}

/// A transport that marks the times of [`Marks`] (a few `Instant::now` calls a transaction).
struct Timed<T> {
    inner: T,
    marks: Marks,
}

impl<T: Transport> Transport for Timed<T> {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.marks = Marks {
            send: Some(Instant::now()),
            ..Marks::default()
        };
        self.inner.send(bytes)
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if got > 0 {
            let now = Instant::now();
            self.marks.first.get_or_insert(now);
            self.marks.last = Some(now);
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

/// Where one vfd transaction's time went, p50 of each phase over the run.
struct Phases {
    before_send: Vec<Duration>,
    to_first_byte: Vec<Duration>,
    reply_bytes: Vec<Duration>,
    after_last_byte: Vec<Duration>,
}

fn median(values: &[Duration]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort();
    ms(percentile(&sorted, 50.0))
}

/// Line settings: 8N1, as Linux pseudo-terminals refuse parity settings (EINVAL), for
/// pyserial as for us.
fn settings(baud: u32) -> SerialSettings {
    SerialSettings {
        baud,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    }
}

/// `count` timed reads by our master on the terminal at `path`, every reply checked, and
/// where the time went.
fn vfd_client(
    path: &str,
    baud: u32,
    count: usize,
    address: u16,
    relay: Option<&Relay>,
) -> Result<(Summary, Phases), String> {
    let transport = PtyTransport::open_path(std::path::Path::new(path)).map_err(io)?;
    let mut master = Master::new(
        Timed {
            inner: transport,
            marks: Marks::default(),
        },
        &fc51::protocols::MODBUS,
        settings(baud),
        fc51::DRIVE.serial.timing,
    )
    .with_address(Some(1));
    let read = Request {
        wire_register: true,
        ..Request::raw(CommandKind::Read, address, 0).with_data_type(DataType::DoubleWord)
    };
    for _ in 0..WARM_UP {
        master.transact(&read).map_err(|e| e.to_string())?;
    }
    if let Some(relay) = relay {
        relay.clear();
    }
    let mut latencies = Vec::with_capacity(count);
    let mut phases = Phases {
        before_send: Vec::with_capacity(count),
        to_first_byte: Vec::with_capacity(count),
        reply_bytes: Vec::with_capacity(count),
        after_last_byte: Vec::with_capacity(count),
    };
    for _ in 0..count {
        let start = Instant::now();
        let answer = master.transact(&read).map_err(|e| e.to_string())?;
        let end = Instant::now();
        latencies.push(end - start);
        if answer.data != Some(VALUE) {
            return Err(format!(
                "vfd read {:08X?}, expected {VALUE:08X}h",
                answer.data
            ));
        }
        let marks = master.transport().marks;
        if let (Some(send), Some(first), Some(last)) = (marks.send, marks.first, marks.last) {
            phases.before_send.push(send - start);
            phases.to_first_byte.push(first - send);
            phases.reply_bytes.push(last - first);
            phases.after_last_byte.push(end - last);
        }
    }
    let turnarounds = relay.map(|r| r.turnarounds(count)).unwrap_or_default();
    Ok((
        Summary {
            latencies,
            turnarounds,
        },
        phases,
    ))
}

/// `count` timed reads by a Python client (`pymodbus` or `minimalmodbus`) on the terminal
/// at `path`; the script checks every reply. Returns its name and version too.
fn python_client(
    library: &str,
    path: &str,
    baud: u32,
    count: usize,
    address: u16,
    relay: Option<&Relay>,
) -> Result<(String, Summary), String> {
    if let Some(relay) = relay {
        relay.clear();
    }
    let output = Command::new("python3")
        .arg("bench/python/modbus_client.py")
        .arg(library)
        .arg(path)
        .args(
            [
                baud,
                count as u32,
                u32::from(address),
                VALUE >> 16,
                VALUE & 0xFFFF,
            ]
            .map(|n| n.to_string()),
        )
        .output()
        .map_err(|e| format!("cannot run python3: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "{library} client failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let name = text
        .split("\"client\": \"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .unwrap_or(library)
        .to_owned();
    let numbers = text
        .split('[')
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .unwrap_or("");
    let latencies: Vec<Duration> = numbers
        .split(',')
        .filter_map(|n| n.trim().parse::<u64>().ok())
        .map(Duration::from_nanos)
        .collect();
    if latencies.len() != count {
        return Err(format!(
            "{library} client reported {} reads",
            latencies.len()
        ));
    }
    let turnarounds = relay.map(|r| r.turnarounds(count)).unwrap_or_default();
    Ok((
        name,
        Summary {
            latencies,
            turnarounds,
        },
    ))
}

/// Which way a chunk went through the relay.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Way {
    ToServer,
    ToClient,
}

/// Joins the clients' pseudo-terminal to the server's, noting when each chunk arrived.
struct Relay {
    events: Arc<Mutex<Vec<(Instant, Way)>>>,
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
}

impl Relay {
    fn new(clients: PtyTransport, server: PtyTransport) -> Result<Relay, String> {
        let events = Arc::new(Mutex::new(Vec::with_capacity(1 << 16)));
        let stop = Arc::new(AtomicBool::new(false));
        let mut threads = Vec::new();
        for (way, from, to) in [
            (
                Way::ToServer,
                clients.try_clone().map_err(io)?,
                server.try_clone().map_err(io)?,
            ),
            (Way::ToClient, server, clients),
        ] {
            let (events, stop) = (Arc::clone(&events), Arc::clone(&stop));
            threads.push(std::thread::spawn(move || {
                forward(way, from, to, &events, &stop)
            }));
        }
        Ok(Relay {
            events,
            stop,
            threads,
        })
    }

    fn clear(&self) {
        self.events
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
    }

    /// The server's turnaround in the last `count` exchanges: from the request's last chunk
    /// to the reply's first chunk, as the relay received them.
    fn turnarounds(&self, count: usize) -> Vec<Duration> {
        let mut events = self
            .events
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone();
        events.sort_by_key(|(at, _)| *at);
        let mut request_end = None;
        let mut turnarounds = Vec::new();
        for (at, way) in events {
            match way {
                Way::ToServer => request_end = Some(at),
                Way::ToClient => {
                    if let Some(end) = request_end.take() {
                        turnarounds.push(at - end);
                    }
                }
            }
        }
        let skip = turnarounds.len().saturating_sub(count);
        turnarounds.split_off(skip)
    }

    fn close(self) {
        self.stop.store(true, Ordering::Relaxed);
        for thread in self.threads {
            let _ = thread.join();
        }
    }
}

fn forward(
    way: Way,
    mut from: PtyTransport,
    mut to: PtyTransport,
    events: &Mutex<Vec<(Instant, Way)>>,
    stop: &AtomicBool,
) {
    let mut buf = [0u8; 256];
    while !stop.load(Ordering::Relaxed) {
        match from.receive(&mut buf, Instant::now() + Duration::from_millis(50)) {
            Ok(0) => {}
            Ok(n) => {
                let at = Instant::now();
                if to.send(&buf[..n]).is_err() {
                    return;
                }
                events
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push((at, way));
            }
            Err(_) => return,
        }
    }
}

/// A server answering on one end of a pseudo-terminal.
enum Server {
    /// Our virtual drive, served by a thread of this process.
    Virtual {
        stop: Arc<AtomicBool>,
        thread: JoinHandle<std::io::Result<()>>,
    },
    /// The pymodbus server, a Python process.
    Pymodbus(Child),
}

impl Server {
    /// Our virtual FC 51 at station 1 speaking Modbus RTU, register 303 holding [`VALUE`].
    fn virtual_drive(mut end: PtyTransport, baud: u32) -> Server {
        let sim = Simulator::new(&fc51::DRIVE);
        sim.lock().set_address(1);
        sim.lock().set_raw(REGISTER, VALUE);
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let stop = Arc::clone(&stop);
            std::thread::spawn(move || {
                serve(
                    &sim,
                    fc51::protocols::MODBUS.protocol(),
                    &mut end,
                    settings(baud),
                    &stop,
                )
            })
        };
        Server::Virtual { stop, thread }
    }

    /// The pymodbus server on the terminal at `path`, holding [`VALUE`] at `address`.
    fn pymodbus(path: &str, baud: u32, address: u16) -> Result<Server, String> {
        let mut child = Command::new("python3")
            .arg("bench/python/modbus_server.py")
            .arg(path)
            .args([baud, u32::from(address), VALUE >> 16, VALUE & 0xFFFF].map(|n| n.to_string()))
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("cannot start the pymodbus server: {e}"))?;
        let mut line = String::new();
        BufReader::new(child.stdout.take().ok_or("no stdout")?)
            .read_line(&mut line)
            .map_err(io)?;
        Ok(Server::Pymodbus(child))
    }

    fn stop(self) {
        match self {
            Server::Virtual { stop, thread } => {
                stop.store(true, Ordering::Relaxed);
                let _ = thread.join();
            }
            Server::Pymodbus(mut child) => {
                let _ = child.kill();
                let _ = child.wait();
            }
        }
    }
}

/// Waits until the server at `path` answers (the pymodbus server opens its port only after
/// saying it is ready).
fn wait_for_server(path: &str, baud: u32, address: u16) -> Result<(), String> {
    let started = Instant::now();
    loop {
        match vfd_client(path, baud, 1, address, None) {
            Ok(_) => return Ok(()),
            Err(message) if started.elapsed() > Duration::from_secs(20) => {
                return Err(format!("the server does not answer: {message}"))
            }
            Err(_) => std::thread::sleep(Duration::from_millis(100)),
        }
    }
}

/// The three clients' results against one server.
struct Round {
    vfd: Summary,
    phases: Phases,
    peers: Vec<Result<(String, Summary), String>>,
}

fn three_clients(
    path: &str,
    baud: u32,
    count: usize,
    address: u16,
    relay: Option<&Relay>,
) -> Result<Round, String> {
    wait_for_server(path, baud, address)?;
    let (vfd, phases) = vfd_client(path, baud, count, address, relay)?;
    let peers = ["pymodbus", "minimalmodbus"]
        .iter()
        .map(|library| python_client(library, path, baud, count, address, relay))
        .collect();
    Ok(Round { vfd, phases, peers })
}

fn main() {
    let (count, bauds) = vfd_bench::first_and_bauds::<usize>(
        "round-trip [COUNT [BAUD...]] (default 2000 reads per client at 115200 and 921600)",
        2000,
        &[115_200, 921_600],
    );
    if let Err(message) = run(count, &bauds) {
        eprintln!("round-trip: {message}");
        std::process::exit(1);
    }
}

/// How long `thread::sleep(duration)` takes on this machine, p50 of 500 (the timer slack
/// and wake-up latency every sleep of a frame gap pays).
fn sleep_p50(duration: Duration) -> f64 {
    let mut taken: Vec<Duration> = (0..500)
        .map(|_| {
            let start = Instant::now();
            std::thread::sleep(duration);
            start.elapsed()
        })
        .collect();
    taken.sort();
    ms(percentile(&taken, 50.0))
}

/// Everything measured at one baud rate.
struct AtBaud {
    baud: u32,
    /// The three clients against our virtual drive, no relay.
    direct: Round,
    /// The three clients through the relay: our virtual drive, then the pymodbus server.
    relayed: Vec<Round>,
}

fn at_baud(count: usize, baud: u32, address: u16) -> Result<AtBaud, String> {
    // 1. Our virtual drive serves the pty's master side; each client opens the slave path.
    let direct = {
        let pty = PseudoTerminal::open().map_err(io)?;
        let path = pty.slave_path().display().to_string();
        let server = Server::virtual_drive(pty.master().map_err(io)?, baud);
        let round = three_clients(&path, baud, count, address, None);
        server.stop();
        round?
    };
    // 2. Each server in turn behind a relay: clients -> pty A -> relay -> pty B -> server.
    let mut relayed = Vec::new();
    for pymodbus in [false, true] {
        let clients = PseudoTerminal::open().map_err(io)?;
        let server_pty = PseudoTerminal::open().map_err(io)?;
        let path = clients.slave_path().display().to_string();
        let (server, relay) = if pymodbus {
            let server_path = server_pty.slave_path().display().to_string();
            let relay = Relay::new(
                clients.master().map_err(io)?,
                server_pty.master().map_err(io)?,
            )?;
            (Server::pymodbus(&server_path, baud, address)?, relay)
        } else {
            let (relay_end, server_end) = server_pty.into_transports().map_err(io)?;
            let relay = Relay::new(clients.master().map_err(io)?, relay_end)?;
            (Server::virtual_drive(server_end, baud), relay)
        };
        let round = three_clients(&path, baud, count, address, Some(&relay));
        server.stop();
        relay.close();
        relayed.push(round?);
    }
    Ok(AtBaud {
        baud,
        direct,
        relayed,
    })
}

/// The client names in table order (vfd first), from a round's results.
fn client_names(round: &Round) -> Vec<String> {
    let mut names = vec!["vfd (Rust, `Master`)".to_owned()];
    names.extend(round.peers.iter().map(|peer| match peer {
        Ok((name, _)) => name.clone(),
        Err(message) => message.clone(),
    }));
    names
}

/// A round's results in table order (vfd first); `None` for a client that failed.
fn summaries(round: &Round) -> Vec<Option<&Summary>> {
    std::iter::once(Some(&round.vfd))
        .chain(round.peers.iter().map(|p| p.as_ref().ok().map(|(_, s)| s)))
        .collect()
}

fn run(count: usize, bauds: &[u32]) -> Result<(), String> {
    let check = Command::new("python3")
        .args(["-c", "import pymodbus, serial, minimalmodbus"])
        .output();
    if !check.map(|o| o.status.success()).unwrap_or(false) {
        return Err(
            "the Python peers are missing: pip install -r bench/python/requirements.txt".to_owned(),
        );
    }
    let address = wire_address()?;
    let load_before = load();
    let results = bauds
        .iter()
        .map(|&baud| at_baud(count, baud, address))
        .collect::<Result<Vec<_>, String>>()?;
    let load_after = load();

    println!(
        "Modbus RTU read of FC 51 parameter 303 (03, two holding registers at {address:04X}h: \
         8-byte request, 9-byte reply, every reply checked for {VALUE}), {count} reads per client \
         after {WARM_UP} warm-up reads, 8N1. Load average (1 min) {load_before} before, \
         {load_after} after."
    );
    println!();
    println!("Against our virtual drive (served in this process on the pty's master side; each client opens the slave path):");
    println!();
    println!("| Baud (3.5-char gap) | Client | Reads/s | p50 | p90 | p99 | max | vfd reads/s ÷ client's |");
    println!("|---|---|---|---|---|---|---|---|");
    for result in &results {
        let gap = ms(settings(result.baud).char_time().mul_f32(3.5));
        let names = client_names(&result.direct);
        let vfd_rate = result.direct.vfd.rate();
        for (name, summary) in names.iter().zip(summaries(&result.direct)) {
            match summary {
                Some(s) => println!(
                    "| {} ({gap:.3} ms) | {name} | {:.0} | {:.3} ms | {:.3} ms | {:.3} ms | {:.3} ms | {:.1}x |",
                    result.baud,
                    s.rate(),
                    s.p(50.0),
                    s.p(90.0),
                    s.p(99.0),
                    s.max(),
                    vfd_rate / s.rate()
                ),
                None => println!("| {} | {name} | | | | | | |", result.baud),
            }
        }
    }
    println!();
    println!("Where vfd's read goes against the virtual drive (p50 of each phase):");
    println!();
    println!("| Baud | `thread::sleep` of the 3.5-char gap alone | Before the request is sent (frame gap kept, stale input dropped) | Request sent to the reply's first byte (the drive keeps the gap too) | First to last reply byte | Last byte to answer | Whole read |");
    println!("|---|---|---|---|---|---|---|");
    for result in &results {
        let phases = &result.direct.phases;
        println!(
            "| {} | {:.3} ms | {:.3} ms | {:.3} ms | {:.3} ms | {:.3} ms | {:.3} ms |",
            result.baud,
            sleep_p50(settings(result.baud).char_time().mul_f32(3.5)),
            median(&phases.before_send),
            median(&phases.to_first_byte),
            median(&phases.reply_bytes),
            median(&phases.after_last_byte),
            result.direct.vfd.p(50.0)
        );
    }
    println!();
    println!("Each server through a relay (client -> pty -> relay -> pty -> server). Turnaround: from the request's last chunk to the reply's first chunk, as the relay received them; \"added\": our virtual drive's turnaround p50 minus the pymodbus server's, same client:");
    println!();
    println!("| Baud | Client | Reads/s: ours / pymodbus server | p50: ours / pymodbus | Turnaround p50: ours / pymodbus | Turnaround p99: ours / pymodbus | Added by ours (p50) |");
    println!("|---|---|---|---|---|---|---|");
    for result in &results {
        let names = client_names(&result.relayed[0]);
        let ours = summaries(&result.relayed[0]);
        let theirs = summaries(&result.relayed[1]);
        for ((name, ours), theirs) in names.iter().zip(ours).zip(theirs) {
            match (ours, theirs) {
                (Some(a), Some(b)) => println!(
                    "| {} | {name} | {:.0} / {:.0} | {:.3} / {:.3} ms | {:.3} / {:.3} ms | {:.3} / {:.3} ms | {:+.3} ms |",
                    result.baud,
                    a.rate(),
                    b.rate(),
                    a.p(50.0),
                    b.p(50.0),
                    a.turnaround(50.0),
                    b.turnaround(50.0),
                    a.turnaround(99.0),
                    b.turnaround(99.0),
                    a.turnaround(50.0) - b.turnaround(50.0)
                ),
                _ => println!("| {} | {name} | failed | | | | |", result.baud),
            }
        }
    }
    Ok(())
}
