//! The stations of `vfd sim`: `--station DRIVE[:PROTOCOL][@ADDRESS]` read and checked (a
//! known drive and protocol, an address in the protocol's range and not taken, one framing
//! on the line, a line speed every drive can be set to), or the one station `-d/--drive`
//! and `--address` give.

use crate::Failure;
use vfd_bus::plant::framing::Framing;
use vfd_bus::{lookup, Catalogue};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::virtual_drive::{BusStation, Simulator};
use vfd_runtime::{DriveInfo, Protocol};

/// One virtual drive of the line, as `vfd sim` serves and names it.
#[derive(Debug, Clone)]
pub struct SimStation {
    /// The drive and the protocol it speaks.
    pub bus: BusStation,
    /// The described drive.
    pub drive: &'static DriveInfo,
    /// Its station number.
    pub address: u8,
}

impl SimStation {
    /// `fc51 (FC51 …) speaking modbus`: how the banner and the logs name it.
    pub fn describe(&self) -> String {
        format!(
            "{} ({}) speaking {}",
            self.drive.id, self.drive.model, self.bus.protocol.id
        )
    }
}

/// A station `DRIVE[:PROTOCOL][@ADDRESS]` as written on the command line.
pub fn parse(catalogue: &Catalogue, spec: &str) -> Result<SimStation, Failure> {
    let hint = "write a station as DRIVE[:PROTOCOL][@ADDRESS], e.g. fc51:modbus@2 or vf-as1@3";
    let (rest, address) = match spec.rsplit_once('@') {
        Some((rest, address)) => {
            let address: u8 = address.parse().map_err(|_| {
                Failure::new(format!(
                    "station `{spec}`: `{address}` is no station address (0-255)"
                ))
                .hint(hint)
            })?;
            (rest, Some(address))
        }
        None => (spec, None),
    };
    // A drive file path may hold a colon (C:\...): the protocol is after the last one,
    // and only when it names a protocol id (no path separator in it).
    let (drive, protocol) = match rest.rsplit_once(':') {
        Some((drive, protocol))
            if !drive.is_empty() && !protocol.contains(['/', '\\']) && !protocol.is_empty() =>
        {
            (drive, Some(protocol))
        }
        _ => (rest, None),
    };
    if drive.is_empty() {
        return Err(Failure::new(format!("station `{spec}` names no drive")).hint(hint));
    }
    let drive = catalogue.drive(drive)?;
    let protocol = lookup::protocol(drive, protocol)?;
    let address = address.unwrap_or_else(|| protocol.address_range.0.max(1));
    let (low, high) = protocol.address_range;
    if address < low.max(1) || address > high {
        return Err(Failure::new(format!(
            "station `{spec}`: address {address} is outside {} {}'s station range {}-{high}",
            drive.id,
            protocol.id,
            low.max(1)
        ))
        .hint("give each station an address in its protocol's range with @N"));
    }
    Ok(station(drive, protocol, address))
}

/// A station of `drive` at `address`, speaking `protocol`, in its factory state.
pub fn station(drive: &'static DriveInfo, protocol: &'static Protocol, address: u8) -> SimStation {
    let simulator = Simulator::new(drive);
    simulator.lock().set_address(address);
    SimStation {
        bus: BusStation {
            simulator,
            protocol,
        },
        drive,
        address,
    }
}

/// Refuses a line whose stations cannot share it: two stations at one address, protocols
/// that frame requests differently, a line speed a drive cannot be set to.
pub fn check_line(stations: &[SimStation], settings: &SerialSettings) -> Result<(), Failure> {
    let Some(first) = stations.first() else {
        return Err(Failure::new("vfd sim: no station to serve")
            .hint("give --drive DRIVE, or one --station DRIVE[:PROTOCOL][@ADDRESS] per station"));
    };
    for (index, station) in stations.iter().enumerate() {
        if let Some(earlier) = stations[..index]
            .iter()
            .find(|s| s.address == station.address)
        {
            return Err(Failure::new(format!(
                "two stations at address {}: {} and {}",
                station.address,
                earlier.describe(),
                station.describe()
            ))
            .hint("each station of a line needs its own address: add @N to the station"));
        }
        // The plant file's rule, so `vfd sim` and `vfd serve --check` agree on which
        // drives can share a line.
        if Framing::of(first.bus.protocol) != Framing::of(station.bus.protocol) {
            return Err(Failure::new(format!(
                "station {} ({}, {}) cannot share the line with station {} ({}, {}): a line \
                 carries one framing",
                station.address,
                station.describe(),
                station.bus.protocol.name,
                first.address,
                first.describe(),
                first.bus.protocol.name
            ))
            .hint("put stations of one protocol family on a line (Modbus RTU with Modbus RTU, Toshiba binary with Toshiba binary)"));
        }
        let rates = station.drive.serial.baud_rates;
        if !rates.is_empty() && !rates.contains(&settings.baud) {
            return Err(Failure::new(format!(
                "station {} ({}) cannot be set to {} baud; it takes {}",
                station.address,
                station.describe(),
                settings.baud,
                rates
                    .iter()
                    .map(u32::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
            .hint("choose a --baud every station on the line takes"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_station_names_its_drive_protocol_and_address() {
        let catalogue = Catalogue::new();
        let s = parse(&catalogue, "fc51:modbus@7").unwrap();
        assert_eq!(
            (s.drive.id, s.bus.protocol.id.as_ref(), s.address),
            ("fc51", "modbus", 7)
        );
        let s = parse(&catalogue, "yd1000").unwrap();
        assert_eq!(s.bus.protocol.id, s.drive.protocols[0].id);
        assert!(parse(&catalogue, "fc51@x").is_err());
        assert!(parse(&catalogue, "@2").is_err());
        assert!(parse(&catalogue, "fc51:nope").is_err());
    }

    #[test]
    fn a_line_refuses_duplicate_addresses_and_mixed_framings() {
        let catalogue = Catalogue::new();
        let settings = catalogue.drive("fc51").unwrap().serial.default;
        let both = [
            parse(&catalogue, "fc51@1").unwrap(),
            parse(&catalogue, "fc51:modbus@1").unwrap(),
        ];
        let err = check_line(&both, &settings).unwrap_err();
        assert!(
            err.message.contains("two stations at address 1"),
            "{}",
            err.message
        );
        let mixed = [
            parse(&catalogue, "fc51:modbus@1").unwrap(),
            parse(&catalogue, "vf-as1:binary@2").unwrap(),
        ];
        let err = check_line(&mixed, &settings).unwrap_err();
        assert!(err.message.contains("one framing"), "{}", err.message);
        let fine = [
            parse(&catalogue, "fc51:modbus@1").unwrap(),
            parse(&catalogue, "vf-as1:modbus@2").unwrap(),
        ];
        check_line(&fine, &settings).unwrap();
    }
}
