//! The asynchronous master against the blocking one, on the same virtual drive over the
//! same kind of line: a pseudo-terminal and a TCP connection on loopback (raw
//! serial-over-TCP, as to a serial device server). For every protocol of every described
//! drive it repeats a read of one register for a while with each master and prints, as a
//! Markdown table, the exchanges a second, the master thread's CPU time and wake-ups per
//! exchange, and the ratios async / blocking.
//!
//! `cargo run --release -p vfd-bench --bin async-master [-- SECONDS [BAUD]]` (default 1 s
//! per run at 115200 baud: the line settings give the frame gaps and timeouts; neither line
//! is paced, so the figures are the masters' own costs plus the drive's gaps).

use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};
use vfd_bench::paced::{thread_cpu_time, thread_wakeups};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transaction::{Async, Master};
use vfd_runtime::transport::{
    AsyncPtyTransport, AsyncTcpTransport, PseudoTerminal, TcpTransport, Transport,
};
use vfd_runtime::virtual_drive::{serve, Simulator};
use vfd_runtime::{CommandKind, DataType, DriveInfo, Protocol, Request, Space};

/// What one run measured.
#[derive(Debug, Clone, Copy, Default)]
struct Run {
    count: u32,
    errors: u32,
    elapsed: Duration,
    cpu: Option<Duration>,
    wakeups: Option<u64>,
}

impl Run {
    fn rate(&self) -> f64 {
        f64::from(self.count) / self.elapsed.as_secs_f64()
    }
    fn cpu_us(&self) -> Option<f64> {
        self.cpu
            .map(|cpu| cpu.as_secs_f64() * 1e6 / f64::from(self.count.max(1)))
    }
    fn wakeups(&self) -> Option<f64> {
        self.wakeups
            .map(|w| w as f64 / f64::from(self.count.max(1)))
    }
}

/// Counts the exchanges `exchange` completes in `duration` on this thread.
fn measure(duration: Duration, mut exchange: impl FnMut() -> bool) -> Run {
    // A few exchanges first: steps (a page switch) and echo detection settle.
    for _ in 0..3 {
        exchange();
    }
    let cpu = thread_cpu_time();
    let wakeups = thread_wakeups();
    let start = Instant::now();
    let mut run = Run::default();
    while start.elapsed() < duration {
        if exchange() {
            run.count += 1;
        } else {
            run.errors += 1;
        }
    }
    run.elapsed = start.elapsed();
    run.cpu = cpu.and_then(|before| Some(thread_cpu_time()? - before));
    run.wakeups = wakeups.and_then(|before| Some(thread_wakeups()? - before));
    run
}

/// A virtual drive served on a thread until the flag is set.
struct Served {
    stop: Arc<AtomicBool>,
    server: thread::JoinHandle<()>,
}

impl Served {
    fn start<T: Transport + Send + 'static>(
        sim: &Simulator,
        protocol: &'static Protocol,
        settings: SerialSettings,
        mut line: T,
    ) -> Served {
        let stop = Arc::new(AtomicBool::new(false));
        let server = {
            let (sim, stop) = (sim.clone(), Arc::clone(&stop));
            thread::spawn(move || {
                let _ = serve(&sim, protocol, &mut line, settings, &stop);
            })
        };
        Served { stop, server }
    }

    fn stop(self) {
        self.stop.store(true, Ordering::Relaxed);
        let _ = self.server.join();
    }
}

/// A TCP listener on loopback whose first client a virtual drive serves.
fn tcp_drive(
    sim: &Simulator,
    protocol: &'static Protocol,
    settings: SerialSettings,
) -> (String, thread::JoinHandle<Served>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let address = format!("tcp://{}", listener.local_addr().expect("address"));
    let sim = sim.clone();
    let accept = thread::spawn(move || {
        let (stream, _) = listener.accept().expect("accept");
        Served::start(
            &sim,
            protocol,
            settings,
            TcpTransport::from_stream(stream).expect("stream"),
        )
    });
    (address, accept)
}

/// The first plain word register `protocol` can read.
fn read_of(drive: &'static DriveInfo, protocol: &Protocol) -> Option<Request> {
    drive
        .registers
        .iter()
        .find(|info| {
            info.space == Space::Parameter
                && info.data_type == DataType::Word
                && protocol.can_read(info)
        })
        .map(|info| Request::for_register(CommandKind::Read, info, 0))
}

fn main() {
    let (seconds, bauds) = vfd_bench::first_and_bauds::<f64>(
        "async-master [SECONDS [BAUD]] (default 1 s per run at 115200)",
        1.0,
        &[115_200],
    );
    let duration = Duration::from_secs_f64(seconds);
    let baud = bauds[0];
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("tokio runtime");
    println!("| Drive | Protocol | Line | Blocking /s | Async /s | Async / blocking | Blocking CPU µs | Async CPU µs | Blocking wake-ups | Async wake-ups | Errors (blocking, async) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols.iter() {
            let Some(request) = read_of(drive, protocol) else {
                continue;
            };
            let settings = SerialSettings {
                baud,
                ..drive.serial.default
            };
            let timing = drive.serial.timing;
            let sim = Simulator::new(drive);
            let address = Some(sim.lock().address());
            // Pseudo-terminal: the master on the slave side, the drive on the pty master.
            let (drive_end, line) = PseudoTerminal::open()
                .and_then(PseudoTerminal::into_transports)
                .expect("pty");
            let served = Served::start(&sim, protocol, settings, drive_end);
            let mut blocking =
                Master::for_protocol(line, protocol, settings, timing).with_address(address);
            let pty_blocking = measure(duration, || blocking.transact(&request).is_ok());
            let line = blocking.into_transport();
            let pty_async = runtime.block_on(async {
                let line = AsyncPtyTransport::from_blocking(line).expect("async pty");
                let mut master = Master::for_protocol(Async(line), protocol, settings, timing)
                    .with_address(address);
                measure_async(duration, &mut master, &request).await
            });
            served.stop();
            row(
                drive.id,
                &protocol.id,
                "pseudo-terminal",
                pty_blocking,
                pty_async,
            );
            // TCP on loopback: a new connection (and serve loop) for each master.
            let (url, accept) = tcp_drive(&sim, protocol, settings);
            let line = TcpTransport::connect(&url).expect("connect");
            let served = accept.join().expect("accept thread");
            let mut blocking =
                Master::for_protocol(line, protocol, settings, timing).with_address(address);
            let tcp_blocking = measure(duration, || blocking.transact(&request).is_ok());
            drop(blocking);
            served.stop();
            let (url, accept) = tcp_drive(&sim, protocol, settings);
            let tcp_async = runtime.block_on(async {
                let line = AsyncTcpTransport::connect(&url).await.expect("connect");
                let mut master = Master::for_protocol(Async(line), protocol, settings, timing)
                    .with_address(address);
                measure_async(duration, &mut master, &request).await
            });
            accept.join().expect("accept thread").stop();
            row(
                drive.id,
                &protocol.id,
                "TCP (loopback)",
                tcp_blocking,
                tcp_async,
            );
        }
    }
}

/// [`measure`] for the asynchronous master, on the runtime's thread.
async fn measure_async<T: vfd_runtime::transport::AsyncTransport>(
    duration: Duration,
    master: &mut Master<Async<T>>,
    request: &Request,
) -> Run {
    for _ in 0..3 {
        let _ = master.transact(request).await;
    }
    let cpu = thread_cpu_time();
    let wakeups = thread_wakeups();
    let start = Instant::now();
    let mut run = Run::default();
    while start.elapsed() < duration {
        if master.transact(request).await.is_ok() {
            run.count += 1;
        } else {
            run.errors += 1;
        }
    }
    run.elapsed = start.elapsed();
    run.cpu = cpu.and_then(|before| Some(thread_cpu_time()? - before));
    run.wakeups = wakeups.and_then(|before| Some(thread_wakeups()? - before));
    run
}

fn row(drive: &str, protocol: &str, line: &str, blocking: Run, asynchronous: Run) {
    let num = |v: Option<f64>| v.map_or("n/a".to_owned(), |v| format!("{v:.1}"));
    println!(
        "| {drive} | {protocol} | {line} | {:.0} | {:.0} | {:.2} | {} | {} | {} | {} | {}, {} |",
        blocking.rate(),
        asynchronous.rate(),
        asynchronous.rate() / blocking.rate(),
        num(blocking.cpu_us()),
        num(asynchronous.cpu_us()),
        num(blocking.wakeups()),
        num(asynchronous.wakeups()),
        blocking.errors,
        asynchronous.errors,
    );
}
