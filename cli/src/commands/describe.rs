//! `vfd list` and `vfd info`: what the descriptions say about each drive, from its
//! `DriveInfo` alone.

use crate::emit::{Emitter, Format};
use crate::out::say;
use crate::Failure;
use vfd_bus::catalogue::Found;
use vfd_bus::record::{DriveRecord, RegisterRecord};
use vfd_bus::values;
use vfd_bus::{lookup, Catalogue};
use vfd_runtime::info::manual_number;
use vfd_runtime::{Access, DriveInfo, RegisterInfo, TakesEffect};

/// Every described drive with its protocols and serial defaults: those compiled in, then
/// the drive files of the search path (a file with problems is named, with the command that
/// lists them).
pub fn list(catalogue: &Catalogue, format: Format) -> Result<(), Failure> {
    if !format.is_text() {
        let mut emitter = Emitter::new(format);
        for drive in catalogue.builtin() {
            emitter.record(&DriveRecord::new(drive, None));
        }
        for found in catalogue.search_path_drives() {
            if let Found::Drive(file, drive, _) = found {
                if !catalogue.builtin().iter().any(|d| d.id == drive.id) {
                    emitter.record(&DriveRecord::new(drive, Some(&file)));
                }
            }
        }
        emitter.finish();
        return Ok(());
    }
    for drive in catalogue.builtin() {
        list_drive(drive, None);
    }
    for found in catalogue.search_path_drives() {
        match found {
            Found::Drive(file, drive, off_the_wire) => {
                if off_the_wire > 0 {
                    say!(
                        "{}: usable on the wire, {off_the_wire} problem(s) elsewhere (`vfd check {}` lists them)",
                        file.display(),
                        file.display()
                    );
                }
                if catalogue.builtin().iter().any(|d| d.id == drive.id) {
                    say!(
                        "{}: drive {} is also built in; by id, vfd uses the built-in one (name the file by its path to use it)",
                        file.display(),
                        drive.id
                    );
                } else {
                    list_drive(drive, Some(&file));
                }
            }
            Found::Broken(file, problems) => say!(
                "{}: not usable, {problems} problem(s) (`vfd check {}` lists them)",
                file.display(),
                file.display()
            ),
        }
    }
    Ok(())
}

/// One drive of `vfd list`, and the file it comes from when it is not built in.
fn list_drive(drive: &DriveInfo, file: Option<&std::path::Path>) {
    {
        let serial = drive.serial.default;
        say!(
            "{:<10} {} {} ({}): {} registers; {} baud, {}{}{}{}",
            drive.id,
            drive.vendor,
            drive.model,
            drive.name_zh,
            drive.registers.len(),
            serial.baud,
            serial.data_bits,
            serial
                .parity
                .as_str()
                .chars()
                .next()
                .unwrap_or('n')
                .to_ascii_uppercase(),
            serial.stop_bits,
            if drive.behaviour.is_some() {
                "; virtual drive"
            } else {
                ""
            }
        );
        for protocol in drive.protocols {
            // A protocol whose character format a setting chooses (DV1 Modbus RTU: 8E1).
            let own = drive.serial.default_for(&protocol.id);
            say!(
                "    {:<10} {} (stations {}-{}{})",
                protocol.id,
                protocol.name,
                protocol.address_range.0,
                protocol.address_range.1,
                if own == serial {
                    String::new()
                } else {
                    format!(", {}", own.format_label())
                }
            );
        }
        if let Some(file) = file {
            say!("    from {}", file.display());
        }
    }
}

/// The registers `name` names on `drive` (an array's elements, or one register), or the
/// lookup's error with its suggestions.
fn named_registers(
    catalogue: &Catalogue,
    drive: &DriveInfo,
    name: &str,
) -> Result<Vec<&'static RegisterInfo>, Failure> {
    let found = lookup::registers(drive, name);
    if found.is_empty() {
        return Err(catalogue.register(drive, name).err().map_or_else(
            || Failure::new(format!("no register `{name}`")),
            Failure::from,
        ));
    }
    Ok(found)
}

/// A drive's registers (one line each), or the named ones in full.
pub fn info(
    catalogue: &Catalogue,
    drive: &str,
    names: &[String],
    format: Format,
) -> Result<(), Failure> {
    let drive = catalogue.drive(drive)?;
    if !format.is_text() {
        let mut registers = Vec::new();
        for name in names {
            registers.extend(named_registers(catalogue, drive, name)?);
        }
        if names.is_empty() {
            registers.extend(drive.registers.iter().copied());
        }
        let mut emitter = Emitter::new(format);
        for register in registers {
            emitter.record(&RegisterRecord::new(drive.id, register));
        }
        emitter.finish();
        return Ok(());
    }
    if names.is_empty() {
        say!(
            "{} {} ({}), {} — manual {}",
            drive.vendor,
            drive.model,
            drive.name_zh,
            drive.name,
            drive.manual_title
        );
        let protocols: Vec<&str> = drive.protocols.iter().map(|p| p.id.as_ref()).collect();
        say!(
            "protocols: {}; {} registers (`vfd info {} REGISTER` for one in full)",
            protocols.join(", "),
            drive.registers.len(),
            catalogue.name_for(drive)
        );
        say!("{}", control_line(drive));
        if let Some(ports) = drive.ports {
            for port in ports.ports {
                let settings: Vec<String> = port
                    .settings
                    .iter()
                    .map(|(what, code)| format!("{what} {code}"))
                    .collect();
                say!(
                    "port {} ({} / {}): {}",
                    port.id,
                    port.name,
                    port.name_zh,
                    settings.join(", ")
                );
            }
            say!(
                "shared by the ports: {}; pick a port with --port-kind",
                ports.shared.join(", ")
            );
        }
        say!(
            "{:<8} {:<7} {:<34} {:<22} {:<7} {:<26} {:<11} {}",
            "number",
            "code",
            "name",
            "",
            "unit",
            "range",
            "access",
            "flags"
        );
        for register in drive.registers {
            say!("{}", summary_line(register));
        }
        return Ok(());
    }
    let mut first = true;
    for name in names {
        for register in named_registers(catalogue, drive, name)? {
            if !first {
                say!("");
            }
            first = false;
            details(drive, register);
        }
    }
    Ok(())
}

fn summary_line(r: &RegisterInfo) -> String {
    let range = if r.bits.is_some() {
        "bit fields".to_owned()
    } else if let Some(codes) = r.codes {
        format!("codes: {}", codes.id)
    } else {
        let scale = |raw: i64| format!("{:.*}", usize::from(r.decimals()), raw as f64 * r.scale);
        format!("{}..{}", scale(r.raw_min), scale(r.raw_max))
    };
    let mut flags = Vec::new();
    if r.ram_only {
        flags.push("RAM");
    }
    if r.persistent_write_to_ram {
        flags.push("persist-to-RAM");
    }
    if r.writable_while_running {
        flags.push("run-writable");
    } else if r.while_running_unknown {
        flags.push("run-unknown");
    }
    if r.takes_effect == TakesEffect::AfterReset {
        flags.push("after-reset");
    }
    format!(
        "{:<8} {:<7} {} {} {:<7} {} {:<11} {}",
        number_text(r),
        r.code,
        clip(r.name, 34),
        clip(r.name_zh, 22),
        r.unit_symbol(),
        clip(&range, 26),
        r.access.as_str(),
        flags.join(",")
    )
}

/// The register's number as the manual writes it; `-` for one known by its wire numbers
/// only.
fn number_text(r: &RegisterInfo) -> String {
    if r.has_address {
        manual_number(r.space, r.address, r.code)
    } else {
        "-".to_owned()
    }
}

/// Columns a character takes on a terminal (CJK characters take two).
fn char_width(c: char) -> usize {
    if c >= '\u{2E80}' && !('\u{FF61}'..='\u{FFDC}').contains(&c) {
        2
    } else {
        1
    }
}

/// `text` clipped to `width` terminal columns and padded to them.
fn clip(text: &str, width: usize) -> String {
    let total: usize = text.chars().map(char_width).sum();
    let mut out = String::new();
    let mut used = 0;
    if total <= width {
        out.push_str(text);
        used = total;
    } else {
        for c in text.chars() {
            if used + char_width(c) > width.saturating_sub(1) {
                break;
            }
            out.push(c);
            used += char_width(c);
        }
        out.push('…');
        used += 1;
    }
    out.push_str(&" ".repeat(width.saturating_sub(used)));
    out
}

/// Everything about one register.
fn details(drive: &DriveInfo, r: &'static RegisterInfo) {
    say!("{}", r.label());
    say!("  code        {}", r.code);
    if !r.aliases.is_empty() {
        say!("  also named  {}", r.aliases.join(", "));
    }
    say!("  id          {}", r.id);
    if r.has_address {
        say!(
            "  number      {} ({}{})",
            manual_number(r.space, r.address, r.code),
            r.space.as_str(),
            if r.array_len > 0 {
                format!(", array of {}", r.array_len)
            } else {
                String::new()
            }
        );
    } else {
        say!("  number      none of its own: reached by its wire numbers");
    }
    for protocol in drive.protocols {
        if let Some(own) = protocol
            .wire_numbers
            .iter()
            .find(|w| w.register == r.address)
        {
            let shown = |n: Option<u16>| n.map_or("-".to_owned(), |n| format!("{n:02X}h"));
            if own.read.is_some() || own.write.is_some() {
                say!(
                    "  on {:<9}read {}, write {}",
                    protocol.id,
                    shown(own.read),
                    shown(own.write)
                );
            }
        } else if let Some((page, offset)) = protocol.page_of(r.address) {
            say!("  on {:<9}page {page}, offset {offset:02X}h", protocol.id);
        }
    }
    let unit = match r.unit_symbol() {
        "" => "none".to_owned(),
        unit => format!("{unit}, in steps of {}", r.scale),
    };
    say!("  unit        {unit}");
    say!("  type        {}", r.data_type.as_str());
    if r.bits.is_none() {
        say!("  range       {}", values::range_text(drive, r));
    }
    match r.default_raw {
        Some(raw) => say!("  default     {}", values::short(r, raw)),
        None => say!("  default     (the manual gives none)"),
    }
    let access = match r.access {
        Access::ReadOnly => "read-only",
        Access::WriteOnly => "write-only",
        Access::ReadWrite => "read-write",
    };
    say!("  access      {access}");
    say!("  storage     {}", vfd_bus::storage::storage_line(drive, r));
    say!(
        "  while run   {}",
        if r.writable_while_running {
            "writable while the motor runs"
        } else if r.while_running_unknown {
            "not stated by the manual (a write while running is attempted; a refusal is reported)"
        } else {
            "not writable while the motor runs"
        }
    );
    if r.takes_effect == TakesEffect::AfterReset {
        say!("  takes effect after a reset or power cycle");
    }
    if r.panel_only {
        say!("  effective only when set from the operator panel");
    }
    if let Some(codes) = r.codes {
        say!(
            "  codes       {} ({}){}",
            codes.name,
            codes.name_zh,
            if codes.exhaustive {
                ""
            } else {
                ", not every value is listed"
            }
        );
        for code in codes.values {
            say!(
                "    {:>5}  {:<20} {}{}",
                code.value,
                code.id,
                code.name,
                if code.name_zh.is_empty() {
                    String::new()
                } else {
                    format!(" / {}", code.name_zh)
                }
            );
        }
    }
    if let Some(bits) = r.bits {
        say!("  bit fields  {} ({})", bits.name, bits.name_zh);
        for field in bits.fields {
            let low = field.mask.trailing_zeros();
            let span = if field.is_flag() {
                format!("{low}")
            } else {
                format!("{}:{low}", low + field.mask.count_ones() - 1)
            };
            let meanings = if field.zero.is_empty() && field.one.is_empty() {
                String::new()
            } else {
                format!(" (0: {}, 1: {})", field.zero, field.one)
            };
            say!(
                "    {span:>5}  {:<20} {} / {}{meanings}",
                field.id,
                field.name,
                field.name_zh
            );
        }
    }
    if let Some(live) = r.held_at_trip_of {
        say!("  at trip     holds the value {live} had at the last trip");
    }
    if r.live_except_while_tripped {
        say!("  at trip     live, but keeps its value while the drive is tripped");
    }
    if let Some(scale_by) = r.scale_by {
        let listed = scale_by
            .choices
            .iter()
            .map(|choice| (format!("= {}", choice.value), choice.info));
        let other = scale_by
            .otherwise
            .map(|info| ("any other value".to_owned(), info));
        for (selector, c) in listed.chain(other) {
            let end = |raw: i64| format!("{:.*}", usize::from(c.decimals()), raw as f64 * c.scale);
            say!(
                "  scale       {} {}: steps of {} {} ({}..{})",
                scale_by.register,
                selector,
                c.scale,
                c.unit_symbol(),
                end(c.raw_min),
                end(c.raw_max)
            );
        }
    }
    for special in r.special_values {
        say!(
            "  also        {} ({}: {}), carried as {:04X}h",
            special.value,
            special.id,
            special.name,
            special.raw
        );
    }
    if !r.per_port.is_empty() {
        let copies: Vec<String> = r
            .per_port
            .iter()
            .map(|(port, code)| format!("{code} on {port}"))
            .collect();
        say!(
            "  per port    {} (--port-kind picks one)",
            copies.join(", ")
        );
    }
    if !r.text.is_empty() {
        say!("  manual      {}", r.text);
    }
}

/// The drive's control roles on one line (`vfd run`, `stop`, `reset`, `state`), or the
/// roles it lacks.
pub fn control_line(drive: &'static vfd_runtime::DriveInfo) -> String {
    match vfd_bus::control::Roles::of(drive) {
        Ok(roles) => format!(
            "control: {} (command {}, speed {} in {}; `vfd run`, `stop`, `reset`, `state`)",
            roles.names().join(", "),
            roles.command.code,
            roles.speed.code,
            match roles.percent_of {
                Some(_) => "Hz, as a percentage",
                None => roles.speed.unit_symbol(),
            }
        ),
        Err(missing) => format!(
            "control: none (no {} role in its behaviour model)",
            missing.missing.join(", ")
        ),
    }
}
