//! A paced line between two pseudo-terminals: bytes written on one end come out of the other
//! at the character rate of a serial line, each held for its wire time, as a UART would
//! deliver them.
//!
//! Linux pseudo-terminals deliver a burst at once and refuse parity settings, so the pace
//! comes from the *described* line format ([`SerialSettings::char_time`]: start, data,
//! parity and stop bits at the baud rate), never from the terminals' own settings.
//!
//! ```text
//! master's end (pty A) -> relay -> pty B (drive's end)
//! master's end (pty A) <- relay <- pty B (drive's end)
//! ```
//!
//! Each direction has its own relay thread. A byte that arrives while the line is still
//! busy with earlier ones waits for them: byte `n` of a burst comes out `n + 1` character
//! times after the line was free (or after it arrived, if later).

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transport::{PseudoTerminal, PtyTransport, Transport};

/// How often an idle relay looks at its stop flag.
const IDLE_POLL: Duration = Duration::from_millis(20);

/// The relays' real-time priority, when granted (1-99; above the drive a bench may run at
/// [`DRIVE_PRIORITY`], as a UART runs below no program).
pub const RELAY_PRIORITY: i32 = 20;

/// A real-time priority for a virtual drive's serve loop next to a paced line (below the
/// relays).
pub const DRIVE_PRIORITY: i32 = 10;

/// When each byte of a line may come out: byte after byte, one character time each, never
/// before the byte arrived plus its character time. Pure arithmetic, so it is tested
/// without any clock.
#[derive(Debug, Clone, Copy)]
pub struct Pacer {
    char_time: Duration,
    /// When the last byte scheduled is completely on the line.
    free_at: Option<Instant>,
}

impl Pacer {
    /// A pacer for characters of `char_time` each.
    pub fn new(char_time: Duration) -> Pacer {
        Pacer {
            char_time,
            free_at: None,
        }
    }

    /// The instant the next byte, received at `arrived`, is completely on the line (its stop
    /// bit ends): one character time after the later of its arrival and the end of the byte
    /// before.
    pub fn schedule(&mut self, arrived: Instant) -> Instant {
        let start = match self.free_at {
            Some(free) if free > arrived => free,
            _ => arrived,
        };
        let due = start + self.char_time;
        self.free_at = Some(due);
        due
    }
}

/// What one direction of a [`PacedLine`] saw: how many bytes it passed and how late it
/// delivered them against their due time (sleep overshoot and scheduling of the relay
/// thread; the pseudo-terminal's own wake-up of the reader comes on top).
#[derive(Debug, Clone, Default)]
pub struct RelayStats {
    /// Bytes delivered.
    pub bytes: u64,
    /// Sum of the lateness of every byte.
    pub late_total: Duration,
    /// The latest byte.
    pub late_max: Duration,
    /// Lateness of every byte, for percentiles (bounded: the first million).
    pub late: Vec<Duration>,
    /// Bytes that came out more than half a character late: the gap before them was over
    /// 1.5 character times, which a drive with an inner-gap limit of 1.5 characters takes
    /// for the end of a frame.
    pub late_over_half_char: u64,
    /// Half a character time of the line.
    half_char: Duration,
}

impl RelayStats {
    fn record(&mut self, late: Duration) {
        if late > self.half_char {
            self.late_over_half_char += 1;
        }
        self.bytes += 1;
        self.late_total += late;
        self.late_max = self.late_max.max(late);
        if self.late.len() < 1_000_000 {
            self.late.push(late);
        }
    }

    /// Mean lateness per byte.
    pub fn late_mean(&self) -> Duration {
        if self.bytes == 0 {
            return Duration::ZERO;
        }
        self.late_total / u32::try_from(self.bytes).unwrap_or(u32::MAX)
    }

    /// Lateness percentile `p` (0-100).
    pub fn late_percentile(&self, p: f64) -> Duration {
        let mut sorted = self.late.clone();
        sorted.sort();
        crate::percentile(&sorted, p)
    }
}

/// How a relay hands on what it paces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delivery {
    /// Each byte when its character has crossed the line, as a UART delivers them.
    Bytes,
    /// What was written at once (a frame: a master writes a request in one write) in one
    /// write, when its last character has crossed the line. For a far end whose drives
    /// drop a frame with a gap of 1.5 characters inside (Modbus RTU): Linux hands a
    /// pseudo-terminal's bytes on from a kernel worker thread, which no real-time priority
    /// reaches, so on a busy machine a byte written on time may still arrive more than half
    /// a character late and break a frame no UART would have broken. The frame's end (when
    /// the drive acts) keeps its wire time.
    Bursts,
}

/// Two pseudo-terminal pairs joined by paced relays (see the module documentation). Stop it
/// with [`PacedLine::stop`], which returns what each direction saw.
#[derive(Debug)]
pub struct PacedLine {
    stop: Arc<AtomicBool>,
    to_drive: JoinHandle<io::Result<RelayStats>>,
    to_master: JoinHandle<io::Result<RelayStats>>,
}

impl PacedLine {
    /// Opens the line at the character rate of `settings`; returns the master's end, the
    /// drive's end and the line. `fine_timers`: the relay threads ask the kernel for 1 µs
    /// timer slack (Linux; the default slack is 50 µs) and for the real-time FIFO class
    /// ([`set_realtime`]), so a byte comes out within a few microseconds of its due time
    /// however busy the machine is (where the kernel grants them).
    pub fn open(
        settings: SerialSettings,
        fine_timers: bool,
    ) -> io::Result<(PtyTransport, PtyTransport, PacedLine)> {
        // The master talks on a terminal's slave side, as a program that opens a serial
        // device (or a pseudo-terminal's path) does; the relay holds the pty master.
        let (master_relay, master_end) = PseudoTerminal::open()?.into_transports()?;
        let (drive_relay, drive_end) = PseudoTerminal::open()?.into_transports()?;
        let line = PacedLine::relays(
            master_relay,
            drive_relay,
            settings,
            fine_timers,
            Delivery::Bytes,
        )?;
        Ok((master_end, drive_end, line))
    }

    /// As [`PacedLine::open`], but the master's end is a device path for another process
    /// to open (`vfd serve`'s bus port), kept alive by the returned transport, which must
    /// not be read; `to_drive` says how the master's frames reach the drive's end.
    pub fn open_for_path(
        settings: SerialSettings,
        fine_timers: bool,
        to_drive: Delivery,
    ) -> io::Result<(std::path::PathBuf, PtyTransport, PtyTransport, PacedLine)> {
        let master_pty = PseudoTerminal::open()?;
        let path = master_pty.slave_path().to_owned();
        let (master_relay, keep_open) = master_pty.into_transports()?;
        let (drive_relay, drive_end) = PseudoTerminal::open()?.into_transports()?;
        let line = PacedLine::relays(master_relay, drive_relay, settings, fine_timers, to_drive)?;
        Ok((path, keep_open, drive_end, line))
    }

    fn relays(
        master_relay: PtyTransport,
        drive_relay: PtyTransport,
        settings: SerialSettings,
        fine_timers: bool,
        to_drive_delivery: Delivery,
    ) -> io::Result<PacedLine> {
        let stop = Arc::new(AtomicBool::new(false));
        let char_time = settings.char_time();
        let to_drive = {
            let (from, to, stop) = (
                master_relay.try_clone()?,
                drive_relay.try_clone()?,
                Arc::clone(&stop),
            );
            thread::Builder::new()
                .name("paced-to-drive".into())
                .spawn(move || relay(from, to, char_time, fine_timers, to_drive_delivery, &stop))?
        };
        let to_master = {
            let stop = Arc::clone(&stop);
            thread::Builder::new()
                .name("paced-to-master".into())
                .spawn(move || {
                    relay(
                        drive_relay,
                        master_relay,
                        char_time,
                        fine_timers,
                        Delivery::Bytes,
                        &stop,
                    )
                })?
        };
        Ok(PacedLine {
            stop,
            to_drive,
            to_master,
        })
    }

    /// Stops both relays; returns what they saw, master to drive first.
    pub fn stop(self) -> io::Result<(RelayStats, RelayStats)> {
        self.stop.store(true, Ordering::Relaxed);
        let join = |handle: JoinHandle<io::Result<RelayStats>>| {
            handle
                .join()
                .unwrap_or_else(|_| Err(io::Error::other("a relay thread panicked")))
        };
        let to_drive = join(self.to_drive)?;
        let to_master = join(self.to_master)?;
        Ok((to_drive, to_master))
    }
}

/// Sets the calling thread's timer slack (Linux; elsewhere nothing happens). Returns
/// whether the kernel took it.
pub fn set_timer_slack(slack: Duration) -> bool {
    #[cfg(target_os = "linux")]
    {
        let nanos = libc::c_ulong::try_from(slack.as_nanos().max(1)).unwrap_or(libc::c_ulong::MAX);
        // SAFETY: PR_SET_TIMERSLACK takes one integer argument and touches no memory.
        unsafe { libc::prctl(libc::PR_SET_TIMERSLACK, nanos, 0, 0, 0) == 0 }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = slack;
        false
    }
}

/// Puts the calling thread in the real-time FIFO class at `priority` (Linux, with the
/// privilege for it; elsewhere nothing happens), so that it runs as soon as it wakes up
/// whatever else the machine is doing. Returns whether the kernel took it.
pub fn set_realtime(priority: i32) -> bool {
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param {
            sched_priority: priority,
        };
        // SAFETY: sched_setscheduler reads one sched_param, which `param` is; pid 0 is the
        // calling thread.
        unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) == 0 }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = priority;
        false
    }
}

/// CPU time the calling thread has used so far (user and system), where the system can tell.
pub fn thread_cpu_time() -> Option<Duration> {
    #[cfg(unix)]
    {
        let mut now = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec, which `now` is.
        let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
        (status == 0).then(|| {
            Duration::new(
                u64::try_from(now.tv_sec).unwrap_or(0),
                u32::try_from(now.tv_nsec).unwrap_or(0),
            )
        })
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// How many times the calling thread has gone to sleep waiting (voluntary context
/// switches: each wait that blocked, woken by input or a timer), where the system can tell.
pub fn thread_wakeups() -> Option<u64> {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: rusage is plain data; getrusage writes one, which `usage` is.
        let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
        // SAFETY: as above; RUSAGE_THREAD asks for the calling thread's figures.
        let status = unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut usage) };
        (status == 0).then(|| u64::try_from(usage.ru_nvcsw).unwrap_or(0))
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

/// Sleeps until `due` (returns at once if it has passed).
fn sleep_until(due: Instant) {
    let now = Instant::now();
    if due > now {
        thread::sleep(due - now);
    }
}

/// One direction of the line: reads bursts from `from` and writes them to `to` a byte at a
/// time, each when its character has crossed the line, or ([`Delivery::Bursts`]) a burst at
/// once when its last character has.
fn relay(
    mut from: PtyTransport,
    mut to: PtyTransport,
    char_time: Duration,
    fine_timers: bool,
    delivery: Delivery,
    stop: &AtomicBool,
) -> io::Result<RelayStats> {
    if fine_timers {
        set_timer_slack(Duration::from_micros(1));
        set_realtime(RELAY_PRIORITY);
    }
    let mut pacer = Pacer::new(char_time);
    let mut stats = RelayStats {
        half_char: char_time / 2,
        ..RelayStats::default()
    };
    let mut buf = [0u8; 512];
    while !stop.load(Ordering::Relaxed) {
        let got = match from.receive(&mut buf, Instant::now() + IDLE_POLL) {
            Ok(got) => got,
            // The end this direction reads from was closed: the line is being taken down.
            Err(error) if error.kind() == io::ErrorKind::BrokenPipe => break,
            Err(error) => return Err(error),
        };
        let arrived = Instant::now();
        if delivery == Delivery::Bursts {
            let mut due = arrived;
            for _ in 0..got {
                due = pacer.schedule(arrived);
            }
            sleep_until(due);
            to.send(&buf[..got])?;
            let late = Instant::now().saturating_duration_since(due);
            for _ in 0..got {
                stats.record(late);
            }
            continue;
        }
        for byte in &buf[..got] {
            let due = pacer.schedule(arrived);
            sleep_until(due);
            to.send(std::slice::from_ref(byte))?;
            stats.record(Instant::now().saturating_duration_since(due));
        }
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vfd_runtime::serial::Parity;

    #[test]
    fn bytes_of_a_burst_follow_each_other_one_character_apart() {
        let t0 = Instant::now();
        let char_time = Duration::from_micros(1146);
        let mut pacer = Pacer::new(char_time);
        let dues: Vec<Duration> = (0..4).map(|_| pacer.schedule(t0) - t0).collect();
        assert_eq!(
            dues,
            [1, 2, 3, 4].map(|n| char_time * n),
            "byte n comes out n character times after the burst"
        );
    }

    #[test]
    fn a_byte_after_a_silence_takes_one_character_from_its_arrival() {
        let t0 = Instant::now();
        let char_time = Duration::from_micros(100);
        let mut pacer = Pacer::new(char_time);
        pacer.schedule(t0);
        // The line was free again at t0 + 100 µs; this byte arrives later.
        let later = t0 + Duration::from_millis(5);
        assert_eq!(pacer.schedule(later), later + char_time);
        // One arriving while the line is busy waits for it.
        assert_eq!(
            pacer.schedule(later + Duration::from_micros(10)),
            later + char_time * 2
        );
    }

    #[test]
    fn the_pace_comes_from_the_described_format_not_the_terminal() {
        // 8E1 at 9600: 11 bits a character, which a Linux pseudo-terminal cannot be set to.
        let settings = SerialSettings {
            baud: 9600,
            data_bits: 8,
            parity: Parity::Even,
            stop_bits: 1,
        };
        let mut pacer = Pacer::new(settings.char_time());
        let t0 = Instant::now();
        for _ in 0..871 {
            pacer.schedule(t0);
        }
        // 872.7 characters a second: the 872nd ends within the second, the 873rd after it.
        assert!(pacer.schedule(t0) - t0 <= Duration::from_secs(1));
        assert!(pacer.schedule(t0) - t0 > Duration::from_secs(1));
    }

    #[test]
    fn every_byte_crosses_the_line_unchanged_and_in_order() {
        let settings = SerialSettings {
            baud: 115_200,
            data_bits: 8,
            parity: Parity::None,
            stop_bits: 1,
        };
        let (mut master, mut drive, line) = PacedLine::open(settings, false).unwrap();
        let bytes: Vec<u8> = (0u8..=255).collect();
        master.send(&bytes).unwrap();
        let deadline = Instant::now() + Duration::from_secs(30);
        let mut got = Vec::new();
        let mut buf = [0u8; 64];
        while got.len() < bytes.len() {
            let n = drive.receive(&mut buf, deadline).unwrap();
            assert!(n > 0, "only {} of 256 bytes arrived", got.len());
            got.extend_from_slice(&buf[..n]);
        }
        assert_eq!(got, bytes);
        drive.send(b"back").unwrap();
        let mut back = Vec::new();
        while back.len() < 4 {
            let n = master.receive(&mut buf, deadline).unwrap();
            assert!(n > 0, "the reply did not come back");
            back.extend_from_slice(&buf[..n]);
        }
        assert_eq!(back, b"back");
        let (to_drive, to_master) = line.stop().unwrap();
        assert_eq!((to_drive.bytes, to_master.bytes), (256, 4));
    }

    #[test]
    fn a_burst_delivered_whole_comes_out_at_once_when_its_last_byte_is_due() {
        let settings = SerialSettings {
            baud: 9600,
            data_bits: 8,
            parity: Parity::Even,
            stop_bits: 1,
        };
        let (path, _keep_open, mut drive, line) =
            PacedLine::open_for_path(settings, false, Delivery::Bursts).unwrap();
        let mut master = PtyTransport::open_path(&path).unwrap();
        let frame = [0x01, 0x03, 0xFD, 0x00, 0x00, 0x01, 0xB5, 0xA6];
        let sent = Instant::now();
        master.send(&frame).unwrap();
        let mut buf = [0u8; 64];
        let got = drive
            .receive(&mut buf, Instant::now() + Duration::from_secs(30))
            .unwrap();
        let arrived = Instant::now();
        assert_eq!(&buf[..got], &frame, "one piece, unchanged");
        assert!(
            arrived - sent >= settings.char_time() * 8,
            "not before its last character has crossed the line"
        );
        let (to_drive, _) = line.stop().unwrap();
        assert_eq!(to_drive.bytes, 8);
    }

    #[test]
    fn the_thread_cpu_clock_advances_with_work() {
        let Some(before) = thread_cpu_time() else {
            return;
        };
        let mut x = 0u64;
        for i in 0..5_000_000u64 {
            x = std::hint::black_box(x.wrapping_add(i * i));
        }
        std::hint::black_box(x);
        assert!(thread_cpu_time().unwrap() > before);
    }
}
