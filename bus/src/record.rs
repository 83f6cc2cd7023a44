//! The records of machine-readable output (`--format json|jsonl|csv`): one struct per kind
//! of row, each field named once here and documented in docs/output.md, so `read`, `watch`,
//! `backup`, `decode`, `info` and `list` all spell a register's code, name, value, unit and
//! raw word the same way.

use serde::Serialize;
use std::time::{SystemTime, UNIX_EPOCH};
use vfd_runtime::units::raw_to_scaled;
use vfd_runtime::{DataType, RegisterInfo};

/// One value of one register: a read (`read`, `watch`, `backup`) or a decoded frame's data
/// (`decode`).
#[derive(Debug, Clone, Serialize)]
pub struct ValueRecord {
    /// The drive's id (`vfd list`).
    pub drive: String,
    /// The register's code as the manual writes it (`FA01`, `3-03`).
    pub code: String,
    /// The register's English name.
    pub name: String,
    /// The manual's Chinese name (empty when it gives none).
    pub name_zh: String,
    /// The value in the register's unit (a code or a bit-field word as its number); `null`
    /// for text parameters and before a first good read.
    pub value: Option<f64>,
    /// The register's unit symbol (`Hz`, `s`, `%`); empty for plain numbers.
    pub unit: String,
    /// The raw word (or double word) on the line; `null` for text parameters.
    pub raw: Option<u32>,
    /// The value as `text` output shows it (`60.00 Hz`, `1 (Even parity / 偶校验)`,
    /// `C400h: run`, or a text parameter's text).
    pub text: Option<String>,
    /// When the value was read: RFC 3339, UTC, milliseconds (`null` for decoded frames).
    pub time: Option<String>,
    /// The same instant as milliseconds since 1970-01-01 UTC.
    pub epoch_ms: Option<u64>,
    /// The drive's trip flag as the reply states it (a lower-case command letter); `null`
    /// where the protocol's reply does not carry one (no second read is made for it).
    pub tripped: Option<bool>,
    /// This sample's read failed: `value`, `raw` and `text` are the last good ones.
    pub stale: bool,
    /// Why the read failed (`timeout`, `bad_reply`, `error_reply`, `mismatch`, `io`,
    /// `other`); `null` when it did not.
    pub error_kind: Option<String>,
    /// The error reply's code (`error_reply` only).
    pub error_code: Option<u16>,
    /// The manual's meaning of the error code, or the error message.
    pub error_meaning: Option<String>,
    /// Failed reads of this command so far (all registers).
    pub errors: u64,
    /// The sample number, from 1 (`read` and `backup`: 1).
    pub sample: u64,
}

impl ValueRecord {
    /// A record of `info` read as `raw` (or `text`), not yet timed.
    pub fn new(
        drive: &str,
        info: &RegisterInfo,
        raw: Option<u32>,
        text: Option<String>,
    ) -> ValueRecord {
        let value = match raw {
            Some(raw) if info.data_type != DataType::Text => Some(number(info, raw)),
            _ => None,
        };
        let text = match (&text, raw) {
            (Some(text), _) => Some(text.clone()),
            (None, Some(raw)) => Some(crate::values::short(info, raw)),
            (None, None) => None,
        };
        ValueRecord {
            drive: drive.to_owned(),
            code: info.code.to_owned(),
            name: info.name.to_owned(),
            name_zh: info.name_zh.to_owned(),
            value,
            unit: info.unit_symbol().to_owned(),
            raw,
            text,
            time: None,
            epoch_ms: None,
            tripped: None,
            stale: false,
            error_kind: None,
            error_code: None,
            error_meaning: None,
            errors: 0,
            sample: 1,
        }
    }

    /// Stamped with the time now.
    pub fn now(mut self) -> ValueRecord {
        let (time, ms) = now();
        self.time = Some(time);
        self.epoch_ms = Some(ms);
        self
    }

    /// Marked stale by `error`.
    pub fn failed(mut self, error: &crate::Error) -> ValueRecord {
        self.stale = true;
        self.error_kind = Some(error.kind().name().to_owned());
        self.error_code = error.code();
        self.error_meaning = Some(error.meaning().to_owned());
        self
    }
}

/// The value of `raw` in the register's units (rounded to its step's decimals).
fn number(info: &RegisterInfo, raw: u32) -> f64 {
    let value = raw_to_scaled(raw, info);
    let factor = 10f64.powi(i32::from(info.decimals()));
    (value * factor).round() / factor
}

/// One register of a drive's description (`info`).
#[derive(Debug, Clone, Serialize)]
pub struct RegisterRecord {
    /// The drive's id.
    pub drive: String,
    /// The register's code.
    pub code: String,
    /// The register's English name.
    pub name: String,
    /// The manual's Chinese name.
    pub name_zh: String,
    /// The register's address on the line.
    pub address: u32,
    /// The unit symbol; empty for plain numbers.
    pub unit: String,
    /// The lowest value, in units (`null` when unbounded or set by another register).
    pub min: Option<f64>,
    /// The highest value, in units.
    pub max: Option<f64>,
    /// The factory default, in units.
    pub default: Option<f64>,
    /// `read-only`, `read-write` or `write-only`.
    pub access: String,
    /// Written to RAM only (lost at power-off).
    pub ram_only: bool,
}

impl RegisterRecord {
    /// The record of `info`, a register of `drive`.
    pub fn new(drive: &str, info: &RegisterInfo) -> RegisterRecord {
        let step = |raw: i64| {
            let factor = 10f64.powi(i32::from(info.decimals()));
            (raw as f64 * info.scale * factor).round() / factor
        };
        RegisterRecord {
            drive: drive.to_owned(),
            code: info.code.to_owned(),
            name: info.name.to_owned(),
            name_zh: info.name_zh.to_owned(),
            address: u32::from(info.address),
            unit: info.unit_symbol().to_owned(),
            min: info.min_bound.is_none().then(|| step(info.raw_min)),
            max: info.max_bound.is_none().then(|| step(info.raw_max)),
            default: info.default_raw.map(|raw| number(info, raw)),
            access: info.access.as_str().to_owned(),
            ram_only: info.ram_only,
        }
    }
}

/// One described drive (`list`).
#[derive(Debug, Clone, Serialize)]
pub struct DriveRecord {
    /// The drive's id.
    pub drive: String,
    /// Vendor.
    pub vendor: String,
    /// Model.
    pub model: String,
    /// English name.
    pub name: String,
    /// The manual's Chinese name.
    pub name_zh: String,
    /// The protocols it speaks, by id, separated by spaces.
    pub protocols: String,
    /// The drive file it comes from; empty when built in.
    pub file: String,
}

impl DriveRecord {
    /// The record of `drive`, read from `file` when it is not built in.
    pub fn new(drive: &vfd_runtime::DriveInfo, file: Option<&std::path::Path>) -> DriveRecord {
        DriveRecord {
            drive: drive.id.to_owned(),
            vendor: drive.vendor.to_owned(),
            model: drive.model.to_owned(),
            name: drive.name.to_owned(),
            name_zh: drive.name_zh.to_owned(),
            protocols: drive
                .protocols
                .iter()
                .map(|p| p.id.as_ref())
                .collect::<Vec<&str>>()
                .join(" "),
            file: file.map(|f| f.display().to_string()).unwrap_or_default(),
        }
    }
}

/// The time now: RFC 3339 in UTC with milliseconds, and milliseconds since the epoch.
pub fn now() -> (String, u64) {
    let ms = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64);
    (rfc3339(ms), ms)
}

/// `ms` since 1970-01-01 UTC as `2026-11-26T22:40:23.123Z`.
pub fn rfc3339(ms: u64) -> String {
    let secs = ms / 1000;
    let days = (secs / 86_400) as i64;
    let of_day = secs % 86_400;
    // Civil date from days since the epoch (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}.{:03}Z",
        of_day / 3600,
        of_day / 60 % 60,
        of_day % 60,
        ms % 1000
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_rfc3339_utc_with_milliseconds() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00.000Z");
        assert_eq!(rfc3339(951_782_400_007), "2000-02-29T00:00:00.007Z");
        assert_eq!(rfc3339(1_795_732_823_123), "2026-11-26T22:40:23.123Z");
    }
}
