//! The asynchronous raw serial-over-TCP transport: the blocking [`crate::transport::TcpTransport`]'s
//! behaviour (the serial line's frames unchanged, a network allowance on every reply, a
//! dropped connection a typed error and the next send a new connection) over tokio's
//! `TcpStream`.

use super::AsyncTransport;
use crate::transport::tcp::{connect_error, resolve, CONNECT_TIMEOUT, NETWORK_ALLOWANCE};
use std::io;
use std::net::SocketAddr;
use std::time::{Duration, Instant};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

/// An [`AsyncTransport`] over a TCP connection to a serial device server.
#[derive(Debug)]
pub struct AsyncTcpTransport {
    /// `tcp://HOST:PORT`, for messages.
    name: String,
    addrs: Vec<SocketAddr>,
    stream: Option<TcpStream>,
    connect_timeout: Duration,
    allowance: Duration,
}

impl AsyncTcpTransport {
    /// Connects to the device server at `addr` (`HOST:PORT` or `tcp://HOST:PORT`), waiting
    /// at most [`CONNECT_TIMEOUT`] (see [`crate::transport::TcpTransport::connect`]).
    pub async fn connect(addr: &str) -> io::Result<AsyncTcpTransport> {
        let (name, addrs) = resolve(addr)?;
        let mut transport = AsyncTcpTransport {
            name,
            addrs,
            stream: None,
            connect_timeout: CONNECT_TIMEOUT,
            allowance: NETWORK_ALLOWANCE,
        };
        transport.reconnect().await?;
        Ok(transport)
    }

    /// The same transport adding `allowance` to every reply timeout instead of
    /// [`NETWORK_ALLOWANCE`].
    #[must_use]
    pub fn with_allowance(mut self, allowance: Duration) -> AsyncTcpTransport {
        self.allowance = allowance;
        self
    }

    /// `tcp://HOST:PORT` of the device server.
    pub fn name(&self) -> &str {
        &self.name
    }

    async fn reconnect(&mut self) -> io::Result<()> {
        self.stream = None;
        let mut last = None;
        for addr in &self.addrs {
            match tokio::time::timeout(self.connect_timeout, TcpStream::connect(addr)).await {
                Ok(Ok(stream)) => {
                    stream.set_nodelay(true)?;
                    self.stream = Some(stream);
                    return Ok(());
                }
                Ok(Err(err)) => last = Some(err),
                Err(_) => last = Some(io::Error::from(io::ErrorKind::TimedOut)),
            }
        }
        let err = last.unwrap_or_else(|| io::Error::from(io::ErrorKind::NotConnected));
        Err(connect_error(&self.name, err, self.connect_timeout))
    }

    fn lost(&mut self, err: io::Error) -> io::Error {
        self.stream = None;
        io::Error::new(
            err.kind(),
            format!("{}: the connection was lost: {err}", self.name),
        )
    }

    fn closed(&mut self) -> io::Error {
        self.stream = None;
        io::Error::new(
            io::ErrorKind::ConnectionAborted,
            format!(
                "{}: the connection was closed by the device server",
                self.name
            ),
        )
    }

    fn not_connected(&self) -> io::Error {
        io::Error::new(
            io::ErrorKind::NotConnected,
            format!(
                "{}: not connected (the connection was closed; the next send reconnects)",
                self.name
            ),
        )
    }
}

impl AsyncTransport for AsyncTcpTransport {
    async fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.stream.is_none() {
            self.reconnect().await?;
        }
        let Some(stream) = self.stream.as_mut() else {
            return Err(self.not_connected());
        };
        match stream.write_all(bytes).await {
            Ok(()) => Ok(()),
            Err(err) => Err(self.lost(err)),
        }
    }

    async fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        let Some(stream) = self.stream.as_mut() else {
            return Err(self.not_connected());
        };
        // With the deadline passed, only what is there now (a timer for a past deadline
        // fires at the runtime's next millisecond tick).
        let read = if deadline <= Instant::now() {
            Err(())
        } else {
            tokio::time::timeout_at(deadline.into(), stream.read(buf))
                .await
                .map_err(|_| ())
        };
        match read {
            // The deadline passed: what is there now, without waiting.
            Err(_) => match stream.try_read(buf) {
                Ok(0) => Err(self.closed()),
                Ok(count) => Ok(count),
                Err(err) if err.kind() == io::ErrorKind::WouldBlock => Ok(0),
                Err(err) => Err(self.lost(err)),
            },
            Ok(Ok(0)) => Err(self.closed()),
            Ok(Ok(count)) => Ok(count),
            Ok(Err(err)) => Err(self.lost(err)),
        }
    }

    async fn clear_input(&mut self) -> io::Result<()> {
        let mut scratch = [0u8; 512];
        while let Some(stream) = self.stream.as_mut() {
            match stream.try_read(&mut scratch) {
                // Closed while idle: the next send reconnects.
                Ok(0) => self.stream = None,
                Ok(_) => {}
                Err(err) if err.kind() == io::ErrorKind::WouldBlock => return Ok(()),
                Err(err) if err.kind() == io::ErrorKind::Interrupted => {}
                Err(_) => self.stream = None,
            }
        }
        Ok(())
    }

    fn allowance(&self) -> Duration {
        self.allowance
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};
    use std::net::TcpListener;

    #[tokio::test]
    async fn a_round_trip_then_a_dropped_connection_then_a_new_one() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = format!("tcp://{}", listener.local_addr().unwrap());
        let server = std::thread::spawn(move || {
            for _ in 0..2 {
                let (mut stream, _) = listener.accept().unwrap();
                let mut buf = [0u8; 4];
                stream.read_exact(&mut buf).unwrap();
                stream.write_all(&buf).unwrap();
                // Then the device server drops the client.
            }
        });
        let mut transport = AsyncTcpTransport::connect(&addr).await.unwrap();
        assert_eq!(transport.allowance(), NETWORK_ALLOWANCE);
        let soon = || Instant::now() + Duration::from_secs(5);
        let mut buf = [0u8; 16];
        transport.send(&[1, 2, 3, 4]).await.unwrap();
        let mut got = 0;
        while got < 4 {
            got += transport.receive(&mut buf[got..], soon()).await.unwrap();
        }
        assert_eq!(&buf[..4], &[1, 2, 3, 4]);
        let error = transport.receive(&mut buf, soon()).await.unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::ConnectionAborted, "{error}");
        assert!(error.to_string().contains(&addr), "{error}");
        // The next send reconnects.
        transport.send(&[5, 6, 7, 8]).await.unwrap();
        let mut got = 0;
        while got < 4 {
            got += transport.receive(&mut buf[got..], soon()).await.unwrap();
        }
        assert_eq!(&buf[..4], &[5, 6, 7, 8]);
        server.join().unwrap();
    }

    #[tokio::test]
    async fn a_silent_server_ends_the_wait_at_the_deadline() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        let mut transport = AsyncTcpTransport::connect(&addr).await.unwrap();
        let (_held, _) = listener.accept().unwrap();
        let started = Instant::now();
        let mut buf = [0u8; 16];
        let got = transport
            .receive(&mut buf, started + Duration::from_millis(50))
            .await
            .unwrap();
        assert_eq!(got, 0);
        let waited = started.elapsed();
        assert!(
            waited >= Duration::from_millis(45) && waited < Duration::from_secs(2),
            "{waited:?}"
        );
    }

    #[tokio::test]
    async fn nothing_listening_is_a_refusal_naming_the_address() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap().to_string();
        drop(listener);
        let error = AsyncTcpTransport::connect(&addr).await.unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::ConnectionRefused);
        assert!(error.to_string().contains(&addr), "{error}");
    }
}
