//! The service on paced lines: `vfd serve` (the release binary, as a plant runs it) polling
//! virtual DV1 drives (Modbus RTU, 9600 baud 8N1) on paced pseudo-terminal lines (bytes
//! delivered at the wire's character rate, `vfd_bench::paced`), with the drives served by
//! the runtime's multi-drop bus server in this process. Prints Markdown:
//!
//! 1. One bus, 8 stations, each polling three consecutive registers (status, frequency
//!    command, output frequency: one request) as fast as it can (`every: 10ms`): readings per second against the wire limit of that poll list (every
//!    station's exchange back to back: request and reply on the wire, a frame gap after
//!    each, the drive's reply delay), and the service's CPU and memory per 100 readings/s.
//! 2. The time from a write request to the drive having applied it: from a JSON line on
//!    `--stdin-writes`, and (when mosquitto is installed) from a `set` message published to
//!    a broker, against the write frame's own wire time.
//! 3. One station unplugged: the line time its tries cost per back-off period, against
//!    one reply timeout.
//! 4. One process, 4 paced buses x 8 stations: each bus's share of its wire limit and the
//!    service's CPU.
//!
//! `cargo build --release -p vfd-cli && cargo run --release -p vfd-bench --bin plant [-- SECONDS]`
//! (SECONDS per measurement, default 8).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use vfd_bench::paced::PacedLine;
use vfd_bench::service::Service;
use vfd_drives::dv1;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{Direction, PtyTransport, Recording};
use vfd_runtime::virtual_drive::{serve_bus, BusStation, Simulator};
use vfd_runtime::Protocol;

const SETTINGS: SerialSettings = SerialSettings {
    baud: 9600,
    parity: Parity::None,
    data_bits: 8,
    stop_bits: 1,
};

/// The first polled register (1001h, H7A status); H6D-HED (1002h, frequency command) and
/// H6F (1003h, output frequency) follow it.
const FIRST: u16 = 0x1001;

/// Registers per station's poll.
const WORDS: usize = 3;

/// The register the writes go to (the frequency command in RAM).
const WRITTEN: &str = "H6D-HED";

fn protocol() -> &'static Protocol {
    dv1::protocols::MODBUS.protocol()
}

/// One paced bus of virtual stations 1..=n.
struct VirtualBus {
    path: PathBuf,
    sims: Vec<Simulator>,
    _keep_open: PtyTransport,
    line: Option<PacedLine>,
    stop: Arc<AtomicBool>,
    server: Option<JoinHandle<std::io::Result<()>>>,
}

impl VirtualBus {
    fn start(stations: u8) -> Result<VirtualBus, String> {
        let (path, keep_open, mut drive_end, line) =
            PacedLine::open_for_path(SETTINGS, false).map_err(|e| e.to_string())?;
        let bus: Vec<BusStation> = (1..=stations)
            .map(|address| {
                let simulator = Simulator::new(&dv1::DRIVE);
                simulator.lock().set_address(address);
                BusStation {
                    simulator,
                    protocol: protocol(),
                }
            })
            .collect();
        let sims = bus.iter().map(|s| s.simulator.clone()).collect();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let server = std::thread::spawn(move || serve_bus(&bus, &mut drive_end, SETTINGS, &flag));
        Ok(VirtualBus {
            path,
            sims,
            _keep_open: keep_open,
            line: Some(line),
            stop,
            server: Some(server),
        })
    }
}

impl Drop for VirtualBus {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(line) = self.line.take() {
            let _ = line.stop();
        }
        if let Some(server) = self.server.take() {
            let _ = server.join();
        }
    }
}

/// The plant file for `buses` (name, device, stations), polling 1001h-1003h every 10 ms.
fn plant_file(dir: &Path, buses: &[(String, &VirtualBus)], backoff_ms: u64) -> PathBuf {
    let mut text = String::from("buses:\n");
    for (name, bus) in buses {
        text.push_str(&format!(
            "  - name: {name}\n    port: {}\n    baud: 9600\n    parity: none\n    offline_after: 3\n    backoff: {{ first_ms: {backoff_ms}, cap_ms: {backoff_ms} }}\n    drives:\n",
            bus.path.display()
        ));
        for address in 1..=bus.sims.len() {
            text.push_str(&format!(
                "      - name: d{address}\n        drive: dv1\n        protocol: modbus\n        station: {address}\n        poll:\n          - every: 10ms\n            registers: [H7A, H6D-HED, H6F]\n        write: [H6D-HED]\n"
            ));
        }
    }
    let path = dir.join(format!("plant-{}.yaml", buses.len()));
    std::fs::write(&path, text).expect("plant file");
    path
}

/// The shortest one station's poll can take on the wire: its frames as the description
/// encodes them, a frame gap after each, the drive's reply delay.
struct Model {
    exchange: Duration,
    request_len: usize,
    reply_timeout: Duration,
}

fn model() -> Result<Model, String> {
    let sim = Simulator::new(&dv1::DRIVE);
    sim.lock().set_address(1);
    let mut master = Master::for_protocol(
        Recording::new(sim.link(protocol())),
        protocol(),
        SETTINGS,
        dv1::DRIVE.serial.timing,
    )
    .with_address(Some(1));
    let mut words = [0u16; WORDS];
    master
        .read_words(FIRST, &mut words)
        .map_err(|e| e.to_string())?;
    let (mut sent, mut received, mut frames) = (0, 0, 0u32);
    for (direction, bytes) in master.transport().log() {
        frames += 1;
        match direction {
            Direction::Sent => sent += bytes.len(),
            Direction::Received => received += bytes.len(),
        }
    }
    let reply_delay = sim.lock().reply_delay(protocol()) + master.reply_wait();
    Ok(Model {
        exchange: SETTINGS.wire_time(sent + received) + master.frame_gap() * frames + reply_delay,
        request_len: sent,
        reply_timeout: master.reply_timeout(sent),
    })
}

fn main() {
    let seconds: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(8);
    if let Err(e) = run(Duration::from_secs(seconds)) {
        eprintln!("plant bench: {e}");
        std::process::exit(1);
    }
}

fn run(measure: Duration) -> Result<(), String> {
    let dir = std::env::temp_dir().join(format!("vfd-plant-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let model = model()?;
    let stations = 8u8;
    let limit = WORDS as f64 / model.exchange.as_secs_f64();
    println!(
        "## vfd serve on paced lines (9600 baud 8N1, DV1 Modbus RTU, 1001h-1003h per station)\n"
    );
    println!(
        "One station's poll on the wire: {:.2} ms (request {} bytes, reply, two frame gaps, reply delay); reply timeout {:.0} ms.\n",
        model.exchange.as_secs_f64() * 1e3,
        model.request_len,
        model.reply_timeout.as_secs_f64() * 1e3
    );

    // 1. One bus, 8 stations, flat out.
    let bus = VirtualBus::start(stations)?;
    let plant = plant_file(&dir, &[("line1".to_owned(), &bus)], 2000);
    let mut service = Service::start(&plant)?;
    std::thread::sleep(Duration::from_secs(2));
    let (readings_0, cpu_0, t0) = (
        service.tally.lock().unwrap().bus_readings("line1"),
        service.cpu_time(),
        Instant::now(),
    );
    let rss_early = service.memory_kib();
    std::thread::sleep(measure);
    let elapsed = t0.elapsed().as_secs_f64();
    let readings = service.tally.lock().unwrap().bus_readings("line1") - readings_0;
    let cpu = service
        .cpu_time()
        .zip(cpu_0)
        .map(|(b, a)| (b - a).as_secs_f64());
    let rss_late = service.memory_kib();
    let rate = readings as f64 / elapsed;
    println!("### Polling 8 stations on one bus\n");
    println!("| readings/s | wire limit | share of the limit | service CPU | CPU per 100 readings/s | RSS after 2 s / after {:.0} s (peak) |", 2.0 + elapsed);
    println!("|---|---|---|---|---|---|");
    println!(
        "| {rate:.1} | {limit:.1} | {:.1} % | {} | {} | {} / {} |",
        100.0 * rate / limit,
        cpu.map_or("n/a".into(), |c| format!("{:.1} %", 100.0 * c / elapsed)),
        cpu.map_or("n/a".into(), |c| format!(
            "{:.2} % of a core",
            100.0 * c / elapsed / (rate / 100.0)
        )),
        rss_early.map_or("n/a".into(), |(rss, _)| format!("{rss} KiB")),
        rss_late.map_or("n/a".into(), |(rss, peak)| format!(
            "{rss} KiB ({peak} KiB)"
        )),
    );

    // 3. Station 8 unplugged: the others' rate, and the line time its tries cost.
    let backoff = Duration::from_secs(2);
    bus.sims[7].set_unplugged(true);
    // Offline after 3 failed rounds, then steady.
    std::thread::sleep(Duration::from_secs(4));
    let others = |tally: &vfd_bench::service::Tally| -> u64 {
        (1..8)
            .map(|i| {
                tally
                    .readings
                    .get(&("line1".to_owned(), format!("d{i}")))
                    .copied()
                    .unwrap_or(0)
            })
            .sum()
    };
    let (before, t1) = (others(&service.tally.lock().unwrap()), Instant::now());
    std::thread::sleep(measure);
    let dead_rate =
        (others(&service.tally.lock().unwrap()) - before) as f64 / t1.elapsed().as_secs_f64();
    bus.sims[7].set_unplugged(false);
    // 2a. Writes through standard input, while the 8 stations are polled.
    std::thread::sleep(Duration::from_secs(3));
    let stdin_latency = write_latencies(
        &bus,
        |value| service.write("line1", "d5", WRITTEN, value),
        measure / 2,
    )?;
    // Per second of line time: the 7 stations' exchanges plus the tries of the 8th; with
    // all 8 answering, each reading took 1/rate of the line. The tries' share of the line
    // is what the 7 stations lost against the rate all 8 had, per reading.
    let lost_share = 1.0 - dead_rate / rate;
    let per_period = backoff.as_secs_f64() * lost_share;
    println!(
        "\n### One of the 8 stations unplugged (back-off {} s, constant)\n",
        backoff.as_secs()
    );
    println!("| the 7 others' readings/s | all 8 answering | line time its tries cost per back-off period | one reply timeout + request |");
    println!("|---|---|---|---|");
    println!(
        "| {dead_rate:.1} | {rate:.1} | {:.0} ms | {:.0} ms |",
        per_period * 1e3,
        (model.reply_timeout + SETTINGS.wire_time(model.request_len)).as_secs_f64() * 1e3
    );

    // 2b. Through a broker, when there is one (by a service of its own on the same line).
    service.stop();
    let mqtt_latency = match mosquitto() {
        Some(path) => Some(mqtt_latencies(&path, &dir, &plant, &bus, measure / 2)?),
        None => None,
    };
    println!(
        "\n### From a write request to the drive having applied it (while the 8 stations are polled)\n"
    );
    println!("| from | n | median | 90th percentile | max | the write frame's own wire time |");
    println!("|---|---|---|---|---|---|");
    let frame = SETTINGS.wire_time(8);
    let row = |from: &str, mut l: Vec<Duration>| {
        l.sort();
        if l.is_empty() {
            println!("| {from} | 0 | | | | |");
            return;
        }
        println!(
            "| {from} | {} | {:.1} ms | {:.1} ms | {:.1} ms | {:.1} ms |",
            l.len(),
            vfd_bench::percentile(&l, 50.0).as_secs_f64() * 1e3,
            vfd_bench::percentile(&l, 90.0).as_secs_f64() * 1e3,
            l.last().unwrap().as_secs_f64() * 1e3,
            frame.as_secs_f64() * 1e3
        );
    };
    row("a JSON line on --stdin-writes", stdin_latency);
    match mqtt_latency {
        Some(l) => row(
            "a `set` message published to mosquitto (mosquitto_pub -l)",
            l,
        ),
        None => {
            println!("| a `set` message via mosquitto | SKIPPED: mosquitto not installed | | | | |")
        }
    }
    drop(bus);

    // 4. Four buses x 8 stations in one process.
    let buses: Vec<VirtualBus> = (0..4)
        .map(|_| VirtualBus::start(stations))
        .collect::<Result<_, _>>()?;
    let named: Vec<(String, &VirtualBus)> = buses
        .iter()
        .enumerate()
        .map(|(i, b)| (format!("line{}", i + 1), b))
        .collect();
    let plant = plant_file(&dir, &named, 2000);
    let service = Service::start(&plant)?;
    std::thread::sleep(Duration::from_secs(3));
    let start: Vec<u64> = named
        .iter()
        .map(|(n, _)| service.tally.lock().unwrap().bus_readings(n))
        .collect();
    let (cpu_0, t0) = (service.cpu_time(), Instant::now());
    std::thread::sleep(measure);
    let elapsed = t0.elapsed().as_secs_f64();
    let cpu = service
        .cpu_time()
        .zip(cpu_0)
        .map(|(b, a)| (b - a).as_secs_f64());
    println!("\n### One process, 4 paced buses x 8 stations\n");
    println!("| bus | readings/s | share of its wire limit |");
    println!("|---|---|---|");
    let mut total = 0.0;
    for ((name, _), first) in named.iter().zip(&start) {
        let rate = (service.tally.lock().unwrap().bus_readings(name) - first) as f64 / elapsed;
        total += rate;
        println!("| {name} | {rate:.1} | {:.1} % |", 100.0 * rate / limit);
    }
    println!(
        "\nService CPU: {} for {total:.0} readings/s ({}); RSS {}.",
        cpu.map_or("n/a".into(), |c| format!(
            "{:.1} % of a core",
            100.0 * c / elapsed
        )),
        cpu.map_or("n/a".into(), |c| format!(
            "{:.2} % of a core per 100 readings/s",
            100.0 * c / elapsed / (total / 100.0)
        )),
        service
            .memory_kib()
            .map_or("n/a".into(), |(rss, peak)| format!(
                "{rss} KiB (peak {peak} KiB)"
            ))
    );
    service.stop();
    drop(buses);
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// Asks for writes of station 5's frequency command (one value after another, `send` asks) spread over
/// `during`, and times each until the drive holds the value.
fn write_latencies(
    bus: &VirtualBus,
    mut send: impl FnMut(&str) -> Result<(), String>,
    during: Duration,
) -> Result<Vec<Duration>, String> {
    let sim = &bus.sims[4];
    let mut latencies = Vec::new();
    let end = Instant::now() + during;
    let mut hz = 10.0;
    while Instant::now() < end {
        hz += 0.5;
        let raw = (hz * 100.0f64).round() as u32;
        let asked = Instant::now();
        send(&format!("{hz:.2} Hz"))?;
        while sim.lock().raw(WRITTEN) != Some(raw) {
            if asked.elapsed() > Duration::from_secs(3) {
                return Err(format!(
                    "the write of {hz} Hz did not reach the drive within 3 s"
                ));
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        latencies.push(asked.elapsed());
        std::thread::sleep(Duration::from_millis(150));
    }
    Ok(latencies)
}

fn mosquitto() -> Option<PathBuf> {
    ["/usr/sbin/mosquitto", "/usr/local/sbin/mosquitto"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
}

/// The same through a private mosquitto, with a `vfd serve --mqtt` of its own polling the
/// same bus (the `--jsonl` one has stopped), and `set` messages published by one
/// `mosquitto_pub -l` (a line on its standard input is one message).
fn mqtt_latencies(
    mosquitto: &Path,
    dir: &Path,
    plant: &Path,
    bus: &VirtualBus,
    during: Duration,
) -> Result<Vec<Duration>, String> {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map_err(|e| e.to_string())?
        .port();
    let config = dir.join("mosquitto.conf");
    std::fs::write(
        &config,
        format!("listener {port} 127.0.0.1\npersistence false\nallow_anonymous true\n"),
    )
    .map_err(|e| e.to_string())?;
    let mut broker = Killed(
        Command::new(mosquitto)
            .arg("-c")
            .arg(&config)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| e.to_string())?,
    );
    let end = Instant::now() + Duration::from_secs(5);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        if Instant::now() > end {
            return Err("mosquitto did not listen".into());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let service = Killed(
        Command::new(vfd_bench::service::vfd_binary()?)
            .arg("serve")
            .arg(plant)
            .args([
                "--mqtt",
                &format!("mqtt://127.0.0.1:{port}"),
                "--mqtt-client-id",
                "vfd-plant-bench",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| e.to_string())?,
    );
    let mut publisher = Killed(
        Command::new("mosquitto_pub")
            .args([
                "-h",
                "127.0.0.1",
                "-p",
                &port.to_string(),
                "-q",
                "1",
                "-l",
                "-t",
                "vfd/line1/d5/H6D-HED/set",
            ])
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("mosquitto_pub: {e}"))?,
    );
    std::thread::sleep(Duration::from_secs(2));
    let stdin: &mut ChildStdin = publisher.0.stdin.as_mut().ok_or("no stdin")?;
    let latencies = write_latencies(
        bus,
        |value| {
            writeln!(stdin, "{value}")
                .and_then(|()| stdin.flush())
                .map_err(|e| e.to_string())
        },
        during,
    );
    drop(publisher);
    drop(service);
    broker.0.kill().ok();
    latencies
}

/// A child killed when dropped.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = Command::new("kill").arg(self.0.id().to_string()).status();
        let _ = self.0.wait();
    }
}
