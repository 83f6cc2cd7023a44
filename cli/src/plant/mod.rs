//! Plant files (TEMPORARY loader for the serve branch; replaced by the plant helper's).

pub mod model;

use crate::{lookup, Failure};
use model::{Allowed, Bus, Plant, Poll, Station};
use serde::Deserialize;
use std::path::Path;
use std::time::Duration;

#[derive(Deserialize)]
struct FileBus {
    name: String,
    port: String,
    baud: Option<u32>,
    parity: Option<String>,
    timeout_ms: Option<u64>,
    retries: Option<u8>,
    offline_after: Option<u32>,
    backoff: Option<FileBackoff>,
    drives: Vec<FileDrive>,
}
#[derive(Deserialize)]
struct FileBackoff {
    first_ms: u64,
    cap_ms: u64,
}
#[derive(Deserialize)]
struct FileDrive {
    name: String,
    drive: String,
    protocol: Option<String>,
    station: Option<u8>,
    poll: Vec<FilePoll>,
    #[serde(default)]
    write: Vec<FileWrite>,
}
#[derive(Deserialize)]
struct FilePoll {
    every: String,
    registers: Vec<String>,
}
#[derive(Deserialize)]
#[serde(untagged)]
enum FileWrite {
    Name(String),
    Full { register: String, persistent: bool },
}
#[derive(Deserialize)]
struct FilePlant {
    buses: Vec<FileBus>,
}

fn every(text: &str) -> Result<Duration, Failure> {
    let t = text.trim();
    let (n, unit) = t.split_at(t.find(|c: char| c.is_alphabetic()).unwrap_or(t.len()));
    let n: f64 = n
        .trim()
        .parse()
        .map_err(|_| Failure::new(format!("bad interval {text}")))?;
    let secs = match unit {
        "ms" => n / 1000.0,
        "s" | "" => n,
        "min" => n * 60.0,
        _ => return Err(Failure::new(format!("bad interval {text}"))),
    };
    Ok(Duration::from_secs_f64(secs))
}

/// Loads a plant file.
pub fn load_for_cli(path: &Path) -> Result<Plant, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", path.display())))?;
    let file: FilePlant = yaml_serde::from_str(&text)
        .map_err(|e| Failure::new(format!("{}: {e}", path.display())))?;
    let mut buses = Vec::new();
    for b in file.buses {
        let mut stations = Vec::new();
        for d in &b.drives {
            let drive = lookup::drive(&d.drive)?;
            let protocol = lookup::protocol(drive, d.protocol.as_deref())?;
            let mut polls = Vec::new();
            for p in &d.poll {
                let e = every(&p.every)?;
                for r in &p.registers {
                    polls.push(Poll {
                        register: lookup::register_for(drive, r, false)?,
                        every: e,
                    });
                }
            }
            let mut writes = Vec::new();
            for w in &d.write {
                let (r, persistent) = match w {
                    FileWrite::Name(r) => (r, false),
                    FileWrite::Full {
                        register,
                        persistent,
                    } => (register, *persistent),
                };
                writes.push(Allowed {
                    register: lookup::register_for(drive, r, true)?,
                    persistent,
                });
            }
            stations.push(Station {
                name: d.name.clone(),
                drive,
                protocol,
                address: d.station.or_else(|| protocol.default_address()),
                port: None,
                polls,
                writes,
            });
        }
        let first = stations
            .first()
            .map(|s| s.drive)
            .ok_or_else(|| Failure::new("empty bus"))?;
        let mut settings = first.serial.default;
        if let Some(baud) = b.baud {
            settings.baud = baud;
        }
        if let Some(p) = &b.parity {
            settings.parity = match p.as_str() {
                "none" => vfd_runtime::serial::Parity::None,
                "odd" => vfd_runtime::serial::Parity::Odd,
                _ => vfd_runtime::serial::Parity::Even,
            };
        }
        let backoff = b.backoff.unwrap_or(FileBackoff {
            first_ms: 1000,
            cap_ms: 60000,
        });
        buses.push(Bus {
            name: b.name,
            port: b.port,
            settings,
            timeout: b.timeout_ms.map(Duration::from_millis),
            min_gap: None,
            host_latency: None,
            retries: b.retries.unwrap_or(0),
            offline_after: b.offline_after.unwrap_or(3),
            backoff_first: Duration::from_millis(backoff.first_ms),
            backoff_cap: Duration::from_millis(backoff.cap_ms),
            stations,
        });
    }
    Ok(Plant {
        path: path.to_owned(),
        buses,
    })
}
