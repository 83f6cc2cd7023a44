//! Words for people, shared by the Rust docs and the Markdown pages: how the manual numbers
//! a register, ranges and values in engineering units, frame bytes, what a frame means.
//! The IR holds facts only; every sentence is built here or in the templates.

use crate::ir::{
    BitOrder, DriveIr, Duplex, ErrorCodesIr, FrameIr, InferredFact, RegisterIr, Synchronisation,
    Topology, WarningIr,
};
use vfd_runtime::units::decimals_of;
use vfd_runtime::Space;

/// How the manual numbers a register: coils by number (`coil 17`), decimal parameters as
/// written (`303`), communication numbers in hex (`FA01`).
pub fn address_label(register: &RegisterIr) -> String {
    if register.wire_only {
        // Known by its wire numbers only: its code is its name.
        return register.code.clone();
    }
    vfd_runtime::info::manual_number(register.space, register.address, &register.code)
}

/// A raw count of `register` in engineering units, without float noise (`320.00`).
pub fn raw_text(register: &RegisterIr, raw: i64) -> String {
    number_text(register, raw as f64 * register.scale)
}

/// An engineering value with the register's decimals (`60.00`).
pub fn number_text(register: &RegisterIr, value: f64) -> String {
    format!("{:.*}", usize::from(decimals_of(register.scale)), value)
}

/// An engineering value with its unit (`60.00 Hz`).
pub fn value_text(register: &RegisterIr, value: f64) -> String {
    if let Some(special) = register.special_values.iter().find(|s| s.value == value) {
        return format!("{} ({})", special.value, special.id);
    }
    let unit = register.unit.symbol();
    let number = number_text(register, value);
    if unit.is_empty() {
        number
    } else {
        format!("{number} {unit}")
    }
}

/// The range as the manual gives it (`0.00 … FH (≤ 320.00)`), or `—` when it gives none.
pub fn range_text(register: &RegisterIr) -> String {
    let (Some(min), Some(max)) = (&register.min, &register.max) else {
        return "—".to_owned();
    };
    let low = match &min.register {
        Some(name) => format!("{name} (≥ {})", raw_text(register, min.raw)),
        None => raw_text(register, min.raw),
    };
    let high = match &max.register {
        Some(name) => format!("{name} (≤ {})", raw_text(register, max.raw)),
        None => raw_text(register, max.raw),
    };
    let specials: Vec<String> = register
        .special_values
        .iter()
        .map(|s| format!("{} ({})", s.value, s.id))
        .collect();
    if specials.is_empty() {
        format!("{low} … {high}")
    } else {
        format!("{low} … {high}, or {}", specials.join(", "))
    }
}

/// The factory default (`50.00`), or `—`.
pub fn default_text(register: &RegisterIr) -> String {
    register.default.map_or_else(
        || "—".to_owned(),
        |d| match register.special_values.iter().find(|s| s.value == d) {
            Some(special) => format!("{} ({})", special.value, special.id),
            None => number_text(register, d),
        },
    )
}

/// The Rust type of the register's value, as written in docs (`Hertz`, `u16`).
pub fn value_type_text(register: &RegisterIr) -> String {
    use crate::ir::ValueKind;
    match &register.value {
        ValueKind::Quantity(name) | ValueKind::CodeTable(name) | ValueKind::Bitfield(name) => {
            name.clone()
        }
        ValueKind::Raw => "u16".to_owned(),
        ValueKind::RawSigned => "i16".to_owned(),
        ValueKind::Scaled => "f64".to_owned(),
        ValueKind::RawDouble => "u32".to_owned(),
        ValueKind::RawSignedDouble => "i32".to_owned(),
        ValueKind::Text => "String".to_owned(),
    }
}

/// The register facts a description inferred, as a list (`unit, step`).
pub fn inferred_text(facts: &[InferredFact]) -> String {
    facts
        .iter()
        .map(|fact| match fact {
            InferredFact::Name => "English name",
            InferredFact::Unit => "unit",
            InferredFact::Scale => "step",
            InferredFact::Range => "range",
            InferredFact::Default => "default",
            InferredFact::Access => "access",
            InferredFact::DataType => "data type",
            InferredFact::RamOnly => "RAM only",
            InferredFact::WritableWhileRunning => "writable while running",
            InferredFact::Address => "address",
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A warning as one sentence, with its manual section when it has one.
pub fn warning_text(warning: &WarningIr) -> String {
    if warning.source.is_empty() {
        warning.text.clone()
    } else {
        format!("{} (manual: {})", warning.text, warning.source)
    }
}

/// Duplex in words.
pub fn duplex_text(duplex: Duplex) -> &'static str {
    match duplex {
        Duplex::Half => "half duplex (one direction at a time)",
        Duplex::Full => "full duplex",
    }
}

/// Line control in words.
pub fn topology_text(topology: Topology) -> &'static str {
    match topology {
        Topology::MasterSlave => "centralised: one master polls, the addressed drive answers",
        Topology::MultiMaster => "multi-master",
    }
}

/// Synchronisation in words.
pub fn synchronisation_text(synchronisation: Synchronisation) -> &'static str {
    match synchronisation {
        Synchronisation::Asynchronous => "asynchronous (start and stop bits)",
        Synchronisation::Synchronous => "synchronous",
    }
}

/// Bit order in words.
pub fn bit_order_text(order: BitOrder) -> &'static str {
    match order {
        BitOrder::LsbFirst => "least significant bit first",
        BitOrder::MsbFirst => "most significant bit first",
    }
}

/// ` (中文)`, or nothing when the manual gives no Chinese text.
pub fn zh(text: &str) -> String {
    if text.is_empty() {
        String::new()
    } else {
        format!(" ({text})")
    }
}

/// Bytes as upper-case hex pairs (`2F 52 FD 00`): the runtime's rendering.
pub use vfd_runtime::error::hex;

/// Frame bytes for people: text with `<CR>`/`<LF>` when every byte is printable, else hex.
pub fn shown_bytes(bytes: &[u8]) -> String {
    if bytes
        .iter()
        .all(|b| b.is_ascii_graphic() || *b == b' ' || *b == b'\r' || *b == b'\n')
    {
        String::from_utf8_lossy(bytes)
            .replace('\r', "<CR>")
            .replace('\n', "<LF>")
    } else {
        hex(bytes)
    }
}

/// What a frame means, in one line (`` `R` (read), station 1, register FA01, data 1770h ``);
/// an error code is written with `error_digits` hex digits and named from `errors`, the
/// table of the frame's protocol.
pub fn meaning_text(
    drive: &DriveIr,
    frame: &FrameIr,
    errors: &ErrorCodesIr,
    error_digits: usize,
) -> String {
    let meaning = &frame.meaning;
    let label = vfd_runtime::protocol::code_label;
    if let Some(code) = meaning.error_code {
        let entry = errors.codes.iter().find(|c| c.code == code);
        // In the manual's notation where the table states it (the DV1's H0C).
        let shown = entry
            .map(|e| e.printed.clone())
            .filter(|p| !p.is_empty())
            .unwrap_or_else(|| format!("{code:0error_digits$X}h"));
        return format!(
            "error reply{}: error {shown}{}",
            meaning
                .code
                .map(|c| format!(" `{}`", label(c)))
                .unwrap_or_default(),
            entry
                .map(|e| match e.name_zh.as_str() {
                    "" => format!(" {}", e.name),
                    zh => format!(" {} ({zh})", e.name),
                })
                .unwrap_or_default()
        );
    }
    let mut parts = Vec::new();
    let kind = meaning.kind.map_or("?", |k| k.as_str());
    match meaning.code {
        Some(code) => parts.push(format!("`{}` ({kind})", label(code))),
        None => parts.push(kind.to_owned()),
    }
    if let Some(address) = meaning.address {
        parts.push(format!("station {address}"));
    }
    match meaning.broadcast {
        Some(vfd_runtime::Broadcast::All) => parts.push("broadcast to every station".to_owned()),
        Some(vfd_runtime::Broadcast::Group(group)) => {
            parts.push(format!("broadcast to the stations {group}"))
        }
        None => {}
    }
    let named = meaning
        .register
        .and_then(|address| drive.register_at(meaning.space.unwrap_or(Space::Parameter), address));
    match (named, meaning.register, meaning.wire_register) {
        (Some(register), _, Some(wire)) if address_label(register) != format!("{wire:04X}") => {
            let prefix = if register.space == Space::Coil {
                ""
            } else {
                "register "
            };
            parts.push(format!(
                "{prefix}{} (wire {wire:04X}h)",
                address_label(register)
            ));
        }
        (Some(register), _, _) => parts.push(format!("register {}", address_label(register))),
        (None, Some(register), _) => {
            parts.push(format!("register {register:04X}h (none described there)"))
        }
        (None, None, Some(wire)) => parts.push(format!("wire register {wire:04X}h")),
        _ => {}
    }
    if let Some(index) = meaning.index {
        parts.push(format!("index {index}"));
    }
    if let Some(data) = meaning.data {
        parts.push(if data > 9 {
            format!("data {data:04X}h ({data})")
        } else {
            format!("data {data}")
        });
    }
    if let Some([first, second]) = meaning.process {
        parts.push(format!("process words {first:04X}h {second:04X}h"));
    }
    if let Some(text) = &meaning.text {
        parts.push(format!("text {text:?}"));
    }
    if let Some(words) = &meaning.words {
        let shown: Vec<String> = words.iter().map(|w| format!("{w:04X}h")).collect();
        parts.push(match shown.is_empty() {
            true => "no words".to_owned(),
            false => format!("words {}", shown.join(" ")),
        });
    }
    if let Some(count) = meaning.read_count {
        parts.push(format!("{count} word(s) asked back"));
    }
    if let Some(status) = meaning.write_status {
        parts.push(format!("write status {status:02X}h"));
    }
    if meaning.tripped {
        parts.push("drive tripped".to_owned());
    }
    parts.join(", ")
}
