//! A bus carries one protocol family: every drive on it must frame its messages alike
//! (the same start and end bytes, checksum and encoding), or each would take the others'
//! frames for line noise. What is compared is the protocol's framing, not the drive: an
//! FC 51 and a DV1 share a bus on Modbus RTU.

use super::problems::Problems;
use super::station::Placed;
use std::fmt;
use vfd_runtime::layout::{ChecksumAlgorithm, Encoding, Part};
use vfd_runtime::Protocol;

/// How a protocol frames its requests.
#[derive(Debug, Clone, PartialEq)]
pub struct Framing {
    encoding: Encoding,
    /// The fixed bytes a frame starts with (empty: it starts with a field).
    start: Vec<u8>,
    /// The checksum's algorithm.
    checksum: Option<ChecksumAlgorithm>,
    /// The fixed bytes a frame ends with (empty: it ends with a field or checksum).
    end: Vec<u8>,
}

impl Framing {
    /// The framing of `protocol`'s requests (its first command's; a protocol frames all
    /// its commands alike). `None` for a protocol without commands.
    pub fn of(protocol: &Protocol) -> Option<Framing> {
        let layout = &protocol.commands.first()?.request;
        let literal = |part: Option<&Part>| match part {
            Some(Part::Literal {
                bytes,
                optional: false,
                ..
            }) => bytes.to_vec(),
            _ => Vec::new(),
        };
        let checksum = layout.parts.iter().find_map(|part| match part {
            Part::Checksum(spec) => Some(spec.algorithm),
            _ => None,
        });
        Some(Framing {
            encoding: layout.encoding,
            start: literal(layout.parts.first()),
            checksum,
            end: literal(layout.parts.last()),
        })
    }
}

impl fmt::Display for Framing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let hex = |bytes: &[u8]| {
            bytes
                .iter()
                .map(|b| format!("{b:02X}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        if self.start.is_empty() {
            f.write_str("no start byte")?;
        } else {
            write!(f, "start {}", hex(&self.start))?;
        }
        match self.checksum {
            Some(checksum) => write!(f, ", {}", checksum.as_str())?,
            None => f.write_str(", no checksum")?,
        }
        if !self.end.is_empty() {
            write!(f, ", end {}", hex(&self.end))?;
        }
        if self.encoding == Encoding::HexPairs {
            f.write_str(", bytes as hex digits")?;
        }
        Ok(())
    }
}

/// Refuses drives of one bus whose protocols frame differently from its first drive's.
/// `placed`: the bus's resolved drives.
pub fn check(bus: &str, placed: &[Placed], problems: &mut Problems<'_>) {
    let Some(first) = placed.first() else {
        return;
    };
    let Some(framing) = Framing::of(first.head.protocol) else {
        return;
    };
    let first_name = &first.name;
    let first = &first.head;
    for Placed {
        path,
        head,
        protocol_named: named,
        ..
    } in &placed[1..]
    {
        let Some(other) = Framing::of(head.protocol) else {
            continue;
        };
        if other == framing {
            continue;
        }
        let alike: Vec<&str> = head
            .drive
            .protocols
            .iter()
            .filter(|p| Framing::of(p).as_ref() == Some(&framing))
            .map(|p| p.id.as_ref())
            .collect();
        let hint = match alike.first() {
            Some(id) => format!(
                "{} also speaks `{id}`, framed as `{first_name}` is: set `protocol: {id}` (and the drive to it), or put the drive on a bus of its own",
                head.drive.id
            ),
            None => "put the drive on a bus of its own (a second adapter or device server port)".to_owned(),
        };
        let at = if *named {
            format!("{path}.protocol")
        } else {
            format!("{path}.drive")
        };
        problems.error(
            &at,
            format!(
                "on bus `{bus}`, {} `{}` frames differently ({other}) from `{first_name}`'s {} `{}` ({framing}): a bus carries one protocol family",
                head.drive.id, head.protocol.id, first.drive.id, first.protocol.id
            ),
            hint,
        );
    }
}
