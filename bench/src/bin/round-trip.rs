//! Round-trip latency through pseudo-terminals against a pymodbus Modbus RTU server: our
//! master and Python clients (pymodbus, minimalmodbus) doing the same reads in one run.
//!
//! `pip install -r bench/python/requirements.txt`, then
//! `cargo run --release -p vfd-bench --bin round-trip [-- COUNT BAUD]`.
//!
//! Two pseudo-terminal pairs joined by a relay let every client open a path, as it would a
//! serial port, and reach the same server: client -> pts A -> relay -> pts B -> server.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use vfd_bench::percentile;
use vfd_runtime::serial::{DriveTiming, Parity, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{PseudoTerminal, PtyTransport, Transport};
use vfd_runtime::{CommandKind, DataType, Request};

const ADDRESS: u16 = 0x0BD5;

fn relay(mut from: PtyTransport, mut to: PtyTransport) {
    std::thread::spawn(move || {
        let mut buf = [0u8; 256];
        loop {
            match from.receive(&mut buf, Instant::now() + Duration::from_secs(3600)) {
                Ok(0) => continue,
                Ok(n) => {
                    if to.send(&buf[..n]).is_err() {
                        return;
                    }
                }
                Err(_) => return,
            }
        }
    });
}

struct Summary {
    client: String,
    latencies: Vec<Duration>,
}

impl Summary {
    fn print(&self, reference: Option<&Summary>) {
        let mut sorted = self.latencies.clone();
        sorted.sort();
        let total: Duration = sorted.iter().sum();
        let rate = sorted.len() as f64 / total.as_secs_f64();
        let ratio = reference.map(|r| {
            let mut theirs = r.latencies.clone();
            theirs.sort();
            format!(
                "{:.1}x",
                percentile(&sorted, 50.0).as_secs_f64() / percentile(&theirs, 50.0).as_secs_f64()
            )
        });
        println!(
            "| {:<24} | {:>8.0} | {:>8.3} | {:>8.3} | {:>8.3} | {:>8.3} | {:>14} |",
            self.client,
            rate,
            ms(percentile(&sorted, 50.0)),
            ms(percentile(&sorted, 90.0)),
            ms(percentile(&sorted, 99.0)),
            ms(*sorted.last().unwrap_or(&Duration::ZERO)),
            ratio.unwrap_or_else(|| "1.0x (baseline)".to_owned())
        );
    }
}

fn ms(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1000.0
}

fn python_client(library: &str, port: &str, baud: u32, count: usize) -> Result<Summary, String> {
    let output = Command::new("python3")
        .args([
            "bench/python/modbus_client.py",
            library,
            port,
            &baud.to_string(),
            &count.to_string(),
            &ADDRESS.to_string(),
        ])
        .output()
        .map_err(|e| format!("cannot run python3: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "{library} client failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let client = text
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
    let latencies = numbers
        .split(',')
        .filter_map(|n| n.trim().parse::<u64>().ok())
        .map(Duration::from_nanos)
        .collect();
    Ok(Summary { client, latencies })
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let count: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(2000);
    let baud: u32 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(115_200);
    if let Err(message) = run(count, baud) {
        eprintln!("round-trip: {message}");
        std::process::exit(1);
    }
}

fn run(count: usize, baud: u32) -> Result<(), String> {
    let check = Command::new("python3")
        .args(["-c", "import pymodbus, serial, minimalmodbus"])
        .output();
    if !check.map(|o| o.status.success()).unwrap_or(false) {
        return Err(
            "the Python peers are missing: pip install -r bench/python/requirements.txt".to_owned(),
        );
    }
    let io = |e: std::io::Error| e.to_string();
    let clients = PseudoTerminal::open().map_err(io)?;
    let server = PseudoTerminal::open().map_err(io)?;
    let client_path = clients.slave_path().display().to_string();
    let server_path = server.slave_path().display().to_string();
    let client_master = clients.master().map_err(io)?;
    let server_master = server.master().map_err(io)?;
    relay(
        client_master.try_clone().map_err(io)?,
        server_master.try_clone().map_err(io)?,
    );
    relay(server_master, client_master);

    let mut child = Command::new("python3")
        .args([
            "bench/python/modbus_server.py",
            &server_path,
            &baud.to_string(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot start the server: {e}"))?;
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("piped"))
        .read_line(&mut line)
        .map_err(io)?;

    // 8N1: Linux pseudo-terminals refuse parity settings (EINVAL), for pyserial as for us.
    let settings = SerialSettings {
        baud,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    };
    let timing = DriveTiming {
        startup_delay: Duration::ZERO,
        processing_allowance: Duration::from_millis(200),
        frame_abandon: Duration::from_secs(1),
    };
    let transport = PtyTransport::open_path(std::path::Path::new(&client_path)).map_err(io)?;
    let mut master = Master::new(
        transport,
        &vfd_drives::fc51::protocols::MODBUS,
        settings,
        timing,
    )
    .with_address(Some(1));
    let read = Request {
        wire_register: true,
        ..Request::raw(CommandKind::Read, ADDRESS, 0).with_data_type(DataType::DoubleWord)
    };
    let expected = (u32::from(ADDRESS) << 16) | u32::from(ADDRESS + 1);
    // The server opens its port after printing "ready": retry until it answers.
    let started = Instant::now();
    while master.transact(&read).is_err() {
        if started.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            return Err("the pymodbus server does not answer".to_owned());
        }
    }
    for _ in 0..20 {
        master.transact(&read).map_err(|e| e.to_string())?;
    }
    let mut latencies = Vec::with_capacity(count);
    for _ in 0..count {
        let start = Instant::now();
        let answer = master.transact(&read).map_err(|e| e.to_string())?;
        latencies.push(start.elapsed());
        if answer.data != Some(expected) {
            return Err(format!(
                "read {:08X?}, expected {expected:08X}h",
                answer.data
            ));
        }
    }
    drop(master);
    let ours = Summary {
        client: "vfd (Rust)".to_owned(),
        latencies,
    };
    let peers = ["pymodbus", "minimalmodbus"]
        .map(|library| python_client(library, &client_path, baud, count));
    let _ = child.kill();

    let wire = settings.wire_time(8 + 9);
    println!("Modbus RTU read of 2 holding registers (8-byte request, 9-byte reply), {count} reads per client,");
    println!("pymodbus server (bench/python/modbus_server.py) over two pseudo-terminals and a relay; {baud} baud 8N1 would take {:.3} ms on a real wire.", ms(wire));
    println!();
    println!(
        "| {:<24} | {:>8} | {:>8} | {:>8} | {:>8} | {:>8} | {:>14} |",
        "client", "reads/s", "p50 ms", "p90 ms", "p99 ms", "max ms", "p50 vs vfd"
    );
    println!(
        "|{}|{}|{}|{}|{}|{}|{}|",
        "-".repeat(26),
        "-".repeat(10),
        "-".repeat(10),
        "-".repeat(10),
        "-".repeat(10),
        "-".repeat(10),
        "-".repeat(16)
    );
    ours.print(None);
    for peer in peers {
        match peer {
            Ok(summary) => summary.print(Some(&ours)),
            Err(message) => println!("| {message} |"),
        }
    }
    Ok(())
}
