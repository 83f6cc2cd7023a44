//! The plant file as written: the serde model the positioned YAML reader reads it into,
//! and whose `///` comments are the JSON Schema's descriptions (`plants/plant.schema.json`).
//! Nothing here is checked beyond the keys and their types: `resolve` does that.

use schemars::JsonSchema;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer};
use std::borrow::Cow;
use std::fmt;

/// A plant file: the buses `vfd serve` polls, each with its drives.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlantFile {
    /// The buses: serial lines (RS-485 adapters) or serial device servers, each served by
    /// its own worker, so a slow bus never delays another.
    pub buses: Vec<BusFile>,
}

/// One serial line (or serial device server) and the drives on it.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BusFile {
    /// The bus's name in topics and records (`vfd/BUS/DRIVE/CODE`): lower-case letters,
    /// digits, `_` and `-`, at most 64 characters; unique in the plant.
    pub name: String,
    /// The serial device (`/dev/ttyUSB0`, `/dev/serial/by-id/...`, `COM3`) or a serial
    /// device server as `tcp://HOST:PORT` (raw frames over TCP). Not opened by `--check`.
    pub port: String,
    /// Baud rate; default: the first drive's factory setting. Every drive on the bus must
    /// be settable to it.
    pub baud: Option<u32>,
    /// Parity (`none`, `even`, `odd`); default: the first drive's factory setting for
    /// the protocol it speaks.
    pub parity: Option<ParityName>,
    /// Data bits per character (7 or 8); default: the first drive's factory setting for
    /// the protocol it speaks. Every drive must be able to use it.
    pub data_bits: Option<u8>,
    /// Stop bits (1 or 2); default: the first drive's factory setting for the protocol it
    /// speaks. Where a setting chooses a protocol's character format (DV1 07-07), data
    /// bits, parity and stop bits together must be one it offers.
    pub stop_bits: Option<u8>,
    /// The time a drive may take to start answering, in milliseconds, instead of each
    /// drive's manual (the wire time of both frames and the host latency are added).
    pub timeout_ms: Option<u64>,
    /// At least this many milliseconds of silence between frames, for a slow gateway or
    /// USB adapter (never shorter than the protocol's own gap).
    pub gap_ms: Option<u64>,
    /// Milliseconds added to every reply timeout for the adapter and the host; default 50.
    pub host_latency_ms: Option<u64>,
    /// Repeats of a read after a lost or garbled reply (0 to 5); default 0. A write is
    /// never repeated: it may have been carried out.
    pub retries: Option<u8>,
    /// Failed exchanges in a row that mark a drive offline (1 to 100); default 3.
    pub offline_after: Option<u32>,
    /// How an offline drive is tried again: after `first_ms`, the wait doubling after each
    /// failed try up to `cap_ms`; default `{ first_ms: 1000, cap_ms: 60000 }`.
    pub backoff: Option<BackoffFile>,
    /// The drives on the bus, each at its own station address.
    pub drives: Vec<DriveFile>,
}

/// Parity, as written in plant files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ParityName {
    /// No parity bit.
    None,
    /// Even parity.
    Even,
    /// Odd parity.
    Odd,
}

/// How an offline drive is tried again.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BackoffFile {
    /// The first wait, in milliseconds, after a drive is marked offline (at least 1).
    pub first_ms: u64,
    /// The longest wait between tries, in milliseconds (at least `first_ms`).
    pub cap_ms: u64,
}

/// One drive on a bus.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriveFile {
    /// The drive's name in topics and records: lower-case letters, digits, `_` and `-`, at
    /// most 64 characters; unique on its bus.
    pub name: String,
    /// The drive model: an id `vfd list` shows (`fc51`), or the path of a drive file,
    /// relative to the plant file's folder (`drives/my_drive.yaml`).
    pub drive: String,
    /// The protocol id (`vfd info DRIVE` lists them); default: the drive's first. All
    /// drives of a bus must share one framing.
    pub protocol: Option<String>,
    /// The protocol's variant the drive is set to, for protocols with several (a
    /// terminator, say); default: the protocol's first.
    pub variant: Option<String>,
    /// The drive's port the bus is on, for drives with several ports (`vfd info DRIVE`
    /// lists them).
    pub port_kind: Option<String>,
    /// The station address, within the protocol's range; unique on the bus. Required on a
    /// bus with several drives; alone on a bus, default: the protocol's (none where its
    /// frames may leave it out, else its lowest station).
    pub station: Option<u8>,
    /// What to read and how often: groups of registers, each with its interval.
    #[serde(default)]
    pub poll: Vec<PollFile>,
    /// The registers that may be written (through MQTT `set` topics): RAM only unless an
    /// entry says `persistent: true`. Left out, nothing may be written.
    #[serde(default)]
    pub write: Vec<WriteEntry>,
}

/// A group of registers read at one interval.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PollFile {
    /// The interval: a number and a unit, `ms`, `s`, `min` or `h` (`250ms`, `1s`, `2.5s`,
    /// `1min`); from 10 ms to 24 h.
    pub every: String,
    /// The registers, as `vfd read` takes them: a code (`FA01`, `3-03`), an address
    /// (`0xFA01`), an id (`output_frequency`) or a name.
    pub registers: Vec<String>,
}

/// A register that may be written: its name alone (RAM only), or `{ register, persistent }`.
#[derive(Debug, Clone)]
pub struct WriteEntry {
    /// The register, as `vfd write` takes it.
    pub register: String,
    /// Writes go to RAM and EEPROM.
    pub persistent: bool,
}

/// The keys of [`WriteEntryFile`], for the reader.
const WRITE_FIELDS: &[&str] = &["register", "persistent"];

/// A write entry written as a mapping.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WriteEntryFile {
    /// The register, as `vfd write` takes it: a code, an address, an id or a name.
    pub register: String,
    /// Writes go to RAM and EEPROM (EEPROM wears out: for settings changed rarely);
    /// default `false`, RAM only (lost at power-off).
    #[serde(default)]
    pub persistent: bool,
}

impl<'de> Deserialize<'de> for WriteEntry {
    /// Written by hand so that a mistake inside `{ ... }` is reported as itself, at its key,
    /// as for any mapping (see `vfd_codegen::yaml::OR_SCALAR`).
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct EntryVisitor;
        impl<'de> Visitor<'de> for EntryVisitor {
            type Value = WriteEntry;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a register, or `{ register: ..., persistent: true }`")
            }
            fn visit_str<E: de::Error>(self, name: &str) -> Result<WriteEntry, E> {
                Ok(WriteEntry {
                    register: name.to_owned(),
                    persistent: false,
                })
            }
            fn visit_u64<E: de::Error>(self, number: u64) -> Result<WriteEntry, E> {
                self.visit_str(&number.to_string())
            }
            fn visit_i64<E: de::Error>(self, number: i64) -> Result<WriteEntry, E> {
                self.visit_str(&number.to_string())
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<WriteEntry, A::Error> {
                WriteEntryFile::deserialize(de::value::MapAccessDeserializer::new(map)).map(
                    |entry| WriteEntry {
                        register: entry.register,
                        persistent: entry.persistent,
                    },
                )
            }
        }
        deserializer.deserialize_struct(WRITE_ENTRY_OR_SCALAR, WRITE_FIELDS, EntryVisitor)
    }
}

/// `WriteEntryFile` + [`vfd_codegen::yaml::OR_SCALAR`]: "this mapping, or a scalar".
const WRITE_ENTRY_OR_SCALAR: &str = "WriteEntryFile|or_scalar";

impl JsonSchema for WriteEntry {
    fn schema_name() -> Cow<'static, str> {
        "WriteEntry".into()
    }

    /// As the hand-written `Deserialize` reads it: a register, or a mapping.
    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "A register that may be written: its name alone (RAM only), or `{ register, persistent }`.",
            "oneOf": [
                { "type": "string", "description": "The register, as `vfd write` takes it; written to RAM only." },
                generator.subschema_for::<WriteEntryFile>(),
            ],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_or_scalar_name_is_the_readers() {
        assert_eq!(
            WRITE_ENTRY_OR_SCALAR,
            format!("WriteEntryFile{}", vfd_codegen::yaml::OR_SCALAR)
        );
        assert_eq!(
            WRITE_FIELDS,
            ["register", "persistent"],
            "the keys of WriteEntryFile"
        );
    }
}
