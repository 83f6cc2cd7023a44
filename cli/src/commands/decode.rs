//! `vfd decode`: captured frames (hex or ASCII with escapes) explained field by field, with
//! the protocol (and the drive, when only one fits) found when not given.

use crate::emit::{Emitter, Format};
use crate::out::say;
use crate::paged::{page_switch, paged_text};
use crate::Failure;
use vfd_bus::record::ValueRecord;
use vfd_bus::values;
use vfd_bus::{lookup, Catalogue};
use vfd_runtime::codec::FrameValues;
use vfd_runtime::error::DecodeError;
use vfd_runtime::layout::{FrameLayout, Part, Role};
use vfd_runtime::meaning::{decode_meaning, Direction, FrameMeaning};
use vfd_runtime::protocol::{code_label, Reply};
use vfd_runtime::{CommandKind, DriveInfo, Protocol, Space};

/// Bytes as text with `\r`, `\n` and `\xHH` escapes.
pub fn escaped(bytes: &[u8]) -> String {
    let mut text = String::new();
    for &b in bytes {
        match b {
            b'\r' => text.push_str("\\r"),
            b'\n' => text.push_str("\\n"),
            b'\\' => text.push_str("\\\\"),
            b if b.is_ascii_graphic() || b == b' ' => text.push(b as char),
            b => text.push_str(&format!("\\x{b:02X}")),
        }
    }
    text
}

/// A frame as typed: hex pairs (`2F 52 FD 00 7E`, `2F52FD007E`) or text with escapes
/// (`(RFD00)\r`, `\x05`). Non-hex characters in what looks like hex are an error.
pub fn parse_frame(text: &str) -> Result<Vec<u8>, Failure> {
    let trimmed = text.trim();
    if trimmed.is_empty() {
        return Err(Failure::new("the frame is empty"));
    }
    if looks_hex(trimmed) {
        let mut digits = String::new();
        for token in trimmed.split(|c: char| c.is_whitespace() || c == ',' || c == ':') {
            let token = token
                .strip_prefix("0x")
                .or_else(|| token.strip_prefix("0X"))
                .unwrap_or(token);
            if let Some(bad) = token.chars().find(|c| !c.is_ascii_hexdigit()) {
                return Err(Failure::new(format!(
                    "`{bad}` is not a hex digit in the hex frame `{trimmed}`"
                ))
                .hint("write hex as pairs (2F 52 FD 00 7E) or text with escapes ('(RFD00)\\r')"));
            }
            if token.len() % 2 == 1 && token.len() > 1 {
                return Err(Failure::new(format!(
                    "`{token}` has an odd number of hex digits in the hex frame `{trimmed}`"
                ))
                .hint("write each byte as two hex digits"));
            }
            if token.len() == 1 {
                digits.push('0');
            }
            digits.push_str(token);
        }
        return Ok((0..digits.len())
            .step_by(2)
            .filter_map(|i| u8::from_str_radix(&digits[i..i + 2], 16).ok())
            .collect());
    }
    unescape(text)
}

/// Whether the text is meant as hex: byte pairs separated by spaces, or one run of mostly
/// hex digits without the punctuation text frames start with.
fn looks_hex(text: &str) -> bool {
    if text.contains('\\') || text.starts_with(['(', ':', '/', '@']) {
        return false;
    }
    let tokens: Vec<&str> = text.split_whitespace().collect();
    if tokens.len() >= 2 {
        return tokens
            .iter()
            .all(|t| t.len() <= 2 || t.starts_with("0x") || t.starts_with("0X"));
    }
    let hexish = text.chars().filter(char::is_ascii_hexdigit).count();
    text.chars().all(|c| c.is_ascii_alphanumeric()) && hexish * 10 >= text.chars().count() * 8
}

fn unescape(text: &str) -> Result<Vec<u8>, Failure> {
    let mut bytes = Vec::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '\\' {
            let mut buf = [0u8; 4];
            bytes.extend_from_slice(c.encode_utf8(&mut buf).as_bytes());
            continue;
        }
        match chars.next() {
            Some('r') => bytes.push(b'\r'),
            Some('n') => bytes.push(b'\n'),
            Some('t') => bytes.push(b'\t'),
            Some('0') => bytes.push(0),
            Some('\\') => bytes.push(b'\\'),
            Some('x') => {
                let hex: String = chars.by_ref().take(2).collect();
                let byte = u8::from_str_radix(&hex, 16).map_err(|_| {
                    Failure::new(format!("`\\x{hex}` is not a byte escape"))
                        .hint("write bytes as \\xHH with two hex digits, e.g. \\x05")
                })?;
                bytes.push(byte);
            }
            Some(other) => {
                return Err(
                    Failure::new(format!("unknown escape `\\{other}` in the frame"))
                        .hint("escapes: \\r \\n \\t \\0 \\\\ \\xHH"),
                )
            }
            None => return Err(Failure::new("the frame ends with a lone `\\`")),
        }
    }
    Ok(bytes)
}

/// Options of `vfd decode`.
#[derive(Debug, Clone)]
pub struct DecodeArgs {
    /// Drive id, if given.
    pub drive: Option<String>,
    /// Protocol id, if given.
    pub protocol: Option<String>,
    /// Only this direction, if given.
    pub direction: Option<Direction>,
    /// How to print (`--json` is [`Format::Json`]).
    pub format: Format,
    /// The frame as typed.
    pub frame: String,
}

/// One way the frame decodes.
struct Fit {
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    direction: Direction,
    meaning: FrameMeaning,
}

/// Decodes a captured frame and explains it; an invalid frame is an error with the reason.
pub fn decode(catalogue: &Catalogue, args: &DecodeArgs) -> Result<(), Failure> {
    let mut bytes = parse_frame(&args.frame)?;
    let drives: Vec<&'static DriveInfo> = match &args.drive {
        Some(id) => vec![catalogue.drive(id)?],
        None => catalogue.all_drives(),
    };
    if let (Some(id), [drive]) = (&args.protocol, drives.as_slice()) {
        lookup::protocol(drive, Some(id))?;
    }
    let directions: Vec<Direction> = match args.direction {
        Some(direction) => vec![direction],
        None => vec![Direction::Request, Direction::Reply],
    };
    let mut notes = Vec::new();
    let (mut fits, mut errors) = fits(&drives, args, &directions, &bytes);
    if fits.is_empty() && bytes.last() != Some(&b'\r') && bytes.iter().all(u8::is_ascii) {
        // Text frames typed without their final CR.
        let mut with_cr = bytes.clone();
        with_cr.push(b'\r');
        let (found, _) = fits_of(&drives, args, &directions, &with_cr);
        if !found.is_empty() {
            notes.push("the frame lacks its final CR (\\r); decoded with it added".to_owned());
            bytes = with_cr;
            fits = found;
            errors.clear();
        }
    }
    if fits.is_empty() {
        let failure = no_fit(args, &bytes, &errors);
        if !args.format.is_text() && args.format != Format::Csv {
            let json = serde_json::json!({
                "valid": false,
                "frame": vfd_runtime::error::hex(&bytes),
                "error": failure.message,
            });
            let text = if args.format == Format::Jsonl {
                serde_json::to_string(&json)
            } else {
                serde_json::to_string_pretty(&json)
            };
            say!("{}", text.unwrap_or_default());
        }
        return Err(failure);
    }
    let first = &fits[0];
    let same_protocol: Vec<&Fit> = fits
        .iter()
        .filter(|f| f.protocol.name == first.protocol.name && f.direction == first.direction)
        .collect();
    let drives_fitting: Vec<&str> = dedup(same_protocol.iter().map(|f| f.drive.id));
    if args.drive.is_none() && drives_fitting.len() > 1 {
        notes.push(format!(
            "drives {} all speak this protocol; names are {}'s (give --drive to choose)",
            drives_fitting.join(", "),
            first.drive.id
        ));
    }
    let other_protocols: Vec<String> = dedup(
        fits.iter()
            .filter(|f| f.protocol.name != first.protocol.name || f.direction != first.direction)
            .map(|f| f.protocol.id.as_ref()),
    )
    .into_iter()
    .map(str::to_owned)
    .collect();
    if fits
        .iter()
        .any(|f| f.protocol.name == first.protocol.name && f.direction != first.direction)
    {
        notes.push(format!(
            "it is also a valid {}; give --{} to read it so",
            other(first.direction).as_str(),
            other(first.direction).as_str()
        ));
    } else if !other_protocols.is_empty() {
        notes.push(format!(
            "it is also valid in: {} (give --protocol)",
            other_protocols.join(", ")
        ));
    }
    if first.meaning.broadcast.is_some() {
        let reads = first.meaning.kind.is_some_and(|kind| !kind.is_write());
        match &first.protocol.broadcast {
            _ if reads => notes.push(
                "a broadcast read: only writes may be broadcast, so drives ignore it and the library never sends one".to_owned(),
            ),
            None => notes.push(format!(
                "{} takes no broadcasts over this protocol",
                first.drive.id
            )),
            Some(rule) if !first.meaning.code.is_some_and(|code| rule.commands.contains(&code)) => {
                notes.push(format!(
                    "{} does not carry out this command when broadcast",
                    first.drive.id
                ))
            }
            Some(_) => {}
        }
    }
    let report = Report::new(first, &bytes, notes);
    match args.format {
        Format::Text => report.print(),
        Format::Json => {
            let text = serde_json::to_string_pretty(&report.json())
                .map_err(|e| Failure::new(format!("cannot write JSON: {e}")))?;
            say!("{text}");
        }
        Format::Jsonl | Format::Csv => {
            let mut emitter = Emitter::new(args.format);
            if let Some(record) = report.record() {
                emitter.record(&record);
            }
            emitter.finish();
        }
    }
    Ok(())
}

fn other(direction: Direction) -> Direction {
    match direction {
        Direction::Request => Direction::Reply,
        Direction::Reply => Direction::Request,
    }
}

fn dedup<'a>(items: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    for item in items {
        if !out.contains(&item) {
            out.push(item);
        }
    }
    out
}

type Errors = Vec<(String, Direction, DecodeError)>;

fn fits(
    drives: &[&'static DriveInfo],
    args: &DecodeArgs,
    directions: &[Direction],
    bytes: &[u8],
) -> (Vec<Fit>, Errors) {
    fits_of(drives, args, directions, bytes)
}

fn fits_of(
    drives: &[&'static DriveInfo],
    args: &DecodeArgs,
    directions: &[Direction],
    bytes: &[u8],
) -> (Vec<Fit>, Errors) {
    let mut found = Vec::new();
    let mut errors = Vec::new();
    for &direction in directions {
        for &drive in drives {
            // Every variant (the Eaton terminator CR or CR LF): a frame fits the one it is in.
            let protocols = drive.protocols.iter().flat_map(|p| p.all_variants());
            for protocol in protocols {
                if args
                    .protocol
                    .as_deref()
                    .is_some_and(|id| !protocol.id.eq_ignore_ascii_case(id))
                {
                    continue;
                }
                match decode_meaning(protocol, direction, bytes) {
                    Ok(meaning) => found.push(Fit {
                        drive,
                        protocol,
                        direction,
                        meaning,
                    }),
                    Err(error) => {
                        errors.push((format!("{}/{}", drive.id, protocol.id), direction, error))
                    }
                }
            }
        }
    }
    (found, errors)
}

/// The innermost error (past "no layout matches").
fn innermost(error: &DecodeError) -> &DecodeError {
    match error {
        DecodeError::NoLayoutMatches { closest, .. } => innermost(closest),
        other => other,
    }
}

/// Why no protocol takes the frame: a checksum mismatch when one explains it, else the
/// closest attempt of each protocol tried.
fn no_fit(args: &DecodeArgs, bytes: &[u8], errors: &Errors) -> Failure {
    let hex = vfd_runtime::error::hex(bytes);
    if let Some((
        name,
        direction,
        DecodeError::ChecksumMismatch {
            computed,
            received,
            algorithm,
            ..
        },
    )) = errors
        .iter()
        .find_map(|(name, direction, error)| match innermost(error) {
            e @ DecodeError::ChecksumMismatch { .. } => Some((name, direction, e)),
            _ => None,
        })
    {
        return Failure::new(format!(
            "checksum mismatch: computed {computed:02X}h, frame has {received:02X}h ({} {} {}, {})",
            name,
            direction.as_str(),
            hex,
            algorithm.as_str()
        ))
        .hint("a byte was changed on the way, or the frame was copied wrongly");
    }
    let mut reasons: Vec<String> = errors
        .iter()
        .map(|(name, direction, error)| format!("{name} {}: {error}", direction.as_str()))
        .collect();
    // A protocol's variants (Eaton's CR and CR LF endings) often fail alike: each reason once.
    let mut seen = std::collections::HashSet::new();
    reasons.retain(|reason| seen.insert(reason.clone()));
    reasons.truncate(6);
    let scope = match (&args.drive, &args.protocol) {
        (Some(d), Some(p)) => format!("{d} {p}"),
        (Some(d), None) => format!("any protocol of {d}"),
        (None, Some(p)) => format!("protocol {p} of any drive"),
        (None, None) => "any described protocol".to_owned(),
    };
    Failure::new(format!("{hex} is not a valid frame of {scope}")).hint(reasons.join("\n  "))
}

/// What is printed about a decoded frame.
struct Report<'a> {
    fit: &'a Fit,
    bytes: &'a [u8],
    notes: Vec<String>,
    fields: Vec<(String, String)>,
    parts: Vec<(String, String)>,
}

impl<'a> Report<'a> {
    fn new(fit: &'a Fit, bytes: &'a [u8], notes: Vec<String>) -> Report<'a> {
        let mut report = Report {
            fit,
            bytes,
            notes,
            fields: Vec::new(),
            parts: Vec::new(),
        };
        report.explain();
        report
    }

    fn add(&mut self, name: &str, value: String) {
        self.fields.push((name.to_owned(), value));
    }

    fn explain(&mut self) {
        let (drive, protocol, meaning) = (self.fit.drive, self.fit.protocol, &self.fit.meaning);
        if let Some(code) = meaning.code {
            let kind = meaning.kind.map_or("error reply", CommandKind::as_str);
            self.add("command", format!("{} ({kind})", code_label(code)));
        } else if let Some(kind) = meaning.kind {
            self.add("command", kind.as_str().to_owned());
        }
        if let Some(address) = meaning.address {
            self.add("station", address.to_string());
        }
        if let Some(broadcast) = meaning.broadcast {
            let stations = match broadcast {
                vfd_runtime::Broadcast::All => "every station".to_owned(),
                vfd_runtime::Broadcast::Group(group) => format!("every station matching {group}"),
            };
            self.add("broadcast", stations);
        }
        if meaning.tripped {
            let who = match self.fit.direction {
                Direction::Request => "yes: the sender (master) reports a trip",
                Direction::Reply => "yes: the drive reports a trip",
            };
            self.add("tripped", who.to_owned());
        }
        // The command the frame belongs to, for what sets it apart (a percentage, no reply).
        let command = protocol.commands.iter().find(|c| {
            Some(c.kind) == meaning.kind && meaning.code.is_some_and(|code| c.answers_to(code))
        });
        if let Some(error) = meaning.error_code {
            let text = match protocol.error_code(error) {
                Some(info) => format!(
                    "{} ({}/{}): {}",
                    info.shown(),
                    info.name,
                    info.name_zh,
                    info.meaning
                ),
                None => format!("{error} ({error:02X}h, not in the manual's table)"),
            };
            self.add("error", text);
        }
        let space = meaning.space.unwrap_or(Space::Parameter);
        let writing = meaning.kind.is_some_and(|k| k.is_write());
        let info = meaning
            .register
            .and_then(|r| drive.register_for(space, r, writing));
        match (info, meaning.register, meaning.wire_register) {
            (Some(info), _, _) => self.add("register", info.label()),
            (None, Some(register), _) => self.add(
                "register",
                format!("{} {register} (not described)", space.as_str()),
            ),
            (None, None, Some(wire)) => {
                // Layouts without a command field: the command of the frame's kind.
                let command = command.or_else(|| {
                    let mut of_kind = protocol
                        .commands
                        .iter()
                        .filter(|c| Some(c.kind) == meaning.kind);
                    of_kind.next().filter(|_| of_kind.next().is_none())
                });
                match page_switch(protocol, command, wire) {
                    // A step of the protocol, not a register of the drive (`pages:`).
                    Some(true) => self.add(
                        "step",
                        format!("page switch (wire number {wire:04X}h): selects the page of the paged requests that follow"),
                    ),
                    Some(false) => self.add(
                        "step",
                        format!("page read (wire number {wire:04X}h): asks which page is selected"),
                    ),
                    None => self.add("register", paged_text(drive, protocol, command, wire)),
                }
            }
            _ => {}
        }
        // The page switch carries a page, not a register's value.
        let paging = meaning.register.is_none()
            && meaning.wire_register.is_some_and(|wire| {
                protocol
                    .commands
                    .iter()
                    .filter(|c| Some(c.kind) == meaning.kind)
                    .any(|c| page_switch(protocol, Some(c), wire).is_some())
            });
        if let Some(index) = meaning.index {
            self.add("index", index.to_string());
        }
        if let Some(text) = &meaning.text {
            self.add("text", format!("{text:?}"));
        }
        let request = self.fit.direction == Direction::Request;
        if let Some(data) = meaning.data {
            match (info, command.and_then(|c| c.percent_of.as_ref())) {
                _ if request && meaning.kind.is_some_and(|k| k.only_reads()) => {
                    self.add(
                        "data",
                        format!("{data:04X}h (dummy: a read carries no value)"),
                    );
                }
                (_, Some(percent_of)) => self.add(
                    "value",
                    format!(
                        "{:.2} % of {} ({data:04X}h)",
                        percent_of.from_raw(data, 100.0),
                        percent_of.register
                    ),
                ),
                (Some(info), None) => {
                    self.add("value", values::short(info, data));
                    if let Some(bits) = info.bits {
                        for line in values::field_lines(bits, data as u16) {
                            self.add("  field", line);
                        }
                    }
                }
                (None, None) if paging => self.add("page", data.to_string()),
                (None, None) => self.add("value", format!("{data} ({data:04X}h)")),
            }
        }
        let register_unanswered = meaning.kind.is_some_and(CommandKind::is_write)
            && info.is_some_and(|info| info.no_reply);
        if request && (command.is_some_and(|c| c.no_reply) || register_unanswered) {
            self.add(
                "reply",
                "none: the drive never answers this request".to_owned(),
            );
        }
        if let Some([first, second]) = meaning.process {
            let (a, b) = match self.fit.direction {
                Direction::Request => ("control word", "reference"),
                Direction::Reply => ("status word", "output value"),
            };
            self.add(a, format!("{first:04X}h"));
            self.add(b, format!("{second:04X}h"));
        }
        self.parts = parts(protocol, self.fit.direction, self.bytes);
    }

    /// `checksum ok`, or `no checksum` for frames sent without one.
    fn checksum(&self) -> &'static str {
        if self.parts.iter().any(|(_, v)| v.ends_with(", ok)")) {
            "checksum ok"
        } else {
            "no checksum"
        }
    }

    fn print(&self) {
        let fit = self.fit;
        say!("frame:    {}", vfd_runtime::error::hex(self.bytes));
        if self.bytes.iter().all(|b| b.is_ascii()) {
            say!("text:     {}", escaped(self.bytes));
        }
        say!(
            "decoded:  {} {} of {} ({}{}), {}",
            fit.protocol.id,
            fit.direction.as_str(),
            fit.drive.id,
            fit.protocol.name,
            other_variant(fit.protocol).map_or_else(String::new, |id| format!(", variant {id}")),
            self.checksum()
        );
        for (name, value) in &self.fields {
            say!("{:<9} {value}", format!("{name}:"));
        }
        if !self.parts.is_empty() {
            say!("parts:");
            for (name, value) in &self.parts {
                say!("  {name:<12} {value}");
            }
        }
        for note in &self.notes {
            say!("note:     {note}");
        }
    }

    /// The frame's register and value as `vfd read` gives them (no time: a captured
    /// frame); `None` when the frame names no register of the drive.
    fn record(&self) -> Option<ValueRecord> {
        let meaning = &self.fit.meaning;
        let info = self.register()?;
        let mut record =
            ValueRecord::new(self.fit.drive.id, info, meaning.data, meaning.text.clone());
        record.tripped = self
            .fit
            .protocol
            .lowercase_means_tripped
            .then_some(meaning.tripped);
        Some(record)
    }

    /// The register the frame names, as the drive describes it.
    fn register(&self) -> Option<&'static vfd_runtime::RegisterInfo> {
        let meaning = &self.fit.meaning;
        let space = meaning.space.unwrap_or(Space::Parameter);
        meaning.register.and_then(|r| {
            self.fit
                .drive
                .register_for(space, r, meaning.kind.is_some_and(|k| k.is_write()))
        })
    }

    fn json(&self) -> serde_json::Value {
        let fit = self.fit;
        let meaning = &fit.meaning;
        let fields: serde_json::Map<String, serde_json::Value> = self
            .fields
            .iter()
            .filter(|(name, _)| !name.starts_with(' '))
            .map(|(name, value)| (name.clone(), serde_json::Value::String(value.clone())))
            .collect();
        let space = meaning.space.unwrap_or(Space::Parameter);
        let info = meaning.register.and_then(|r| {
            fit.drive
                .register_for(space, r, meaning.kind.is_some_and(|k| k.is_write()))
        });
        let bit_fields: Option<Vec<serde_json::Value>> = info.and_then(|i| i.bits).and_then(|bits| {
            meaning.data.map(|data| {
                bits.fields
                    .iter()
                    .map(|f| serde_json::json!({"id": f.id, "name": f.name, "value": f.value(data as u16)}))
                    .collect()
            })
        });
        let mut json = serde_json::json!({
            "valid": true,
            "frame": vfd_runtime::error::hex(self.bytes),
            "drive": fit.drive.id,
            "protocol": fit.protocol.id,
            "direction": fit.direction.as_str(),
            "checksum": self.checksum(),
            "station": meaning.address,
            "broadcast": meaning.broadcast.map(|b| b.to_string()),
            "code": meaning.code.map(code_label),
            "kind": meaning.kind.map(CommandKind::as_str),
            "register": info.map(|i| i.code),
            "register_name": info.map(|i| i.name),
            "register_number": meaning.register,
            "wire_register": meaning.wire_register,
            "index": meaning.index,
            "data": meaning.data,
            "value": meaning.data.and_then(|d| info.map(|i| values::short(i, d))),
            "bit_fields": bit_fields,
            "error_code": meaning.error_code,
            "tripped": meaning.tripped,
            "text": meaning.text,
            "process": meaning.process,
            "fields": fields,
            "parts": self.parts.iter().map(|(n, v)| serde_json::json!({"name": n, "value": v})).collect::<Vec<_>>(),
            "notes": self.notes,
            "record": self.record(),
        });
        if let (Some(id), Some(object)) = (other_variant(fit.protocol), json.as_object_mut()) {
            object.insert("variant".to_owned(), serde_json::json!(id));
        }
        json
    }
}

/// The protocol's variant when it is not the first (the layouts as the file writes them).
fn other_variant(protocol: &Protocol) -> Option<&str> {
    protocol
        .variants
        .as_ref()
        .filter(|variants| variants.current != 0)
        .and_then(|_| protocol.variant_id())
}

/// Every part of the frame's layout with its value, as the protocol file names it.
fn parts(protocol: &Protocol, direction: Direction, bytes: &[u8]) -> Vec<(String, String)> {
    let decoded: Option<(&FrameLayout, FrameValues)> = match direction {
        Direction::Request => protocol
            .decode_request_exact(bytes)
            .ok()
            .map(|r| (&r.command.request, r.values)),
        Direction::Reply => match protocol.decode_reply_exact(None, bytes) {
            Ok(Reply::Data {
                command, values, ..
            }) => Some((&command.reply, values)),
            Ok(Reply::Error { values, .. }) => protocol.error_reply.as_ref().map(|l| (l, values)),
            Err(_) => None,
        },
    };
    let Some((layout, values)) = decoded else {
        return Vec::new();
    };
    layout
        .parts
        .iter()
        .zip(values.parts.iter())
        .filter(|(_, value)| value.present)
        .map(|(part, value)| match part {
            Part::Literal { name, bytes, .. } => (name.to_string(), escaped(bytes)),
            Part::Field(field) => (
                field.name.to_string(),
                match field.role {
                    Role::Address => {
                        match vfd_runtime::broadcast::from_field_value(field, value.value) {
                            Some(_) => format!("{} (broadcast)", value_shown(field, value.value)),
                            None => value.value.to_string(),
                        }
                    }
                    Role::Command => code_label(value.value),
                    Role::Register | Role::Data | Role::Process1 | Role::Process2 => {
                        format!("{:04X}h", value.value)
                    }
                    Role::Words => {
                        let words = values.words(layout, bytes);
                        let shown: Vec<String> = words
                            .as_slice()
                            .iter()
                            .map(|w| format!("{w:04X}h"))
                            .collect();
                        if shown.is_empty() {
                            "(none)".to_owned()
                        } else {
                            shown.join(" ")
                        }
                    }
                    Role::WriteStatus => {
                        let failed: Vec<String> = (0..8)
                            .filter(|bit| value.value & (1 << bit) != 0)
                            .map(|bit| format!("word {} not written", bit + 1))
                            .collect();
                        if failed.is_empty() {
                            format!("{:02X}h (every word written)", value.value)
                        } else {
                            format!("{:02X}h ({})", value.value, failed.join(", "))
                        }
                    }
                    _ => value.value.to_string(),
                },
            ),
            Part::Checksum(sum) => (
                sum.name.to_string(),
                format!("{:02X}h ({}, ok)", value.value, sum.algorithm.as_str()),
            ),
            Part::Word(word) => (word.name.to_string(), format!("{:04X}h", value.value)),
            Part::Length(length) => (length.name.to_string(), value.value.to_string()),
        })
        .collect()
}

/// A station field's value as written on the wire: the broadcast bytes, the digits with the
/// wildcard in the open places, or the number.
fn value_shown(field: &vfd_runtime::FieldSpec, value: u32) -> String {
    let layout = FrameLayout {
        name: "station".into(),
        parts: std::borrow::Cow::Owned(vec![Part::Field(field.clone())]),
        encoding: vfd_runtime::Encoding::Binary,
        plan: None,
    };
    let values = FrameValues {
        parts: {
            let mut parts = [vfd_runtime::FieldValue::default(); vfd_runtime::layout::MAX_PARTS];
            parts[0] = vfd_runtime::FieldValue {
                present: true,
                value,
                width: 0,
            };
            parts
        },
        data_size: 0,
    };
    let mut out = [0u8; 16];
    match vfd_runtime::codec::encode(&layout, &values, &mut out) {
        Ok(len) if field.format.is_digits() => escaped(&out[..len]),
        _ => format!("{value:02X}h"),
    }
}
