//! The service on paced lines: `vfd serve` (the release binary, as a plant runs it) polling
//! virtual DV1 drives (Modbus RTU, 9600 baud 8E1) on paced pseudo-terminal lines (bytes
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
//! The first bus's rate and the write times are also measured with the service embedded in
//! this process (the library's `vfd_bus::ServiceCore`, as a Rust program runs it), its
//! CPU that of its own threads.
//!
//! `cargo build --release -p vfd-cli && cargo run --release -p vfd-bench --bin plant [-- SECONDS]`
//! (SECONDS per measurement, default 8).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{ChildStdin, Command, Stdio};
use std::time::{Duration, Instant};
use vfd_bench::embedded::InProcess;
use vfd_bench::service::{Measured, Service};
use vfd_bench::virtual_bus::{self, Exchange, Killed, VirtualBus, SETTINGS};
use vfd_drives::dv1;
use vfd_runtime::Protocol;

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

/// The plant file for `buses` (name, device, stations), polling 1001h-1003h every 10 ms.
fn plant_file(dir: &Path, buses: &[(String, &VirtualBus)], backoff_ms: u64) -> PathBuf {
    let mut text = String::from("buses:\n");
    for (name, bus) in buses {
        text.push_str(&format!(
            "  - name: {name}\n    port: {}\n    baud: 9600\n    parity: even\n    stop_bits: 1\n    offline_after: 3\n    backoff: {{ first_ms: {backoff_ms}, cap_ms: {backoff_ms} }}\n    drives:\n",
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

/// The exchange of one station's poll (1001h-1003h of a DV1).
fn model() -> Result<Exchange, String> {
    virtual_bus::exchange(&dv1::DRIVE, protocol(), FIRST, WORDS)
}

/// `n` DV1 stations speaking Modbus RTU.
fn dv1_bus(n: u8) -> Result<VirtualBus, String> {
    VirtualBus::start(&vec![(&dv1::DRIVE, protocol()); usize::from(n)])
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
    let limit = WORDS as f64 / model.time.as_secs_f64();
    println!(
        "## vfd serve on paced lines (9600 baud 8E1, DV1 Modbus RTU, 1001h-1003h per station)\n"
    );
    println!(
        "One station's poll on the wire: {:.2} ms (request {} bytes, reply, two frame gaps, reply delay); reply timeout {:.0} ms.\n",
        model.time.as_secs_f64() * 1e3,
        model.request_len,
        model.reply_timeout.as_secs_f64() * 1e3
    );

    // 1. One bus, 8 stations, flat out.
    let bus = dv1_bus(stations)?;
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
        Some(path) => Some((
            mqtt_latencies(&path, &dir, &plant, &bus, measure / 2, false)?,
            mqtt_latencies(&path, &dir, &plant, &bus, measure / 2, true)?,
        )),
        None => None,
    };
    // 1b and 2c. The same bus, the service embedded in this process (the library's core).
    let embedded = InProcess::start(&plant)?;
    std::thread::sleep(Duration::from_secs(2));
    let (rate_in, cpu_in) = flat_out(&embedded, "line1", measure);
    let embedded_latency = write_latencies(
        &bus,
        |value| embedded.write("line1", "d5", WRITTEN, value),
        measure / 2,
    )?;
    embedded.stop();
    println!("\n### The same bus, the service embedded in this process (`vfd_bus::ServiceCore`)\n");
    println!("| readings/s | wire limit | share of the limit | service threads' CPU | CPU per 100 readings/s |");
    println!("|---|---|---|---|---|");
    println!(
        "| {rate_in:.1} | {limit:.1} | {:.1} % | {} | {} |",
        100.0 * rate_in / limit,
        cpu_in.map_or("n/a".into(), |c| format!("{:.1} %", 100.0 * c)),
        cpu_in.map_or("n/a".into(), |c| format!(
            "{:.2} % of a core",
            100.0 * c / (rate_in / 100.0)
        )),
    );

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
    row(
        "a request handed to the embedded service core (`WriteRouter::send`)",
        embedded_latency,
    );
    match mqtt_latency {
        Some((default, nodelay)) => {
            row(
                "a `set` message published to mosquitto (mosquitto_pub -l), broker defaults",
                default,
            );
            row("the same, the broker with `set_tcp_nodelay true`", nodelay);
        }
        None => {
            println!("| a `set` message via mosquitto | SKIPPED: mosquitto not installed | | | | |")
        }
    }
    drop(bus);

    // 4. Four buses x 8 stations in one process.
    let buses: Vec<VirtualBus> = (0..4)
        .map(|_| dv1_bus(stations))
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

/// `bus`'s readings per second over `measure`, and the service's CPU over it (a share of
/// one core).
fn flat_out(service: &dyn Measured, bus: &str, measure: Duration) -> (f64, Option<f64>) {
    let (first, cpu_0, t0) = (
        service.tally().lock().unwrap().bus_readings(bus),
        service.cpu_time(),
        Instant::now(),
    );
    std::thread::sleep(measure);
    let elapsed = t0.elapsed().as_secs_f64();
    let readings = service.tally().lock().unwrap().bus_readings(bus) - first;
    let cpu = service
        .cpu_time()
        .zip(cpu_0)
        .map(|(b, a)| (b - a).as_secs_f64() / elapsed);
    (readings as f64 / elapsed, cpu)
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
/// `mosquitto_pub -l` (a line on its standard input is one message); `nodelay`: the broker
/// sends without Nagle's delay (`set_tcp_nodelay`, off by default).
fn mqtt_latencies(
    mosquitto: &Path,
    dir: &Path,
    plant: &Path,
    bus: &VirtualBus,
    during: Duration,
    nodelay: bool,
) -> Result<Vec<Duration>, String> {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map_err(|e| e.to_string())?
        .port();
    let config = dir.join("mosquitto.conf");
    std::fs::write(
        &config,
        format!(
            "listener {port} 127.0.0.1\npersistence false\nallow_anonymous true\nset_tcp_nodelay {nodelay}\n"
        ),
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
