//! `vfd ports`: the serial ports the system has, with the USB vendor and product ids,
//! manufacturer, product and serial number where the system knows them.
//!
//! The list is `serialport::available_ports` (built without libudev: on Linux it reads
//! `/sys/class/tty`, USB details included). Two Linux corrections are made here: the
//! 8250 driver's placeholder ports (`/dev/ttyS0`..`ttyS3` with no UART behind them, UART
//! type 0 in sysfs) are left out, and a system without `/sys/class/tty` (some containers)
//! has no ports instead of making the crate panic.

use crate::emit::{Emitter, Format};
use crate::out::say;
use crate::Failure;
use serialport::{SerialPortInfo, SerialPortType};
use std::path::Path;

/// One serial port, as `vfd ports --format json|jsonl|csv` prints it.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Port {
    /// The name to give `--port` (`/dev/ttyUSB0`, `COM3`).
    pub name: String,
    /// `usb`, `pci`, `bluetooth` or `other`.
    pub kind: &'static str,
    /// USB vendor id, four hex digits (`0403`), where known.
    pub vendor_id: Option<String>,
    /// USB product id, four hex digits (`6001`), where known.
    pub product_id: Option<String>,
    /// USB manufacturer string, where known.
    pub manufacturer: Option<String>,
    /// USB product string, where known.
    pub product: Option<String>,
    /// USB serial number, where known.
    pub serial_number: Option<String>,
}

/// The line printed when the system has no serial port.
pub const NONE: &str = "no serial ports found (a USB adapter shows up here once plugged in)";

/// Lists the serial ports, one record each in a machine-readable `format` (fields as in
/// [`Port`]).
pub fn run(format: Format) -> Result<(), Failure> {
    let ports = system_ports()?;
    if format.is_text() {
        for line in text_lines(&ports) {
            say!("{line}");
        }
        return Ok(());
    }
    let mut emitter = Emitter::new(format);
    for port in &ports {
        emitter.record(port);
    }
    emitter.finish();
    Ok(())
}

/// The ports of this system, sorted by name.
fn system_ports() -> Result<Vec<Port>, Failure> {
    let sys_tty = Path::new("/sys/class/tty");
    if cfg!(target_os = "linux") && !sys_tty.is_dir() {
        // serialport would panic here; a system without sysfs has no ports to show.
        return Ok(Vec::new());
    }
    let found = serialport::available_ports()
        .map_err(|e| Failure::new(format!("cannot list the serial ports: {e}")))?;
    let mut ports: Vec<Port> = found
        .into_iter()
        .filter(|info| !is_placeholder_uart(sys_tty, &info.port_name))
        .map(port)
        .collect();
    ports.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(ports)
}

/// A Linux 8250 placeholder: `/dev/ttySN` whose sysfs `type` is 0 (no UART found there).
/// Only Linux has the file; elsewhere nothing is a placeholder.
fn is_placeholder_uart(sys_tty: &Path, port_name: &str) -> bool {
    let Some(device) = port_name.strip_prefix("/dev/") else {
        return false;
    };
    if !device.starts_with("ttyS") {
        return false;
    }
    std::fs::read_to_string(sys_tty.join(device).join("type")).is_ok_and(|text| text.trim() == "0")
}

/// The crate's description as a [`Port`].
fn port(info: SerialPortInfo) -> Port {
    let mut port = Port {
        name: info.port_name,
        kind: "other",
        vendor_id: None,
        product_id: None,
        manufacturer: None,
        product: None,
        serial_number: None,
    };
    match info.port_type {
        SerialPortType::UsbPort(usb) => {
            port.kind = "usb";
            port.vendor_id = Some(format!("{:04x}", usb.vid));
            port.product_id = Some(format!("{:04x}", usb.pid));
            port.manufacturer = usb.manufacturer;
            port.product = usb.product;
            port.serial_number = usb.serial_number;
        }
        SerialPortType::PciPort => port.kind = "pci",
        SerialPortType::BluetoothPort => port.kind = "bluetooth",
        SerialPortType::Unknown => {}
    }
    port
}

/// One line per port (name, kind, then what is known), or [`NONE`].
fn text_lines(ports: &[Port]) -> Vec<String> {
    if ports.is_empty() {
        return vec![NONE.to_owned()];
    }
    let width = ports.iter().map(|p| p.name.len()).max().unwrap_or(0);
    ports
        .iter()
        .map(|p| {
            let mut line = format!("{:width$}  {}", p.name, p.kind);
            if let (Some(vid), Some(pid)) = (&p.vendor_id, &p.product_id) {
                line.push_str(&format!("  {vid}:{pid}"));
            }
            for text in [&p.manufacturer, &p.product].into_iter().flatten() {
                line.push_str(&format!("  {text}"));
            }
            if let Some(serial) = &p.serial_number {
                line.push_str(&format!("  serial {serial}"));
            }
            line
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serialport::UsbPortInfo;

    #[test]
    fn usb_details_are_kept_and_printed() {
        let usb = port(SerialPortInfo {
            port_name: "/dev/ttyUSB0".to_owned(),
            port_type: SerialPortType::UsbPort(UsbPortInfo {
                vid: 0x0403,
                pid: 0x6001,
                serial_number: Some("A50285BI".to_owned()),
                manufacturer: Some("FTDI".to_owned()),
                product: Some("FT232R USB UART".to_owned()),
            }),
        });
        assert_eq!(usb.kind, "usb");
        assert_eq!(usb.vendor_id.as_deref(), Some("0403"));
        assert_eq!(usb.product_id.as_deref(), Some("6001"));
        let com = port(SerialPortInfo {
            port_name: "COM3".to_owned(),
            port_type: SerialPortType::PciPort,
        });
        assert_eq!(
            text_lines(&[usb.clone(), com]),
            [
                "/dev/ttyUSB0  usb  0403:6001  FTDI  FT232R USB UART  serial A50285BI",
                "COM3          pci",
            ]
        );
        let json = serde_json::to_value(&usb).unwrap();
        assert_eq!(json["vendor_id"], "0403");
        assert_eq!(json["serial_number"], "A50285BI");
    }

    #[test]
    fn no_ports_is_one_line() {
        assert_eq!(text_lines(&[]), [NONE]);
    }

    /// Over a made-up `/sys/class/tty`: a ttyS with UART type 0 is a placeholder, one with
    /// a UART (type 4, 16550A) or without the file is a port, other names are never looked up.
    #[test]
    fn placeholder_uarts_are_read_from_sysfs() {
        let root = std::env::temp_dir().join(format!("vfd-sysfs-{}", std::process::id()));
        for (device, uart) in [
            ("ttyS0", Some("4\n")),
            ("ttyS1", Some("0\n")),
            ("ttyS2", None),
        ] {
            std::fs::create_dir_all(root.join(device)).unwrap();
            if let Some(uart) = uart {
                std::fs::write(root.join(device).join("type"), uart).unwrap();
            }
        }
        assert!(!is_placeholder_uart(&root, "/dev/ttyS0"));
        assert!(is_placeholder_uart(&root, "/dev/ttyS1"));
        assert!(!is_placeholder_uart(&root, "/dev/ttyS2"));
        assert!(!is_placeholder_uart(&root, "/dev/ttyUSB0"));
        assert!(!is_placeholder_uart(&root, "COM3"));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
