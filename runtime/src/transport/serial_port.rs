//! Real serial-port transport (RS-485 / RS-232 adapters) built on the `serialport` crate.

use std::fmt;
use std::io::{self, Read, Write};
use std::time::{Duration, Instant};

use serialport::{ClearBuffer, DataBits, FlowControl, Parity as PortParity, SerialPort, StopBits};

use super::Transport;
use crate::serial::{Parity, SerialSettings};

/// Timeout used while opening the port, before the first `send` or `receive` sets its own.
const OPEN_TIMEOUT: Duration = Duration::from_millis(100);

/// Fixed allowance on top of the transmission time for a `send` to be accepted.
const SEND_SLACK: Duration = Duration::from_secs(1);

/// Bits on the wire per byte in the worst supported frame: start, 8 data, parity, 2 stop.
const MAX_BITS_PER_BYTE: u64 = 12;

/// A [`Transport`] over a serial port.
///
/// `receive` waits at most until its deadline; `send` hands the bytes to the operating
/// system and fails if they are not accepted within about twice their transmission time
/// plus one second.
pub struct SerialTransport {
    port: Box<dyn SerialPort>,
    /// Port name used in error messages.
    path: String,
    /// Baud rate used to size the `send` timeout; 0 when unknown.
    baud: u32,
}

impl fmt::Debug for SerialTransport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SerialTransport")
            .field("path", &self.path)
            .field("baud", &self.baud)
            .finish_non_exhaustive()
    }
}

impl SerialTransport {
    /// Opens the serial port at `path` (e.g. `/dev/ttyUSB0`) with the given line
    /// settings and no flow control.
    ///
    /// Fails with [`io::ErrorKind::InvalidInput`] when the settings are not supported
    /// (data bits other than 7 or 8, stop bits other than 1 or 2, a zero baud rate).
    pub fn open(path: &str, settings: &SerialSettings) -> io::Result<SerialTransport> {
        let port = port_builder(path, settings)?
            .timeout(OPEN_TIMEOUT)
            .open()
            .map_err(|err| port_error(path, "cannot open", err))?;
        Ok(SerialTransport {
            port,
            path: path.to_string(),
            baud: settings.baud,
        })
    }

    /// Wraps an already opened and configured port.
    pub fn from_port(port: Box<dyn SerialPort>) -> SerialTransport {
        let path = port
            .name()
            .unwrap_or_else(|| "<unnamed serial port>".to_string());
        let baud = port.baud_rate().unwrap_or(0);
        SerialTransport { port, path, baud }
    }

    /// Adds the port path and the failed action to an I/O error.
    fn io_error(&self, action: &str, err: io::Error) -> io::Error {
        io::Error::new(
            err.kind(),
            format!("serial port {}: {action}: {err}", self.path),
        )
    }
}

impl Transport for SerialTransport {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if bytes.is_empty() {
            return Ok(());
        }
        let timeout = send_timeout(self.baud, bytes.len());
        self.port
            .set_timeout(timeout)
            .map_err(|err| port_error(&self.path, "cannot set the write timeout", err))?;
        let mut rest = bytes;
        while !rest.is_empty() {
            match self.port.write(rest) {
                Ok(0) => {
                    return Err(self.io_error(
                        "write",
                        io::Error::new(io::ErrorKind::WriteZero, "the port accepted no bytes"),
                    ))
                }
                Ok(written) => rest = &rest[written..],
                Err(err)
                    if matches!(
                        err.kind(),
                        io::ErrorKind::Interrupted | io::ErrorKind::WouldBlock
                    ) => {}
                Err(err) => return Err(self.io_error("write", err)),
            }
        }
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        loop {
            let remaining = deadline.saturating_duration_since(Instant::now());
            self.port
                .set_timeout(remaining)
                .map_err(|err| port_error(&self.path, "cannot set the read timeout", err))?;
            match self.port.read(buf) {
                Ok(count) => return Ok(count),
                Err(err) if err.kind() == io::ErrorKind::TimedOut => return Ok(0),
                Err(err)
                    if matches!(
                        err.kind(),
                        io::ErrorKind::Interrupted | io::ErrorKind::WouldBlock
                    ) =>
                {
                    if remaining.is_zero() {
                        return Ok(0);
                    }
                }
                Err(err) => return Err(self.io_error("read", err)),
            }
        }
    }

    fn clear_input(&mut self) -> io::Result<()> {
        self.port
            .clear(ClearBuffer::Input)
            .map_err(|err| port_error(&self.path, "cannot clear the input buffer", err))
    }
}

/// The builder for the port at `path` with the given line settings and no flow control,
/// shared by [`SerialTransport`] and the asynchronous serial transport (feature `tokio`).
///
/// Fails with [`io::ErrorKind::InvalidInput`] when the settings are not supported.
pub(crate) fn port_builder(
    path: &str,
    settings: &SerialSettings,
) -> io::Result<serialport::SerialPortBuilder> {
    if settings.baud == 0 {
        return Err(invalid_setting(
            path,
            "baud rate 0 is not supported".to_string(),
        ));
    }
    let data_bits = match settings.data_bits {
        7 => DataBits::Seven,
        8 => DataBits::Eight,
        other => {
            return Err(invalid_setting(
                path,
                format!("unsupported data bits {other} (expected 7 or 8)"),
            ))
        }
    };
    let stop_bits = match settings.stop_bits {
        1 => StopBits::One,
        2 => StopBits::Two,
        other => {
            return Err(invalid_setting(
                path,
                format!("unsupported stop bits {other} (expected 1 or 2)"),
            ))
        }
    };
    let parity = match settings.parity {
        Parity::None => PortParity::None,
        Parity::Even => PortParity::Even,
        Parity::Odd => PortParity::Odd,
    };
    Ok(serialport::new(path, settings.baud)
        .data_bits(data_bits)
        .parity(parity)
        .stop_bits(stop_bits)
        .flow_control(FlowControl::None))
}

/// Time allowed for the operating system to accept `len` bytes at `baud` (0: unknown):
/// about twice their transmission time plus one second.
pub(crate) fn send_timeout(baud: u32, len: usize) -> Duration {
    if baud == 0 {
        return SEND_SLACK + Duration::from_millis(u64::try_from(len).unwrap_or(u64::MAX));
    }
    let bits = u64::try_from(len)
        .unwrap_or(u64::MAX)
        .saturating_mul(MAX_BITS_PER_BYTE);
    let micros = bits.saturating_mul(2_000_000) / u64::from(baud);
    SEND_SLACK.saturating_add(Duration::from_micros(micros))
}

/// Converts a `serialport` error to an I/O error naming the port and the failed action.
pub(crate) fn port_error(path: &str, action: &str, err: serialport::Error) -> io::Error {
    let description = err.description.clone();
    let kind = io::Error::from(err).kind();
    io::Error::new(kind, format!("serial port {path}: {action}: {description}"))
}

/// An [`io::ErrorKind::InvalidInput`] error for an unsupported line setting.
fn invalid_setting(path: &str, message: String) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("serial port {path}: {message}"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(data_bits: u8, parity: Parity, stop_bits: u8) -> SerialSettings {
        SerialSettings {
            baud: 9600,
            data_bits,
            parity,
            stop_bits,
        }
    }

    #[cfg(all(unix, feature = "pty"))]
    fn receive_exact(transport: &mut dyn Transport, len: usize) -> Vec<u8> {
        let deadline = Instant::now() + Duration::from_secs(5);
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        while out.len() < len {
            let n = transport.receive(&mut buf, deadline).unwrap();
            assert!(n > 0, "timed out after {} of {len} bytes", out.len());
            out.extend_from_slice(&buf[..n]);
        }
        out
    }

    #[test]
    fn rejects_unsupported_data_bits() {
        let err = SerialTransport::open("/dev/null", &settings(5, Parity::None, 1)).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert!(err.to_string().contains("data bits 5"), "{err}");
    }

    #[test]
    fn rejects_unsupported_stop_bits() {
        let err = SerialTransport::open("/dev/null", &settings(8, Parity::Even, 3)).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert!(err.to_string().contains("stop bits 3"), "{err}");
    }

    #[test]
    fn missing_port_error_names_the_path() {
        let path = "/dev/definitely-not-a-serial-port";
        let err = SerialTransport::open(path, &settings(8, Parity::None, 1)).unwrap_err();
        assert!(err.to_string().contains(path), "{err}");
    }

    #[test]
    #[cfg(all(unix, feature = "pty"))]
    fn talks_over_a_pseudo_terminal() {
        let pty = crate::transport::PseudoTerminal::open().unwrap();
        let path = pty.slave_path().to_str().unwrap().to_string();
        let mut master = pty.master().unwrap();
        let mut port = SerialTransport::open(&path, &settings(8, Parity::Odd, 2)).unwrap();

        let bytes: Vec<u8> = (0u8..=0xFF).collect();
        master.send(&bytes).unwrap();
        assert_eq!(receive_exact(&mut port, bytes.len()), bytes);
        port.send(&bytes).unwrap();
        assert_eq!(receive_exact(&mut master, bytes.len()), bytes);

        let mut buf = [0u8; 8];
        let deadline = Instant::now() + Duration::from_millis(20);
        assert_eq!(port.receive(&mut buf, deadline).unwrap(), 0);
        port.clear_input().unwrap();
    }
}
