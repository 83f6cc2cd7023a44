//! The service at scale: 8 paced buses x 16 stations (128 virtual drives of three models:
//! DV1, VF-AS1 and GS2 in turn on every bus, all on Modbus RTU at 9600 baud 8E1), every
//! station polled as fast as its line carries (`every: 10ms`), in one process. Run with the
//! `vfd serve` binary (`--jsonl --stdin-writes`, a child process) and with the library's
//! service core embedded in this process (`vfd_bus::ServiceCore`). Prints Markdown:
//!
//! 1. Each bus's readings per second against its wire limit (every station's exchange back
//!    to back: request and reply on the wire, a frame gap after each, the drive's reply
//!    delay; the models' exchanges differ, so the limit is the bus's sum).
//! 2. The service's CPU over the whole run (a share of one core) and its resident memory,
//!    sampled every minute: flat, or growing.
//! 3. One station of bus 1 unplugged (back-off 2 s, constant): the line time its tries
//!    cost per back-off period, against one reply timeout and its request.
//! 4. The time from a write request (a JSON line on standard input; a request handed to
//!    the embedded core) to the drive holding the value, while all 128 are polled.
//!
//! `cargo build --release -p vfd-cli && cargo run --release -p vfd-bench --bin plant-scale
//! [-- MINUTES [binary|library|both]]` (default: 10 minutes, both).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use vfd_bench::embedded::InProcess;
use vfd_bench::service::{Measured, Service};
use vfd_bench::virtual_bus::{self, Exchange, VirtualBus, SETTINGS};
use vfd_bus::Catalogue;
use vfd_runtime::{DriveInfo, Protocol};

/// Buses, unless `PLANT_SCALE_BUSES` says another number (to tell the machine's limits from
/// the line's).
fn buses() -> usize {
    std::env::var("PLANT_SCALE_BUSES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(8)
}
const STATIONS: usize = 16;
const BACK_OFF: Duration = Duration::from_secs(2);

/// A model on the buses: its id, the registers each station of it polls (consecutive: one
/// request), and the register written in the write measurement (`None`: not written).
struct Model {
    id: &'static str,
    polled: &'static [&'static str],
    written: Option<&'static str>,
}

const MODELS: [Model; 3] = [
    Model {
        id: "dv1",
        polled: &["H7A", "H6D-HED", "H6F"],
        written: Some("H6D-HED"),
    },
    Model {
        id: "vf-as1",
        polled: &["FD00"],
        written: None,
    },
    Model {
        id: "gs2",
        polled: &["2103h"],
        written: None,
    },
];

/// One model, resolved: the drive, its Modbus protocol, its poll's exchange.
struct Resolved {
    model: &'static Model,
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    exchange: Exchange,
}

fn resolve(catalogue: &Catalogue) -> Result<Vec<Resolved>, String> {
    // `PLANT_SCALE_MODELS=dv1`: only the models named (comma-separated), to tell mixed
    // models on one line from the rest.
    let only = std::env::var("PLANT_SCALE_MODELS").ok();
    MODELS
        .iter()
        .filter(|model| {
            only.as_deref()
                .is_none_or(|list| list.split(',').any(|id| id == model.id))
        })
        .map(|model| {
            let drive = catalogue.drive(model.id).map_err(|e| e.to_string())?;
            let protocol =
                vfd_bus::lookup::protocol(drive, Some("modbus")).map_err(|e| e.to_string())?;
            let first = vfd_bus::lookup::register_for(drive, model.polled[0], false, model.id)
                .map_err(|e| e.to_string())?;
            let exchange =
                virtual_bus::exchange(drive, protocol, first.address, model.polled.len())?;
            Ok(Resolved {
                model,
                drive,
                protocol,
                exchange,
            })
        })
        .collect()
}

/// The model of station `address` (1-based): the three in turn.
fn model_of(models: &[Resolved], address: usize) -> &Resolved {
    &models[(address - 1) % models.len()]
}

fn plant_file(dir: &Path, buses: &[VirtualBus], models: &[Resolved]) -> PathBuf {
    let mut text = String::from("buses:\n");
    for (b, bus) in buses.iter().enumerate() {
        text.push_str(&format!(
            "  - name: line{}\n    port: {}\n    baud: 9600\n    parity: even\n    stop_bits: 1\n    offline_after: 3\n    backoff: {{ first_ms: {ms}, cap_ms: {ms} }}\n    drives:\n",
            b + 1,
            bus.path.display(),
            ms = BACK_OFF.as_millis()
        ));
        for address in 1..=bus.sims.len() {
            let model = model_of(models, address).model;
            text.push_str(&format!(
                "      - name: d{address}\n        drive: {}\n        protocol: modbus\n        station: {address}\n        poll:\n          - every: 10ms\n            registers: [{}]\n",
                model.id,
                model.polled.join(", ")
            ));
            if let Some(written) = model.written {
                text.push_str(&format!("        write: [{written}]\n"));
            }
        }
    }
    let path = dir.join("plant-scale.yaml");
    std::fs::write(&path, text).expect("plant file");
    path
}

/// Line time per second (a share of the line) the readings of `stations` (address, count
/// per second) took, from each model's exchange.
fn busy(models: &[Resolved], stations: impl Iterator<Item = (usize, f64)>) -> f64 {
    stations
        .map(|(address, per_second)| {
            let model = model_of(models, address);
            per_second / model.model.polled.len() as f64 * model.exchange.time.as_secs_f64()
        })
        .sum()
}

/// Readings per second of each station of `bus` between two tallies `elapsed` apart.
fn station_rates(
    before: &std::collections::HashMap<(String, String), u64>,
    after: &std::collections::HashMap<(String, String), u64>,
    bus: &str,
    elapsed: f64,
) -> Vec<(usize, f64)> {
    (1..=STATIONS)
        .map(|address| {
            let key = (bus.to_owned(), format!("d{address}"));
            let n = after.get(&key).copied().unwrap_or(0) - before.get(&key).copied().unwrap_or(0);
            (address, n as f64 / elapsed)
        })
        .collect()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let minutes: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(10);
    let which = args.next().unwrap_or_else(|| "both".to_owned());
    if let Err(e) = run(minutes, &which) {
        eprintln!("plant-scale bench: {e}");
        std::process::exit(1);
    }
}

fn run(minutes: u64, which: &str) -> Result<(), String> {
    let dir = std::env::temp_dir().join(format!("vfd-plant-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let catalogue = Catalogue::new();
    let models = resolve(&catalogue)?;
    println!(
        "## {} paced buses x {STATIONS} stations in one process (9600 baud 8E1, Modbus RTU)\n",
        buses()
    );
    println!("| model | polled (one request) | one poll on the wire | reply timeout |");
    println!("|---|---|---|---|");
    for m in &models {
        println!(
            "| {} | {} | {:.2} ms | {:.0} ms |",
            m.model.id,
            m.model.polled.join(", "),
            m.exchange.time.as_secs_f64() * 1e3,
            m.exchange.reply_timeout.as_secs_f64() * 1e3
        );
    }
    let round: f64 = (1..=STATIONS)
        .map(|a| model_of(&models, a).exchange.time.as_secs_f64())
        .sum();
    let per_round: usize = (1..=STATIONS)
        .map(|a| model_of(&models, a).model.polled.len())
        .sum();
    let limit = per_round as f64 / round;
    println!(
        "\nA bus's round (16 stations' polls back to back): {:.1} ms, {per_round} readings: wire limit {limit:.1} readings/s per bus.\n",
        round * 1e3
    );
    for mode in ["binary", "library"] {
        if which != "both" && which != mode {
            continue;
        }
        let buses: Vec<VirtualBus> = (0..buses())
            .map(|_| {
                let stations: Vec<(&'static DriveInfo, &'static Protocol)> = (1..=STATIONS)
                    .map(|a| {
                        let m = model_of(&models, a);
                        (m.drive, m.protocol)
                    })
                    .collect();
                VirtualBus::start(&stations)
            })
            .collect::<Result<_, _>>()?;
        let plant = plant_file(&dir, &buses, &models);
        let mut service: Box<dyn Measured> = match mode {
            "binary" => Box::new(Service::start(&plant)?),
            _ => Box::new(InProcess::start(&plant)?),
        };
        measure(&mut *service, mode, &buses, &models, limit, minutes)?;
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

fn measure(
    service: &mut dyn Measured,
    mode: &str,
    buses: &[VirtualBus],
    models: &[Resolved],
    limit: f64,
    minutes: u64,
) -> Result<(), String> {
    let title = match mode {
        "binary" => "the `vfd serve` binary (`--jsonl --stdin-writes`, a child process; CPU and memory its own)",
        _ => "the service core embedded in this process (`vfd_bus::ServiceCore`; CPU of its own threads, memory of the whole process with its 128 virtual drives and 8 paced lines)",
    };
    println!("### {title}\n");
    std::thread::sleep(Duration::from_secs(5));
    let first = service.tally().lock().unwrap().readings.clone();
    let (cpu_0, t0) = (service.cpu_time(), Instant::now());
    let mut samples = Vec::new();
    for minute in 1..=minutes {
        while t0.elapsed() < Duration::from_secs(60 * minute) {
            std::thread::sleep(Duration::from_millis(500));
        }
        samples.push(service.memory_kib().map_or(0, |(rss, _)| rss));
    }
    let elapsed = t0.elapsed().as_secs_f64();
    let cpu = service
        .cpu_time()
        .zip(cpu_0)
        .map(|(b, a)| (b - a).as_secs_f64() / elapsed);
    let last = service.tally().lock().unwrap().readings.clone();
    println!("| bus | readings/s | share of its wire limit ({limit:.1}/s) |");
    println!("|---|---|---|");
    let (mut total, mut lowest) = (0.0, f64::MAX);
    for b in 1..=buses.len() {
        let name = format!("line{b}");
        let rate: f64 = station_rates(&first, &last, &name, elapsed)
            .iter()
            .map(|(_, r)| r)
            .sum();
        total += rate;
        lowest = lowest.min(rate / limit);
        println!("| {name} | {rate:.1} | {:.1} % |", 100.0 * rate / limit);
    }
    println!(
        "\nOver {minutes} min: {total:.0} readings/s in all, the lowest bus at {:.1} % of its limit; service CPU {} ({}).",
        100.0 * lowest,
        cpu.map_or("n/a".into(), |c| format!("{:.2} % of one core", 100.0 * c)),
        cpu.map_or("n/a".into(), |c| format!(
            "{:.2} % per 100 readings/s",
            100.0 * c / (total / 100.0)
        )),
    );
    println!(
        "Resident memory each minute (KiB): {}.\n",
        samples
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    );

    // A dead station: the last of bus 1.
    let all_busy = busy(
        models,
        station_rates(&first, &last, "line1", elapsed).into_iter(),
    );
    buses[0].sims[STATIONS - 1].set_unplugged(true);
    std::thread::sleep(Duration::from_secs(4));
    let before = service.tally().lock().unwrap().readings.clone();
    let t1 = Instant::now();
    std::thread::sleep(Duration::from_secs(20));
    let after = service.tally().lock().unwrap().readings.clone();
    let others = station_rates(&before, &after, "line1", t1.elapsed().as_secs_f64())
        .into_iter()
        .filter(|(a, _)| *a != STATIONS);
    let others_busy = busy(models, others);
    buses[0].sims[STATIONS - 1].set_unplugged(false);
    let dead = model_of(models, STATIONS);
    println!(
        "Station {STATIONS} of line1 unplugged ({}): the line busy {:.1} % with it answering, {:.1} % for the other 15 without it: its tries cost {:.0} ms per {} s back-off period (bound: one reply timeout and its request, {:.0} ms).\n",
        dead.model.id,
        100.0 * all_busy,
        100.0 * others_busy,
        (all_busy - others_busy).max(0.0) * BACK_OFF.as_secs_f64() * 1e3,
        BACK_OFF.as_secs(),
        (dead.exchange.reply_timeout + SETTINGS.wire_time(dead.exchange.request_len)).as_secs_f64()
            * 1e3
    );

    // Writes to station 4 of bus 1 (a DV1) while everything is polled.
    std::thread::sleep(Duration::from_secs(3));
    let sim = &buses[0].sims[3];
    let register = model_of(models, 4)
        .model
        .written
        .expect("station 4 is written");
    let mut latencies = Vec::new();
    let mut hz = 10.0;
    for _ in 0..30 {
        hz += 0.5;
        let raw = (hz * 100.0f64).round() as u32;
        let asked = Instant::now();
        service.write("line1", "d4", register, &format!("{hz:.2} Hz"))?;
        while sim.lock().raw(register) != Some(raw) {
            if asked.elapsed() > Duration::from_secs(5) {
                return Err(format!(
                    "the write of {hz} Hz did not reach the drive within 5 s"
                ));
            }
            std::thread::sleep(Duration::from_micros(200));
        }
        latencies.push(asked.elapsed());
        std::thread::sleep(Duration::from_millis(150));
    }
    latencies.sort();
    println!(
        "A write request to the drive holding the value ({} writes of line1/d4 {register}): median {:.1} ms, 90th percentile {:.1} ms, max {:.1} ms (one DV1 poll on the wire: {:.1} ms).\n",
        latencies.len(),
        vfd_bench::percentile(&latencies, 50.0).as_secs_f64() * 1e3,
        vfd_bench::percentile(&latencies, 90.0).as_secs_f64() * 1e3,
        latencies.last().map_or(0.0, |l| l.as_secs_f64() * 1e3),
        model_of(models, 4).exchange.time.as_secs_f64() * 1e3
    );
    Ok(())
}
