//! Register values as people write and read them: engineering units (`60Hz`, `60`,
//! `30.0s`), raw words (`C400h`, `0xC400`), bit-field words by field name
//! (`command_enabled,run`) and code tables by name (`even`), all from the register's
//! [`RegisterInfo`], so every described drive works the same way.

use vfd_runtime::info::{BitWordInfo, CodeTableInfo};
use vfd_runtime::units::{raw_to_number, raw_to_scaled, scaled_to_raw};
use vfd_runtime::{DataType, DriveInfo, RegisterInfo};

/// A number in the register's units with as many decimals as its step has (`60.00 Hz`).
pub fn scaled(info: &RegisterInfo, raw: u32) -> String {
    let value = raw_to_scaled(raw, info);
    let text = format!("{value:.*}", usize::from(info.decimals()));
    match info.unit_symbol() {
        "" => text,
        unit => format!("{text} {unit}"),
    }
}

/// A raw word as the manuals write it (`C400h`).
pub fn hex(info: &RegisterInfo, raw: u32) -> String {
    if info.data_type == DataType::DoubleWord {
        format!("{raw:08X}h")
    } else {
        format!("{raw:04X}h")
    }
}

/// The value on one line: `60.00 Hz`, `1 (Even parity / 偶校验)`, `C400h: command_enabled,
/// frequency_enabled, run`.
pub fn short(info: &RegisterInfo, raw: u32) -> String {
    if let Some(special) = info.special_raw(raw) {
        return format!("{} ({}: {})", special.value, special.id, special.name);
    }
    if let Some(bits) = info.bits {
        let set = set_fields(bits, raw as u16);
        return format!(
            "{}: {}",
            hex(info, raw),
            if set.is_empty() {
                "-".to_owned()
            } else {
                set.join(", ")
            }
        );
    }
    if let Some(codes) = info.codes {
        return format!("{} ({})", scaled(info, raw), code_meaning(codes, raw));
    }
    scaled(info, raw)
}

/// What a code means (`Even parity / 偶校验`), or that the table lacks it.
pub fn code_meaning(codes: &CodeTableInfo, raw: u32) -> String {
    match u16::try_from(raw).ok().and_then(|value| codes.find(value)) {
        Some(code) if code.name_zh.is_empty() => code.name.to_owned(),
        Some(code) => format!("{} / {}", code.name, code.name_zh),
        None if codes.exhaustive => format!("not a code of the table `{}`", codes.id),
        None => format!("not in the manual's table `{}`", codes.id),
    }
}

/// Names of the fields of `bits` that are not zero in `word` (multi-bit fields as
/// `name=value`).
pub fn set_fields(bits: &BitWordInfo, word: u16) -> Vec<String> {
    bits.fields
        .iter()
        .filter(|f| f.value(word) != 0)
        .map(|f| {
            if f.is_flag() {
                f.id.to_owned()
            } else {
                format!("{}={}", f.id, f.value(word))
            }
        })
        .collect()
}

/// Every field of a bit-field word, one line each: `bit 10  run  1  Run/stop: Run`.
pub fn field_lines(bits: &BitWordInfo, word: u16) -> Vec<String> {
    bits.fields
        .iter()
        .map(|f| {
            let value = f.value(word);
            let low = f.mask.trailing_zeros();
            let span = if f.is_flag() {
                format!("bit {low}")
            } else {
                format!("bits {}:{low}", low + f.mask.count_ones() - 1)
            };
            let meaning = match (f.is_flag(), value, f.codes) {
                (_, _, Some(codes)) => code_meaning(codes, u32::from(value)),
                (true, 0, _) => f.zero.to_owned(),
                (true, _, _) => f.one.to_owned(),
                _ => String::new(),
            };
            let meaning = if meaning.is_empty() {
                String::new()
            } else {
                format!(": {meaning}")
            };
            format!("{span:<10} {:<22} {value}  {}{meaning}", f.id, f.name)
        })
        .collect()
}

/// A value for `info` from what a person wrote. Refuses values outside the register's
/// static range, with the range.
pub fn parse(info: &'static RegisterInfo, text: &str) -> Result<u32, String> {
    let trimmed = text.trim();
    if trimmed.is_empty() {
        return Err(format!("no value given for {}", info.label()));
    }
    if let Some(raw) = raw_word(info, trimmed) {
        return check_raw(info, raw);
    }
    if let Some(special) = info
        .special_values
        .iter()
        .find(|s| s.id.eq_ignore_ascii_case(trimmed))
    {
        return Ok(special.raw);
    }
    if let Some(bits) = info.bits {
        if trimmed == "0" {
            // No field set (a stop word).
            return check_raw(info, 0);
        }
        return parse_fields(info, bits, trimmed);
    }
    if let Some(codes) = info.codes {
        if let Some(code) = codes.lookup(trimmed) {
            return check_raw(info, u32::from(code.value));
        }
    }
    let unit = info.unit_symbol();
    let number = if !unit.is_empty() && trimmed.len() > unit.len() && trimmed.ends_with(unit) {
        trimmed[..trimmed.len() - unit.len()].trim()
    } else {
        trimmed
    };
    let value: f64 = number.parse().map_err(|_| {
        let mut message = format!(
            "`{text}` is not a value for {}: give a number",
            info.label()
        );
        if !unit.is_empty() {
            message.push_str(&format!(" in {unit} (e.g. 12.5{unit})"));
        }
        if let Some(codes) = info.codes {
            let names: Vec<&str> = codes.values.iter().map(|c| c.id).collect();
            message.push_str(&format!(" or a code: {}", names.join(", ")));
        }
        message.push_str(", or a raw word such as 0x0064");
        message
    })?;
    scaled_to_raw(value, info).map_err(|e| e.to_string())
}

/// `C400h` or `0xC400` as a raw word (`12h` is twelve hours for a register in hours).
fn raw_word(info: &RegisterInfo, text: &str) -> Option<u32> {
    let digits = text
        .strip_prefix("0x")
        .or_else(|| text.strip_prefix("0X"))
        .or_else(|| {
            if info.unit_symbol() == "h" {
                None
            } else {
                text.strip_suffix('h').or_else(|| text.strip_suffix('H'))
            }
        })?;
    u32::from_str_radix(digits, 16).ok()
}

/// Checks a raw word against the register's range.
fn check_raw(info: &'static RegisterInfo, raw: u32) -> Result<u32, String> {
    let limit = if info.data_type == DataType::DoubleWord {
        u32::MAX
    } else {
        0xFFFF
    };
    if info.special_raw(raw).is_some() {
        return Ok(raw);
    }
    let number = raw_to_number(raw, info.signed, info.data_type) as i64;
    if raw > limit || number < info.raw_min || number > info.raw_max {
        return Err(format!(
            "{}: raw value {} is outside the range {} to {}{}",
            info.label(),
            hex(info, raw),
            range_end(info, info.raw_min),
            range_end(info, info.raw_max),
            info.bound_note()
        ));
    }
    Ok(raw)
}

/// A raw range end in the register's units.
fn range_end(info: &RegisterInfo, raw: i64) -> String {
    let value = raw as f64 * info.scale;
    let text = format!("{value:.*}", usize::from(info.decimals()));
    match info.unit_symbol() {
        "" => text,
        unit => format!("{text} {unit}"),
    }
}

/// `command_enabled,run` or `run|reverse` or `preset=3`: the word with those fields set,
/// every other bit clear.
fn parse_fields(
    info: &'static RegisterInfo,
    bits: &BitWordInfo,
    text: &str,
) -> Result<u32, String> {
    let mut word: u16 = 0;
    for part in text
        .split([',', '|', '+'])
        .map(str::trim)
        .filter(|p| !p.is_empty())
    {
        let (name, value) = match part.split_once('=') {
            Some((name, value)) => {
                let value = value.trim();
                let parsed = value
                    .parse::<u16>()
                    .ok()
                    .or_else(|| {
                        bits.field(name.trim())
                            .and_then(|f| f.codes)
                            .and_then(|c| c.lookup(value))
                            .map(|c| c.value)
                    })
                    .ok_or_else(|| format!("`{part}`: `{value}` is not a number"))?;
                (name.trim(), parsed)
            }
            None => (part, 1),
        };
        let field = bits.field(name).ok_or_else(|| {
            let names: Vec<&str> = bits.fields.iter().map(|f| f.id).collect();
            format!(
                "{} has no field `{name}`; its fields: {} (or give a raw word such as 0x8400)",
                info.label(),
                names.join(", ")
            )
        })?;
        let max = field.mask >> field.mask.trailing_zeros();
        if value > max {
            return Err(format!(
                "field `{}` of {} holds 0 to {max}, not {value}",
                field.id,
                info.label()
            ));
        }
        word = (word & !field.mask) | ((value << field.mask.trailing_zeros()) & field.mask);
    }
    Ok(u32::from(word))
}

/// The range in the register's units, with bounds named after other registers resolved
/// where the drive describes them: `0.00 Hz to 320.00 Hz (upper bound at run time: FH,
/// Maximum frequency)`.
pub fn range_text(drive: &DriveInfo, info: &RegisterInfo) -> String {
    let mut text = format!(
        "{} to {}",
        range_end(info, info.raw_min),
        range_end(info, info.raw_max)
    );
    let name = |code: &str| match drive.register(code) {
        Some(other) => format!("{} ({})", other.code, other.name),
        None => code.to_owned(),
    };
    match (info.min_bound, info.max_bound) {
        (None, None) => {}
        (Some(low), None) => text.push_str(&format!("; at run time not below {}", name(low))),
        (None, Some(high)) => text.push_str(&format!("; at run time not above {}", name(high))),
        (Some(low), Some(high)) => text.push_str(&format!(
            "; at run time between {} and {}",
            name(low),
            name(high)
        )),
    }
    text
}
