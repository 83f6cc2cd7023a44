//! One drive entry of a bus, resolved: its drive model (a built-in id, a drive of the
//! search path, or a drive file relative to the plant file), protocol, variant, port and
//! station address, each refused with the choices there are.

use super::file::DriveFile;
use super::problems::Problems;
use crate::{Catalogue, SetupError};
use std::path::Path;
use vfd_runtime::{DriveInfo, Port, Protocol, Role};

/// A drive entry with everything but its registers resolved.
#[derive(Debug, Clone, Copy)]
pub struct Head {
    /// The drive model.
    pub drive: &'static DriveInfo,
    /// The protocol, in its variant.
    pub protocol: &'static Protocol,
    /// The station address (`None`: the protocol sends none).
    pub address: Option<u8>,
    /// The drive's port the bus is on.
    pub port: Option<Port>,
}

/// A resolved drive entry and where it is in the file.
#[derive(Debug, Clone)]
pub struct Placed {
    /// Its YAML path (`buses[0].drives[1]`).
    pub path: String,
    /// Its `name`.
    pub name: String,
    /// What it resolved to.
    pub head: Head,
    /// Whether it names its protocol (else it speaks the drive's first).
    pub protocol_named: bool,
}

/// Resolves the entry at `path` (`buses[0].drives[1]`); `alone`: the only drive of its bus.
/// `None` when the drive or protocol cannot be found (reported).
pub fn resolve(
    entry: &DriveFile,
    path: &str,
    dir: &Path,
    alone: bool,
    problems: &mut Problems<'_>,
) -> Option<Head> {
    let drive = match drive(problems.catalogue, &entry.drive, dir) {
        Ok(drive) => drive,
        Err(failure) => {
            problems.failure(&format!("{path}.drive"), failure);
            return None;
        }
    };
    let protocol = match crate::lookup::protocol(drive, entry.protocol.as_deref()) {
        Ok(protocol) => protocol,
        Err(failure) => {
            problems.failure(&format!("{path}.protocol"), failure);
            return None;
        }
    };
    let protocol = match entry.variant.as_deref() {
        None => protocol,
        Some(id) => match protocol.variant_or_error(id) {
            Ok(variant) => variant,
            Err(error) => {
                problems.error(
                    &format!("{path}.variant"),
                    error.to_string(),
                    "name one of the protocol's variants (`vfd info DRIVE` lists them), or leave `variant` out for the first",
                );
                protocol
            }
        },
    };
    let port = entry
        .port_kind
        .as_deref()
        .and_then(|name| match drive.ports {
            None => {
                problems.error(
                    &format!("{path}.port_kind"),
                    format!(
                        "drive {} has one serial port: `port_kind` does not apply",
                        drive.id
                    ),
                    "leave `port_kind` out",
                );
                None
            }
            Some(ports) => {
                let port = Port::of(drive, name);
                if port.is_none() {
                    problems.error(
                        &format!("{path}.port_kind"),
                        format!("drive {} has no port `{name}`", drive.id),
                        format!("its ports: {}", ports.ids()),
                    );
                }
                port
            }
        });
    let (min, max) = protocol.address_range;
    let address = match entry.station {
        Some(station) if !(min..=max).contains(&station) => {
            problems.error(
                &format!("{path}.station"),
                format!(
                    "station {station} is outside {}'s range {min} to {max} for protocol `{}`",
                    drive.id, protocol.id
                ),
                format!(
                    "set the drive's station address to one of {min} to {max}, and write that here"
                ),
            );
            Some(station)
        }
        Some(station) if broadcast_address(protocol) == Some(station) => {
            problems.error(
                &format!("{path}.station"),
                format!(
                    "station {station} is the broadcast address of protocol `{}`: every drive on the line carries out a request to it and none answers",
                    protocol.id
                ),
                if station == min {
                    format!("set the drive's station address to one of {} to {max}, and write that here", min + 1)
                } else if station == max {
                    format!("set the drive's station address to one of {min} to {}, and write that here", max - 1)
                } else {
                    format!("set the drive's station address to one of {min} to {max} other than {station}, and write that here")
                },
            );
            Some(station)
        }
        Some(station) => Some(station),
        None if alone => protocol.default_address(),
        None => {
            problems.error(
                path,
                "missing key `station`: a bus with several drives needs each one's station address",
                format!(
                    "add `station:` with the address the drive is set to ({min} to {max} for {} `{}`)",
                    drive.id, protocol.id
                ),
            );
            None
        }
    };
    Some(Head {
        drive,
        protocol,
        address,
        port,
    })
}

/// The station number that addresses every station at once on `protocol` (Modbus 0,
/// Toshiba binary FFh), where its station field has one: the protocol file's `broadcast`.
fn broadcast_address(protocol: &Protocol) -> Option<u8> {
    protocol
        .commands
        .iter()
        .filter_map(|command| command.request.field(Role::Address))
        .find_map(|field| field.broadcast.as_ref()?.all_value)
        .and_then(|value| u8::try_from(value).ok())
}

/// The drive `name` names: a drive file by its path (a relative path starts at the plant
/// file's folder), else a drive id, as every command finds it, with "did you mean".
fn drive(catalogue: &Catalogue, name: &str, dir: &Path) -> Result<&'static DriveInfo, SetupError> {
    if Catalogue::is_path(name) {
        let path = dir.join(name);
        if !path.is_file() {
            return Err(SetupError::new(format!("no drive file {}", path.display())).with_hint(
                "a drive file's path starts at the plant file's folder; or give a drive id (`vfd list`)",
            ));
        }
        return catalogue.drive(&path.to_string_lossy());
    }
    catalogue.drive(name).map_err(|error| {
        let ids: Vec<&str> = catalogue.all_drives().iter().map(|d| d.id).collect();
        match (vfd_codegen::yaml::closest(name, &ids), error.hint()) {
            (Some(close), Some(hint)) => {
                let hint = format!("did you mean `{close}`? {hint}");
                error.with_hint(hint)
            }
            _ => error,
        }
    })
}
