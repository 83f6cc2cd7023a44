//! Finding what people name: protocols by id, variants, ports, and registers by manual
//! code (`FA01`, `FH`, `3-03`), alias (`P.195`), address (`0xFA01`, `FA01h`, `303`), id or
//! English or Chinese name (`最高频率`), case-insensitive (drives: [`Catalogue::drive`]).
//! Nothing here names a drive: everything comes from [`DriveInfo`]. Names are looked up when
//! a command or a plant is set up; what runs after holds what they found.

use crate::{Catalogue, SetupError};
use vfd_runtime::info::manual_number;
use vfd_runtime::{Access, DriveInfo, Port, Protocol, RegisterInfo};

/// The drive's protocol with this id; the first one when `id` is `None`.
pub fn protocol(drive: &DriveInfo, id: Option<&str>) -> Result<&'static Protocol, SetupError> {
    let known = || {
        let ids: Vec<&str> = drive.protocols.iter().map(|p| p.id.as_ref()).collect();
        ids.join(", ")
    };
    match id {
        None => drive
            .protocols
            .first()
            .copied()
            .ok_or_else(|| SetupError::new(format!("drive {} describes no protocol", drive.id))),
        Some(id) => drive
            .protocols
            .iter()
            .copied()
            .find(|p| p.id.eq_ignore_ascii_case(id))
            .ok_or_else(|| {
                SetupError::new(format!("drive {} has no protocol `{id}`", drive.id))
                    .with_hint(format!("it speaks: {}", known()))
            }),
    }
}

/// `protocol` in its variant `id` (`None`: as it is).
pub fn variant(
    protocol: &'static Protocol,
    id: Option<&str>,
) -> Result<&'static Protocol, SetupError> {
    let Some(id) = id else {
        return Ok(protocol);
    };
    protocol.variant_or_error(id).map_err(|error| {
        SetupError::new(error.to_string())
            .with_hint("name one of the protocol's variants, or leave --variant out")
    })
}

/// Every register `name` may mean, best match first: an exact code, id or alias, then the
/// code, id, alias, address or name without regard to case, then names containing it.
pub fn registers(drive: &DriveInfo, name: &str) -> Vec<&'static RegisterInfo> {
    let wanted = name.trim();
    let all = drive.registers;
    let exact: Vec<_> = all
        .iter()
        .copied()
        .filter(|r| r.code == wanted || r.id == wanted || r.aliases.contains(&wanted))
        .collect();
    if !exact.is_empty() {
        return exact;
    }
    let address = parse_address(wanted);
    let same: Vec<_> = all
        .iter()
        .copied()
        .filter(|r| {
            r.code.eq_ignore_ascii_case(wanted)
                || r.id.eq_ignore_ascii_case(wanted)
                || r.aliases.iter().any(|a| a.eq_ignore_ascii_case(wanted))
                || r.name.eq_ignore_ascii_case(wanted)
                || r.name_zh == wanted
                // A register known by its wire numbers only has no number to be found by.
                || (r.has_address
                    && (manual_number(r.space, r.address, r.code).eq_ignore_ascii_case(wanted)
                        || address.is_some_and(|a| a == r.address)))
        })
        .collect();
    if !same.is_empty() {
        return same;
    }
    // Parameter numbers as manuals print them with a group separator (`3-03` for 303).
    let joined: String = wanted.chars().filter(|c| !matches!(c, '-' | '.')).collect();
    if joined != wanted && !joined.is_empty() {
        let grouped: Vec<_> = all
            .iter()
            .copied()
            .filter(|r| r.code.eq_ignore_ascii_case(&joined))
            .collect();
        if !grouped.is_empty() {
            return grouped;
        }
    }
    let lower = wanted.to_lowercase();
    if lower.chars().count() < 2 {
        return Vec::new();
    }
    all.iter()
        .copied()
        .filter(|r| {
            r.name.to_lowercase().contains(&lower)
                || r.name_zh.contains(wanted)
                || r.id.contains(&lower.replace(' ', "_"))
        })
        .collect()
}

/// The port `name` names (id or English name) of `drive`; `None` when no port is named.
/// Refuses a name the drive does not have, or any name for a drive with one port.
pub fn port(drive: &'static DriveInfo, name: Option<&str>) -> Result<Option<Port>, SetupError> {
    let Some(name) = name else {
        return Ok(None);
    };
    let Some(ports) = drive.ports else {
        return Err(SetupError::new(format!(
            "drive {} has one serial port: --port-kind does not apply",
            drive.id
        ))
        .with_hint("leave --port-kind out"));
    };
    Port::of(drive, name).map(Some).ok_or_else(|| {
        SetupError::new(format!("drive {} has no port `{name}`", drive.id))
            .with_hint(format!("its ports: {}", ports.ids()))
    })
}

/// The one register `name` means on `drive`, or why not (none, or several); `named` is how
/// a command line names the drive ([`Catalogue::name_for`]), for the hint.
pub fn register(
    drive: &DriveInfo,
    name: &str,
    named: &str,
) -> Result<&'static RegisterInfo, SetupError> {
    let found = registers(drive, name);
    match found.as_slice() {
        [one] => Ok(one),
        [] => Err(
            SetupError::new(format!("drive {} has no register `{name}`", drive.id)).with_hint(
                format!(
                    "name it by code (FA01), address (0xFA01), id or name; `vfd info {named}` lists them"
                ),
            ),
        ),
        many => {
            let names: Vec<String> = many
                .iter()
                .take(8)
                .map(|r| format!("{} ({})", r.code, r.name))
                .collect();
            Err(SetupError::new(format!(
                "`{name}` matches {} registers of {}",
                many.len(),
                drive.id
            ))
            .with_hint(format!("say which: {}", names.join(", "))))
        }
    }
}

/// The one register `name` means for a read (`writing` false) or a write: where it names
/// two registers sharing an address (one read-only, one write-only: 1001h read as a status
/// word, written as a run command), the one the direction reaches. `named`: as
/// [`register`].
pub fn register_for(
    drive: &DriveInfo,
    name: &str,
    writing: bool,
    named: &str,
) -> Result<&'static RegisterInfo, SetupError> {
    let found = registers(drive, name);
    if let [first, second] = found.as_slice() {
        if first.address == second.address && first.space == second.space {
            let blocked = if writing {
                Access::ReadOnly
            } else {
                Access::WriteOnly
            };
            if let Some(one) = [first, second].into_iter().find(|r| r.access != blocked) {
                return Ok(one);
            }
        }
    }
    register(drive, name, named)
}

impl Catalogue {
    /// The one register `name` means on `drive` ([`register`]).
    pub fn register(
        &self,
        drive: &DriveInfo,
        name: &str,
    ) -> Result<&'static RegisterInfo, SetupError> {
        register(drive, name, &self.name_for(drive))
    }

    /// The one register `name` means on `drive` for a read or a write ([`register_for`]).
    pub fn register_for(
        &self,
        drive: &DriveInfo,
        name: &str,
        writing: bool,
    ) -> Result<&'static RegisterInfo, SetupError> {
        register_for(drive, name, writing, &self.name_for(drive))
    }
}

/// `0xFA01`, `FA01h` or a decimal number, as a register address.
fn parse_address(text: &str) -> Option<u16> {
    if let Some(hex) = text
        .strip_prefix("0x")
        .or_else(|| text.strip_prefix("0X"))
        .or_else(|| text.strip_suffix('h'))
        .or_else(|| text.strip_suffix('H'))
    {
        return u16::from_str_radix(hex, 16).ok();
    }
    text.parse().ok()
}
