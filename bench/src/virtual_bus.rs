//! The plant benchmarks' far end: virtual drives on a paced line (bytes delivered at the
//! wire's character rate, [`crate::paced`]), served by the runtime's multi-drop bus server
//! in this process, with the service's end a pseudo-terminal path a plant file names; and
//! the shortest time one station's poll can take on that wire, from a recorded exchange.

use crate::paced::{set_realtime, Delivery, PacedLine, DRIVE_PRIORITY};
use std::path::PathBuf;
use std::process::{Child, Command};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{Direction, PtyTransport, Recording};
use vfd_runtime::virtual_drive::{serve_bus, BusStation, Simulator};
use vfd_runtime::{DriveInfo, Protocol};

/// The line every plant benchmark bus runs at: 9600 baud 8E1 (a format each polled model
/// takes over Modbus RTU; the DV1 allows no 8N1 there).
pub const SETTINGS: SerialSettings = SerialSettings {
    baud: 9600,
    parity: Parity::Even,
    data_bits: 8,
    stop_bits: 1,
};

/// One paced bus of virtual stations at addresses 1..=n.
pub struct VirtualBus {
    /// The service's end of the line (a pseudo-terminal's path).
    pub path: PathBuf,
    /// The stations' virtual drives, station 1 first.
    pub sims: Vec<Simulator>,
    _keep_open: PtyTransport,
    line: Option<PacedLine>,
    stop: Arc<AtomicBool>,
    server: Option<JoinHandle<std::io::Result<()>>>,
}

impl VirtualBus {
    /// A bus of `stations` (each a drive and the protocol it speaks), at addresses 1, 2, ...
    pub fn start(
        stations: &[(&'static DriveInfo, &'static Protocol)],
    ) -> Result<VirtualBus, String> {
        let (path, keep_open, mut drive_end, line) =
            PacedLine::open_for_path(SETTINGS, true, Delivery::Bursts)
                .map_err(|e| e.to_string())?;
        let bus: Vec<BusStation> = stations
            .iter()
            .zip(1u8..)
            .map(|(&(drive, protocol), address)| {
                let simulator = Simulator::new(drive);
                simulator.lock().set_address(address);
                BusStation {
                    simulator,
                    protocol,
                }
            })
            .collect();
        let sims = bus.iter().map(|s| s.simulator.clone()).collect();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let server = std::thread::spawn(move || {
            set_realtime(DRIVE_PRIORITY);
            serve_bus(&bus, &mut drive_end, SETTINGS, &flag)
        });
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

/// The shortest one station's poll can take on the wire.
#[derive(Debug, Clone, Copy)]
pub struct Exchange {
    /// Its frames as the description encodes them, a frame gap after each, the drive's
    /// reply delay.
    pub time: Duration,
    /// The request's length in bytes.
    pub request_len: usize,
    /// How long the master waits for the reply.
    pub reply_timeout: Duration,
}

/// The exchange reading `words` registers from `first` of `drive` over `protocol` (one
/// request), recorded against its virtual drive.
pub fn exchange(
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    first: u16,
    words: usize,
) -> Result<Exchange, String> {
    let sim = Simulator::new(drive);
    sim.lock().set_address(1);
    let mut master = Master::for_protocol(
        Recording::new(sim.link(protocol)),
        protocol,
        SETTINGS,
        drive.serial.timing,
    )
    .with_address(Some(1));
    let mut read = vec![0u16; words];
    master
        .read_words(first, &mut read)
        .map_err(|e| format!("{}: {e}", drive.id))?;
    let (mut sent, mut received, mut frames) = (0, 0, 0u32);
    for (direction, bytes) in master.transport().log() {
        frames += 1;
        match direction {
            Direction::Sent => sent += bytes.len(),
            Direction::Received => received += bytes.len(),
        }
    }
    let reply_delay = sim.lock().reply_delay(protocol) + master.reply_wait();
    Ok(Exchange {
        time: SETTINGS.wire_time(sent + received) + master.frame_gap() * frames + reply_delay,
        request_len: sent,
        reply_timeout: master.reply_timeout(sent),
    })
}

/// A child process killed (SIGTERM) and waited for when dropped.
pub struct Killed(pub Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = Command::new("kill").arg(self.0.id().to_string()).status();
        let _ = self.0.wait();
    }
}
