//! The asynchronous serial-port transport (features `tokio` and `serial`), over
//! `tokio_serial::SerialStream`: the same port settings and errors as
//! [`crate::transport::SerialTransport`], waiting on tokio's reactor.

use std::fmt;
use std::future::poll_fn;
use std::io;
use std::pin::Pin;
use std::time::Instant;

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio_serial::{ClearBuffer, SerialPort, SerialStream};

use super::AsyncTransport;
use crate::serial::SerialSettings;
use crate::transport::serial_port::{port_builder, port_error, send_timeout};

/// An [`AsyncTransport`] over a serial port.
///
/// `receive` waits at most until its deadline without blocking the executor's thread;
/// `send` fails with [`io::ErrorKind::TimedOut`] if the operating system does not accept
/// the bytes within about twice their transmission time plus one second.
pub struct AsyncSerialTransport {
    port: SerialStream,
    /// Port name used in error messages.
    path: String,
    /// Baud rate used to size the `send` timeout; 0 when unknown.
    baud: u32,
}

impl fmt::Debug for AsyncSerialTransport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("AsyncSerialTransport")
            .field("path", &self.path)
            .field("baud", &self.baud)
            .finish_non_exhaustive()
    }
}

impl AsyncSerialTransport {
    /// Opens the serial port at `path` (e.g. `/dev/ttyUSB0`) with the given line settings
    /// and no flow control, as [`crate::transport::SerialTransport::open`] does.
    ///
    /// Fails with [`io::ErrorKind::InvalidInput`] when the settings are not supported
    /// (data bits other than 7 or 8, stop bits other than 1 or 2, a zero baud rate).
    ///
    /// # Panics
    ///
    /// When called outside a tokio runtime (the port registers with its reactor).
    pub fn open(path: &str, settings: &SerialSettings) -> io::Result<AsyncSerialTransport> {
        let builder = port_builder(path, settings)?;
        let port =
            SerialStream::open(&builder).map_err(|err| port_error(path, "cannot open", err))?;
        Ok(AsyncSerialTransport {
            port,
            path: path.to_string(),
            baud: settings.baud,
        })
    }

    /// Wraps an already opened and configured port.
    pub fn from_stream(port: SerialStream) -> AsyncSerialTransport {
        let path = port
            .name()
            .unwrap_or_else(|| "<unnamed serial port>".to_string());
        let baud = port.baud_rate().unwrap_or(0);
        AsyncSerialTransport { port, path, baud }
    }

    /// Adds the port path and the failed action to an I/O error.
    fn io_error(&self, action: &str, err: io::Error) -> io::Error {
        io::Error::new(
            err.kind(),
            format!("serial port {}: {action}: {err}", self.path),
        )
    }

    /// Writes all of `bytes`, waiting for the port to accept more as needed.
    async fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        let mut rest = bytes;
        while !rest.is_empty() {
            let written = poll_fn(|cx| Pin::new(&mut self.port).poll_write(cx, rest)).await?;
            if written == 0 {
                return Err(io::Error::new(
                    io::ErrorKind::WriteZero,
                    "the port accepted no bytes",
                ));
            }
            rest = &rest[written..];
        }
        Ok(())
    }
}

impl AsyncTransport for AsyncSerialTransport {
    async fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if bytes.is_empty() {
            return Ok(());
        }
        let timeout = send_timeout(self.baud, bytes.len());
        match tokio::time::timeout(timeout, self.write_all(bytes)).await {
            Ok(Ok(())) => Ok(()),
            Ok(Err(err)) => Err(self.io_error("write", err)),
            Err(_elapsed) => Err(self.io_error(
                "write",
                io::Error::new(
                    io::ErrorKind::TimedOut,
                    format!("the port did not accept the bytes within {timeout:?}"),
                ),
            )),
        }
    }

    async fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        let port = &mut self.port;
        let read = poll_fn(|cx| {
            let mut read_buf = ReadBuf::new(buf);
            Pin::new(&mut *port)
                .poll_read(cx, &mut read_buf)
                .map_ok(|()| read_buf.filled().len())
        });
        // A read is cancel-safe: when the deadline wins, no byte was taken.
        match tokio::time::timeout_at(tokio::time::Instant::from_std(deadline), read).await {
            Ok(Ok(count)) => Ok(count),
            Ok(Err(err)) => Err(self.io_error("read", err)),
            Err(_elapsed) => Ok(0),
        }
    }

    async fn clear_input(&mut self) -> io::Result<()> {
        self.port
            .clear(ClearBuffer::Input)
            .map_err(|err| port_error(&self.path, "cannot clear the input buffer", err))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::serial::Parity;
    use std::time::Duration;

    fn settings(data_bits: u8, parity: Parity, stop_bits: u8) -> SerialSettings {
        SerialSettings {
            baud: 9600,
            data_bits,
            parity,
            stop_bits,
        }
    }

    #[tokio::test]
    async fn rejects_unsupported_settings_naming_them() {
        let err =
            AsyncSerialTransport::open("/dev/null", &settings(5, Parity::None, 1)).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert!(err.to_string().contains("data bits 5"), "{err}");
        let path = "/dev/definitely-not-a-serial-port";
        let err = AsyncSerialTransport::open(path, &settings(8, Parity::None, 1)).unwrap_err();
        assert!(err.to_string().contains(path), "{err}");
    }

    #[cfg(all(unix, feature = "pty"))]
    mod over_a_pseudo_terminal {
        use super::*;
        use crate::transport::{PseudoTerminal, PtyTransport, Transport};
        use std::thread;

        /// Reads exactly `len` bytes, failing the test if the deadline passes first.
        async fn receive_exact(transport: &mut AsyncSerialTransport, len: usize) -> Vec<u8> {
            let deadline = Instant::now() + Duration::from_secs(5);
            let mut out = Vec::new();
            let mut buf = [0u8; 64];
            while out.len() < len {
                let n = transport.receive(&mut buf, deadline).await.unwrap();
                assert!(n > 0, "timed out after {} of {len} bytes", out.len());
                out.extend_from_slice(&buf[..n]);
            }
            out
        }

        /// A serial port on the slave side of a fresh pseudo-terminal, and the blocking
        /// master side.
        fn port_and_master() -> (AsyncSerialTransport, PtyTransport) {
            let pty = PseudoTerminal::open().unwrap();
            let path = pty.slave_path().to_str().unwrap().to_string();
            let master = pty.master().unwrap();
            let port = AsyncSerialTransport::open(&path, &settings(8, Parity::Odd, 2)).unwrap();
            (port, master)
        }

        #[tokio::test]
        async fn round_trips_every_byte_value() {
            let (mut port, mut master) = port_and_master();
            let bytes: Vec<u8> = (0u8..=0xFF).collect();
            port.send(&bytes).await.unwrap();
            let echo = thread::spawn(move || {
                let deadline = Instant::now() + Duration::from_secs(5);
                let mut got = Vec::new();
                let mut buf = [0u8; 64];
                while got.len() < 256 {
                    let n = master.receive(&mut buf, deadline).unwrap();
                    assert!(n > 0, "the master timed out after {} bytes", got.len());
                    got.extend_from_slice(&buf[..n]);
                }
                master.send(&got).unwrap();
                (master, got)
            });
            assert_eq!(receive_exact(&mut port, bytes.len()).await, bytes);
            let (_master, got) = echo.join().unwrap();
            assert_eq!(got, bytes);
        }

        #[tokio::test]
        async fn a_receive_leaves_the_thread_to_other_tasks() {
            let (mut port, mut master) = port_and_master();
            let mut buf = [0u8; 8];
            let deadline = Instant::now() + Duration::from_secs(5);
            // On a current-thread runtime the sender only runs while the receive waits.
            let sender = async {
                tokio::time::sleep(Duration::from_millis(20)).await;
                master.send(b"x").unwrap();
            };
            let (received, ()) = tokio::join!(port.receive(&mut buf, deadline), sender);
            assert_eq!(received.unwrap(), 1);
            assert_eq!(buf[0], b'x');
        }

        #[tokio::test]
        async fn a_silent_peer_gives_zero_at_the_deadline() {
            let (mut port, _master) = port_and_master();
            let mut buf = [0u8; 8];
            let start = Instant::now();
            let deadline = start + Duration::from_millis(50);
            assert_eq!(port.receive(&mut buf, deadline).await.unwrap(), 0);
            let took = start.elapsed();
            assert!(
                took >= Duration::from_millis(45),
                "returned early: {took:?}"
            );
            assert!(took < Duration::from_secs(2), "returned late: {took:?}");
        }

        #[tokio::test]
        async fn clear_input_drops_stale_bytes() {
            let (mut port, mut master) = port_and_master();
            master.send(b"stale").unwrap();
            // Let the bytes reach the port's input buffer.
            tokio::time::sleep(Duration::from_millis(50)).await;
            port.clear_input().await.unwrap();
            let mut buf = [0u8; 8];
            let deadline = Instant::now() + Duration::from_millis(50);
            assert_eq!(port.receive(&mut buf, deadline).await.unwrap(), 0);
            master.send(b"fresh").unwrap();
            assert_eq!(receive_exact(&mut port, 5).await, b"fresh");
        }
    }
}
