//! `vfd block`: one block transfer (a protocol's `kind: block` command), with the words
//! written in each target register's units and the words read shown like `vfd read`. The
//! selection (which registers the words are) is read from the drive's selector registers,
//! or taken from the description's defaults, with `--set` overriding single selectors.

use crate::commands::watch::{print_value, show_trip};
use crate::line_args::LineArgs;
use crate::out::say;
use crate::Failure;
use std::collections::BTreeMap;
use vfd_bus::session::Value;
use vfd_bus::values;
use vfd_bus::{lookup, Catalogue};
use vfd_runtime::{DriveInfo, Protocol, Space};

/// What `vfd block` was told.
pub struct BlockArgs<'a> {
    /// The line.
    pub line: &'a LineArgs,
    /// Values to write, one per write position.
    pub writes: &'a [String],
    /// Words to ask back (default: every read position).
    pub reads: Option<u8>,
    /// Take the selectors at the description's defaults instead of reading them.
    pub defaults: bool,
    /// `CODE=VALUE` selector values that override the others.
    pub sets: &'a [String],
}

/// The protocol to use: the one given, else the drive's first with a block transfer.
fn block_protocol(drive: &DriveInfo, id: Option<&str>) -> Result<&'static Protocol, Failure> {
    let with_block: Vec<&str> = drive
        .protocols
        .iter()
        .filter(|p| p.block_command().is_some())
        .map(|p| p.id.as_ref())
        .collect();
    let protocol = match id {
        Some(id) => lookup::protocol(drive, Some(id))?,
        None => match with_block.first() {
            Some(id) => lookup::protocol(drive, Some(id))?,
            None => lookup::protocol(drive, None)?,
        },
    };
    if protocol.block_command().is_none() {
        let hint = if with_block.is_empty() {
            format!("drive {} describes no block transfer", drive.id)
        } else {
            format!("use --protocol {}", with_block.join(" or "))
        };
        return Err(Failure::new(format!(
            "protocol {} of drive {} has no block transfer",
            protocol.id, drive.id
        ))
        .hint(hint));
    }
    Ok(protocol)
}

/// `CODE=VALUE` pairs, by register number.
fn parse_sets(
    catalogue: &Catalogue,
    drive: &DriveInfo,
    sets: &[String],
) -> Result<BTreeMap<u16, u32>, Failure> {
    let mut values = BTreeMap::new();
    for set in sets {
        let (name, text) = set.split_once('=').ok_or_else(|| {
            Failure::new(format!("`{set}` is not CODE=VALUE")).hint("e.g. --set F870=1")
        })?;
        let info = catalogue.register(drive, name)?;
        let raw = values::parse(info, text).map_err(Failure::new)?;
        values.insert(info.address, raw);
    }
    Ok(values)
}

/// Runs one block transfer and prints what it wrote and read.
pub fn block(catalogue: &Catalogue, args: &BlockArgs<'_>) -> Result<(), Failure> {
    let drive = catalogue.drive(&args.line.drive)?;
    let protocol = block_protocol(drive, args.line.protocol.as_deref())?;
    let Some(spec) = protocol.block.as_ref() else {
        return Err(Failure::new("no block selection"));
    };
    let sets = parse_sets(catalogue, drive, args.sets)?;
    let mut line = args.line.clone();
    line.protocol = Some(protocol.id.to_string());
    let mut session = crate::open_session::open_session(&line, catalogue)?;
    let mut current = sets.clone();
    if !args.defaults {
        for register in spec.selector_registers() {
            if current.contains_key(&register) {
                continue;
            }
            if let Some(info) = drive.register_at(Space::Parameter, register) {
                if let Some(raw) = session.read(info)?.raw {
                    current.insert(register, raw);
                }
            }
        }
    }
    let selection = spec.selection(|register| current.get(&register).copied());
    let label = |register: Option<u16>| match register
        .and_then(|r| drive.register_at(Space::Parameter, r))
    {
        Some(info) => format!("{} {}", info.code, info.name),
        None => "no selection".to_owned(),
    };
    let mut words = Vec::new();
    for (position, text) in args.writes.iter().enumerate() {
        let target = selection.write.get(position).copied().flatten();
        let info = target.and_then(|r| drive.register_at(Space::Parameter, r));
        let raw = match info {
            Some(info) => values::parse(info, text).map_err(Failure::new)?,
            None => parse_word(text).map_err(|failure| {
                let selector = spec
                    .write
                    .get(position)
                    .and_then(|s| drive.register_at(Space::Parameter, s.register))
                    .map_or_else(|| "its selector".to_owned(), |s| s.code.to_string());
                failure.hint(format!(
                    "write word {} goes to no register ({selector} selects none here), so only a raw word (C400h, 0xC400, decimal) is taken; select a register with {selector} (it takes effect at the drive's reset) or give --set {selector}=N for a drive set so",
                    position + 1
                ))
            })?,
        };
        words.push(
            u16::try_from(raw)
                .map_err(|_| Failure::new(format!("`{text}` does not fit a 16-bit word")))?,
        );
    }
    let reads = args
        .reads
        .unwrap_or(u8::try_from(selection.read.len()).unwrap_or(u8::MAX));
    let outcome = session.block_transfer(&selection, &words, reads)?;
    say!(
        "block transfer on {}: selectors {}{}",
        protocol.id,
        if args.defaults {
            "at the description's defaults"
        } else {
            "as read from the drive (it uses the values of its last reset)"
        },
        if sets.is_empty() {
            ""
        } else {
            ", some given with --set"
        }
    );
    for (position, (target, word)) in outcome.writes.iter().zip(&words).enumerate() {
        let info = target.and_then(|r| drive.register_at(Space::Parameter, r));
        let shown = info.map_or(format!("{word:04X}h"), |info| {
            values::short(info, u32::from(*word))
        });
        let state = if outcome.write_failed(position) {
            "NOT written"
        } else {
            "written"
        };
        say!(
            "write {} -> {}: {shown} {state}",
            position + 1,
            label(*target)
        );
    }
    if (0..words.len()).any(|position| outcome.write_failed(position)) {
        say!(
            "  (a word is not written when its position selects nothing on the drive, which \
             takes its selection at a reset, or when its register refuses the value)"
        );
    }
    for (position, (target, word)) in outcome.reads.iter().enumerate() {
        match target.and_then(|r| drive.register_at(Space::Parameter, r)) {
            Some(info) => print_value(
                info,
                &Value {
                    raw: Some(u32::from(*word)),
                    text: None,
                    tripped: outcome.tripped,
                    decimals: None,
                },
            ),
            None => say!("read {}  (no selection) = {word:04X}h", position + 1),
        }
    }
    if outcome.tripped {
        show_trip(&mut session);
    }
    Ok(())
}

/// A raw word for a position that selects nothing: `C400h`, `0xC400` or decimal.
fn parse_word(text: &str) -> Result<u32, Failure> {
    let text = text.trim();
    let parsed = if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        u32::from_str_radix(hex, 16)
    } else if let Some(hex) = text.strip_suffix('h').or_else(|| text.strip_suffix('H')) {
        u32::from_str_radix(hex, 16)
    } else {
        text.parse()
    };
    parsed.map_err(|_| {
        Failure::new(format!("`{text}` is not a word"))
            .hint("give C400h, 0xC400 or a decimal number")
    })
}
