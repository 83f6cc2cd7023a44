//! `vfd serve` as the plant benchmark runs it: the release binary as a child process with
//! `--jsonl` (and `--stdin-writes`), its events counted per bus and station as they come,
//! and its CPU time and memory read from `/proc` (Linux).

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What the service reported, as counts (memory stays bounded however long the run).
#[derive(Debug, Default)]
pub struct Tally {
    /// Readings per (bus, drive).
    pub readings: HashMap<(String, String), u64>,
    /// When each station was last reported offline or online, with the state.
    pub availability: Vec<(Instant, String, String, bool)>,
    /// When each write's outcome arrived, by request id, and whether it was carried out.
    pub written: HashMap<u64, (Instant, bool)>,
}

impl Tally {
    /// Readings of `bus` so far.
    pub fn bus_readings(&self, bus: &str) -> u64 {
        self.readings
            .iter()
            .filter(|((b, _), _)| b == bus)
            .map(|(_, n)| n)
            .sum()
    }
}

/// A service the plant benchmarks measure: the `vfd serve` binary ([`Service`]) or the
/// library's service core in this process ([`crate::embedded::InProcess`]).
pub trait Measured {
    /// What it reported so far.
    fn tally(&self) -> &Mutex<Tally>;
    /// Its CPU time so far (user + system).
    fn cpu_time(&self) -> Option<Duration>;
    /// Resident memory now and at its peak, in KiB.
    fn memory_kib(&self) -> Option<(u64, u64)>;
    /// Asks for a write of `value` to `register` of `drive` on `bus`.
    fn write(&mut self, bus: &str, drive: &str, register: &str, value: &str) -> Result<(), String>;
}

impl Measured for Service {
    fn tally(&self) -> &Mutex<Tally> {
        &self.tally
    }
    fn cpu_time(&self) -> Option<Duration> {
        Service::cpu_time(self)
    }
    fn memory_kib(&self) -> Option<(u64, u64)> {
        Service::memory_kib(self)
    }
    fn write(&mut self, bus: &str, drive: &str, register: &str, value: &str) -> Result<(), String> {
        Service::write(self, bus, drive, register, value)
    }
}

/// A running `vfd serve`.
pub struct Service {
    child: Child,
    stdin: Option<ChildStdin>,
    /// What it reported so far.
    pub tally: Arc<Mutex<Tally>>,
}

/// The `vfd` binary next to this benchmark's own (`cargo build --release -p vfd-cli`
/// puts it there).
pub fn vfd_binary() -> Result<PathBuf, String> {
    let me = std::env::current_exe().map_err(|e| e.to_string())?;
    let vfd = me.with_file_name(format!("vfd{}", std::env::consts::EXE_SUFFIX));
    if vfd.exists() {
        Ok(vfd)
    } else {
        Err(format!(
            "{} not found: build it first with `cargo build --release -p vfd-cli`",
            vfd.display()
        ))
    }
}

impl Service {
    /// Starts `vfd serve PLANT --jsonl --stdin-writes`.
    pub fn start(plant: &Path) -> Result<Service, String> {
        let mut child = Command::new(vfd_binary()?)
            .args(["serve", "--jsonl", "--stdin-writes"])
            .arg(plant)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("vfd serve: {e}"))?;
        let tally = Arc::new(Mutex::new(Tally::default()));
        let stdout = child.stdout.take().ok_or("no stdout")?;
        let sink = Arc::clone(&tally);
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                let now = Instant::now();
                let field = |name: &str| -> Option<&str> {
                    let key = format!("\"{name}\":");
                    let start = line.find(&key)? + key.len();
                    let rest = &line[start..];
                    let rest = rest.strip_prefix('"').unwrap_or(rest);
                    let end = rest.find(['"', ',', '}'])?;
                    Some(&rest[..end])
                };
                let mut tally = sink.lock().unwrap_or_else(|p| p.into_inner());
                let (bus, drive) = (
                    field("bus").unwrap_or("").to_owned(),
                    field("drive").unwrap_or("").to_owned(),
                );
                match field("event") {
                    Some("reading") => *tally.readings.entry((bus, drive)).or_default() += 1,
                    Some("availability") => {
                        let online = field("online") == Some("true");
                        tally.availability.push((now, bus, drive, online));
                    }
                    Some("written") => {
                        let id = field("id").and_then(|id| id.parse().ok()).unwrap_or(0);
                        let ok = field("ok") == Some("true");
                        tally.written.insert(id, (now, ok));
                    }
                    _ => {}
                }
            }
        });
        Ok(Service {
            stdin: child.stdin.take(),
            child,
            tally,
        })
    }

    /// Asks for a write (one JSON line on its standard input).
    pub fn write(
        &mut self,
        bus: &str,
        drive: &str,
        register: &str,
        value: &str,
    ) -> Result<(), String> {
        let stdin = self.stdin.as_mut().ok_or("stdin closed")?;
        writeln!(
            stdin,
            "{{\"bus\":\"{bus}\",\"drive\":\"{drive}\",\"register\":\"{register}\",\"value\":\"{value}\"}}"
        )
        .and_then(|()| stdin.flush())
        .map_err(|e| format!("vfd serve's stdin: {e}"))
    }

    /// Its CPU time so far (user + system).
    pub fn cpu_time(&self) -> Option<Duration> {
        process_cpu_time(self.child.id())
    }

    /// Its resident memory now, and the most it had, in KiB.
    pub fn memory_kib(&self) -> Option<(u64, u64)> {
        memory_kib(self.child.id())
    }

    /// SIGTERM, then waits for it.
    pub fn stop(mut self) {
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// CPU time (user + system) of process `pid` so far, from `/proc/PID/stat`.
pub fn process_cpu_time(pid: u32) -> Option<Duration> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command name (which may hold spaces) in parentheses.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the whole line: 12 and 13 after the name.
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    let per_second = clock_ticks();
    Some(Duration::from_secs_f64(ticks as f64 / per_second as f64))
}

/// Resident memory of process `pid` now, and the most it had, in KiB (`/proc/PID/status`).
pub fn memory_kib(pid: u32) -> Option<(u64, u64)> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let kib = |key: &str| {
        status
            .lines()
            .find(|l| l.starts_with(key))?
            .split_whitespace()
            .nth(1)?
            .parse::<u64>()
            .ok()
    };
    Some((kib("VmRSS:")?, kib("VmHWM:")?))
}

/// Clock ticks per second (`/proc`'s unit of CPU time).
pub fn clock_ticks() -> u64 {
    // SAFETY: sysconf has no preconditions.
    let ticks = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    u64::try_from(ticks).ok().filter(|t| *t > 0).unwrap_or(100)
}
