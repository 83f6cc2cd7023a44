//! A bus's line: its port string (checked for form only, never opened), its serial
//! settings (the bus's own, else its first drive's factory settings) and whether every
//! drive on it can be set to them, and its timing and back-off, each within sane bounds.

use super::file::{BusFile, ParityName};
use super::problems::Problems;
use super::station::Placed;
use std::time::Duration;
use vfd_runtime::serial::{Parity, SerialSettings};

/// The scheme of a serial device server's address.
const TCP_SCHEME: &str = "tcp://";

/// What the bus entry at `path` says about its line, checked.
pub struct Line {
    /// The serial settings.
    pub settings: SerialSettings,
    /// `timeout_ms`.
    pub timeout: Option<Duration>,
    /// `gap_ms`.
    pub min_gap: Option<Duration>,
    /// `host_latency_ms`.
    pub host_latency: Option<Duration>,
    /// `retries`, default 0.
    pub retries: u8,
    /// `offline_after`, default 3.
    pub offline_after: u32,
    /// `backoff.first_ms`, default 1 s.
    pub backoff_first: Duration,
    /// `backoff.cap_ms`, default 60 s.
    pub backoff_cap: Duration,
}

/// Checks the port string's form (`tcp://HOST:PORT`, or a device name).
pub fn port(bus: &BusFile, path: &str, problems: &mut Problems<'_>) {
    let at = format!("{path}.port");
    let port = bus.port.trim();
    if port.is_empty() {
        problems.error(
            &at,
            "the port is empty",
            "name the serial device (/dev/ttyUSB0, COM3; `vfd ports` lists them) or a serial device server as tcp://HOST:PORT",
        );
        return;
    }
    if let Some(address) = port.strip_prefix(TCP_SCHEME) {
        let valid = address.rsplit_once(':').is_some_and(|(host, number)| {
            !host.is_empty() && number.parse::<u16>().is_ok_and(|n| n > 0)
        });
        if !valid {
            problems.error(
                &at,
                format!("`{port}` is not a serial device server's address"),
                "write it as tcp://HOST:PORT, e.g. tcp://192.168.1.50:4001",
            );
        }
    } else if let Some((scheme, _)) = port.split_once("://") {
        problems.error(
            &at,
            format!("`{scheme}://` is not a kind of port vfd opens"),
            "a serial device (/dev/ttyUSB0, COM3) or a serial device server as tcp://HOST:PORT (raw frames over TCP)",
        );
    }
}

/// The bus's line settings and timing; `placed`: its drives resolved, each of which must
/// be settable to the line settings.
pub fn line(bus: &BusFile, path: &str, placed: &[Placed], problems: &mut Problems<'_>) -> Line {
    let factory = placed
        .first()
        .map(|p| p.head.drive.serial.default_for(&p.head.protocol.id));
    let mut settings = factory.unwrap_or(SerialSettings {
        baud: 9600,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    });
    if let Some(baud) = bus.baud {
        settings.baud = baud;
    }
    if let Some(parity) = bus.parity {
        settings.parity = match parity {
            ParityName::None => Parity::None,
            ParityName::Even => Parity::Even,
            ParityName::Odd => Parity::Odd,
        };
    }
    if let Some(bits) = bus.data_bits {
        settings.data_bits = bits;
    }
    if let Some(bits) = bus.stop_bits {
        settings.stop_bits = bits;
    }
    settings_fit(bus, path, &settings, placed, problems);
    let millis = |key: &str, value: Option<u64>, max: u64, problems: &mut Problems<'_>| {
        let value = value?;
        if value > max {
            problems.error(
                &format!("{path}.{key}"),
                format!("`{key}: {value}` is more than {max} ms"),
                format!(
                    "give at most {max}; a longer wait only delays every other drive on the bus"
                ),
            );
        }
        Some(Duration::from_millis(value))
    };
    let timeout = millis("timeout_ms", bus.timeout_ms, 10_000, problems);
    let min_gap = millis("gap_ms", bus.gap_ms, 1_000, problems);
    let host_latency = millis("host_latency_ms", bus.host_latency_ms, 5_000, problems);
    if timeout == Some(Duration::ZERO) {
        problems.error(
            &format!("{path}.timeout_ms"),
            "`timeout_ms: 0` leaves a drive no time to answer",
            "leave it out for each drive's manual, or give the drive's reply delay in milliseconds",
        );
    }
    let retries = bus.retries.unwrap_or(0);
    if retries > 5 {
        problems.error(
            &format!("{path}.retries"),
            format!("`retries: {retries}` is more than 5"),
            "a read that fails 6 times in a row will not succeed on the 7th; the drive goes offline and is tried again with back-off",
        );
    }
    let offline_after = bus.offline_after.unwrap_or(3);
    if !(1..=100).contains(&offline_after) {
        problems.error(
            &format!("{path}.offline_after"),
            format!("`offline_after: {offline_after}` is outside 1 to 100"),
            "the failed exchanges in a row that mark a drive offline; default 3",
        );
    }
    let (first, cap) = bus
        .backoff
        .as_ref()
        .map_or((1000, 60_000), |b| (b.first_ms, b.cap_ms));
    if first == 0 {
        problems.error(
            &format!("{path}.backoff.first_ms"),
            "`first_ms: 0` would try an offline drive without pause",
            "give the first wait in milliseconds, e.g. 1000",
        );
    } else if cap < first {
        problems.error(
            &format!("{path}.backoff.cap_ms"),
            format!("`cap_ms: {cap}` is less than `first_ms: {first}`"),
            "the cap is the longest wait between tries of an offline drive: at least the first",
        );
    } else if cap > 86_400_000 {
        problems.error(
            &format!("{path}.backoff.cap_ms"),
            format!("`cap_ms: {cap}` is more than a day"),
            "an offline drive would be tried again less than once a day; give at most 86400000",
        );
    }
    Line {
        settings,
        timeout,
        min_gap,
        host_latency,
        retries,
        offline_after,
        backoff_first: Duration::from_millis(first),
        backoff_cap: Duration::from_millis(cap),
    }
}

/// Refuses line settings a drive of the bus cannot be set to, at the bus's key where the
/// bus gives it, else at the drive (the settings were its first drive's).
fn settings_fit(
    bus: &BusFile,
    path: &str,
    settings: &SerialSettings,
    placed: &[Placed],
    problems: &mut Problems<'_>,
) {
    let first = placed.first().map(|p| p.head.drive.id).unwrap_or("");
    for Placed { path: at, head, .. } in placed {
        let serial = head.drive.serial;
        let stop_bits = serial.stop_bits_choices();
        let list = |items: Vec<String>| items.join(", ");
        let offered: Vec<_> = serial.formats_for(&head.protocol.id).collect();
        let checks: [(&str, bool, String, String); 5] = [
            (
                "baud",
                serial.baud_rates.contains(&settings.baud),
                format!("{} baud", settings.baud),
                list(serial.baud_rates.iter().map(u32::to_string).collect()),
            ),
            (
                "parity",
                serial.parities.contains(&settings.parity),
                format!("parity {}", settings.parity.as_str()),
                list(
                    serial
                        .parities
                        .iter()
                        .map(|p| p.as_str().to_owned())
                        .collect(),
                ),
            ),
            (
                "data_bits",
                serial.data_bits.contains(&settings.data_bits),
                format!("{} data bits", settings.data_bits),
                list(serial.data_bits.iter().map(u8::to_string).collect()),
            ),
            (
                "stop_bits",
                stop_bits.contains(&settings.stop_bits),
                format!("{} stop bits", settings.stop_bits),
                list(stop_bits.iter().map(u8::to_string).collect()),
            ),
            // A protocol whose format a setting chooses (DV1 07-07) takes only those.
            (
                "format",
                offered.is_empty() || offered.iter().any(|l| l.fits(settings)),
                format!("{} over {}", settings.format_label(), head.protocol.id),
                list(offered.iter().map(|l| l.label()).collect()),
            ),
        ];
        for (key, fits, setting, choices) in checks {
            if fits {
                continue;
            }
            let given = match key {
                "baud" => bus.baud.is_some(),
                "parity" => bus.parity.is_some(),
                "data_bits" => bus.data_bits.is_some(),
                "format" => {
                    bus.data_bits.is_some() || bus.parity.is_some() || bus.stop_bits.is_some()
                }
                _ => bus.stop_bits.is_some(),
            };
            let allows = if key == "format" {
                format!("only {choices} over {}", head.protocol.id)
            } else {
                format!("{key}: {choices}")
            };
            // The format is given by the bus's data_bits, parity and stop_bits together.
            let key = match key {
                "format" if bus.data_bits.is_some() => "data_bits",
                "format" if bus.parity.is_some() => "parity",
                "format" => "stop_bits",
                key => key,
            };
            let (place, whence) = if given {
                (format!("{path}.{key}"), "")
            } else {
                (
                    format!("{at}.drive"),
                    " (the factory setting of the bus's first drive, ",
                )
            };
            let whence = if given {
                whence.to_owned()
            } else {
                format!("{whence}{first})")
            };
            problems.error(
                &place,
                format!(
                    "drive {} cannot be set to {setting}{whence}, the line setting of bus `{}`",
                    head.drive.id, bus.name
                ),
                format!(
                    "its manual allows {allows}; give `{key}:` on the bus, one every drive on it can use, or put the drive on a bus of its own"
                ),
            );
        }
    }
}
