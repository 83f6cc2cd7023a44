//! The asynchronous pseudo-terminal transport (features `tokio` and `pty`, Unix): a
//! terminal file descriptor in non-blocking mode, waited on with tokio's [`AsyncFd`],
//! behaving as [`crate::transport::PtyTransport`] does.

use std::fs::File;
use std::io::{self, Read, Write};
use std::os::fd::{AsRawFd, OwnedFd};
use std::path::Path;
use std::time::Instant;

use nix::errno::Errno;
use nix::fcntl::{fcntl, FcntlArg, OFlag};
use nix::sys::termios::{tcflush, FlushArg};
use tokio::io::unix::AsyncFd;

use super::AsyncTransport;
use crate::transport::pty::{Side, CLOSED_SLAVE_RETRY};
use crate::transport::{PseudoTerminal, PtyTransport};

/// An [`AsyncTransport`] over a terminal file descriptor: the master side of a
/// [`PseudoTerminal`], or a terminal device opened with [`AsyncPtyTransport::open_path`]
/// (for example the slave path `vfd sim` prints).
///
/// Every constructor must run inside a tokio runtime: the descriptor registers with its
/// reactor (they panic otherwise).
#[derive(Debug)]
pub struct AsyncPtyTransport {
    /// The terminal, in non-blocking mode.
    file: File,
    /// A duplicate of `file` registered with the reactor. Tokio keeps a hang-up as
    /// readiness for good, but a pty master's hang-up ends when a process opens the
    /// slave again: a fresh duplicate, registered anew, then waits for real input.
    fd: AsyncFd<File>,
    side: Side,
    /// The slave side of the pair, held open so a master never sees a closed slave.
    _slave: Option<OwnedFd>,
}

impl AsyncPtyTransport {
    /// Makes a blocking pseudo-terminal transport asynchronous: the same descriptor, put
    /// in non-blocking mode and registered with the runtime's reactor.
    ///
    /// # Panics
    ///
    /// When called outside a tokio runtime.
    pub fn from_blocking(transport: PtyTransport) -> io::Result<AsyncPtyTransport> {
        let (file, side, slave) = transport.into_parts();
        let flags = fcntl(file.as_raw_fd(), FcntlArg::F_GETFL).map_err(io::Error::from)?;
        let flags = OFlag::from_bits_retain(flags) | OFlag::O_NONBLOCK;
        fcntl(file.as_raw_fd(), FcntlArg::F_SETFL(flags)).map_err(io::Error::from)?;
        Ok(AsyncPtyTransport {
            fd: register(&file)?,
            file,
            side,
            _slave: slave,
        })
    }

    /// The master side of `pty`, for talking to another program that opens
    /// [`PseudoTerminal::slave_path`]. Keeps the slave side open too (as
    /// [`PseudoTerminal::master`] does), so the master keeps working while the other
    /// program opens, closes or reopens the slave path.
    ///
    /// # Panics
    ///
    /// When called outside a tokio runtime.
    pub fn master(pty: PseudoTerminal) -> io::Result<AsyncPtyTransport> {
        AsyncPtyTransport::from_blocking(pty.master()?)
    }

    /// Splits `pty` into the asynchronous master side, which the asynchronous master talks
    /// on, and the blocking slave side, on which a thread can serve a virtual drive
    /// (`virtual_drive::serve`). Once the slave side is dropped, receiving on the master
    /// returns `Ok(0)` at each deadline.
    ///
    /// # Panics
    ///
    /// When called outside a tokio runtime.
    pub fn split(pty: PseudoTerminal) -> io::Result<(AsyncPtyTransport, PtyTransport)> {
        let (master, slave) = pty.into_transports()?;
        Ok((AsyncPtyTransport::from_blocking(master)?, slave))
    }

    /// Opens an existing terminal device (for example the `/dev/pts/N` a running
    /// `vfd sim` serves on) as [`PtyTransport::open_path`] does: read and write, not as
    /// the controlling terminal, in raw mode.
    ///
    /// # Panics
    ///
    /// When called outside a tokio runtime.
    pub fn open_path(path: &Path) -> io::Result<AsyncPtyTransport> {
        AsyncPtyTransport::from_blocking(PtyTransport::open_path(path)?)
    }

    /// Registers a fresh duplicate of the terminal, forgetting a hang-up that is over.
    fn reregister(&mut self) -> io::Result<()> {
        self.fd = register(&self.file)?;
        Ok(())
    }

    /// Whether `err` means no process has the slave side open: only on a master, where
    /// the kernel reports `EIO` in that state until some process opens it.
    fn slave_closed(&self, err: &io::Error) -> bool {
        self.side == Side::Master && err.raw_os_error() == Some(Errno::EIO as i32)
    }
}

impl AsyncTransport for AsyncPtyTransport {
    async fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        let mut rest = bytes;
        while !rest.is_empty() {
            let mut ready = self.fd.writable().await?;
            match ready.try_io(|fd| fd.get_ref().write(rest)) {
                Ok(Ok(0)) => {
                    return Err(io::Error::new(
                        io::ErrorKind::WriteZero,
                        "pseudo-terminal accepted no bytes",
                    ))
                }
                Ok(Ok(written)) => rest = &rest[written..],
                Ok(Err(err)) if err.kind() == io::ErrorKind::Interrupted => {}
                Ok(Err(err)) => return Err(err),
                // Not writable after all: the readiness was cleared, wait again.
                Err(_would_block) => {}
            }
        }
        Ok(())
    }

    async fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        if deadline <= Instant::now() {
            // Only what is there now: a timer for a deadline already passed would fire at
            // the runtime's next millisecond tick.
            return match self.fd.get_ref().read(buf) {
                Ok(0) => Err(io::Error::new(
                    io::ErrorKind::BrokenPipe,
                    "pseudo-terminal: the other side was closed",
                )),
                Ok(count) => Ok(count),
                Err(err)
                    if matches!(
                        err.kind(),
                        io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                    ) || err.raw_os_error() == Some(nix::libc::EIO) =>
                {
                    Ok(0)
                }
                Err(err) => Err(err),
            };
        }
        let until = tokio::time::Instant::from_std(deadline);
        loop {
            // Readiness first: with the deadline already passed, bytes waiting are still
            // returned (the timeout polls the wait before its timer).
            let mut ready = match tokio::time::timeout_at(until, self.fd.readable()).await {
                Ok(ready) => ready?,
                Err(_elapsed) => return Ok(0),
            };
            let hung_up = ready.ready().is_read_closed();
            let err = match ready.try_io(|fd| fd.get_ref().read(buf)) {
                Ok(Ok(0)) => {
                    // End of file: the other side of the terminal hung up for good.
                    return Err(io::Error::new(
                        io::ErrorKind::BrokenPipe,
                        "pseudo-terminal: the other side was closed",
                    ));
                }
                Ok(Ok(count)) => return Ok(count),
                Ok(Err(err)) => err,
                // A hang-up that is over (a process opened the slave side again): tokio
                // would report it ready for good, so register anew and wait for input.
                Err(_would_block) if hung_up => {
                    self.reregister()?;
                    continue;
                }
                // Not readable after all: the readiness was cleared, wait again.
                Err(_would_block) => continue,
            };
            drop(ready);
            if err.kind() == io::ErrorKind::Interrupted {
                continue;
            }
            if !self.slave_closed(&err) {
                return Err(err);
            }
            // No process has the slave open: nothing can arrive until one opens it, and
            // the descriptor stays ready (hung up), so look again a little later.
            let remaining = deadline.saturating_duration_since(Instant::now());
            if remaining.is_zero() {
                return Ok(0);
            }
            tokio::time::sleep(remaining.min(CLOSED_SLAVE_RETRY)).await;
        }
    }

    async fn clear_input(&mut self) -> io::Result<()> {
        tcflush(&self.file, FlushArg::TCIFLUSH).map_err(io::Error::from)
    }
}

/// Registers a duplicate of `file` with the current runtime's reactor.
fn register(file: &File) -> io::Result<AsyncFd<File>> {
    let duplicate = file.try_clone()?;
    // SAFETY: the duplicate is owned by the `AsyncFd` from here on and never replaced
    // (nothing calls `get_mut`), so its descriptor stays open and the same until the
    // `AsyncFd` is dropped.
    unsafe { AsyncFd::register(duplicate) }.map_err(io::Error::from)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::Transport;
    use std::thread;
    use std::time::Duration;

    fn soon() -> Instant {
        Instant::now() + Duration::from_secs(5)
    }

    /// Reads exactly `len` bytes, failing the test if the deadline passes first.
    async fn receive_exact(transport: &mut AsyncPtyTransport, len: usize) -> Vec<u8> {
        let deadline = soon();
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        while out.len() < len {
            let n = transport.receive(&mut buf, deadline).await.unwrap();
            assert!(n > 0, "timed out after {} of {len} bytes", out.len());
            out.extend_from_slice(&buf[..n]);
        }
        out
    }

    /// Reads exactly `len` bytes on a blocking transport.
    fn receive_exact_blocking(transport: &mut PtyTransport, len: usize) -> Vec<u8> {
        let deadline = soon();
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        while out.len() < len {
            let n = transport.receive(&mut buf, deadline).unwrap();
            assert!(n > 0, "timed out after {} of {len} bytes", out.len());
            out.extend_from_slice(&buf[..n]);
        }
        out
    }

    /// Asserts that a receive on a silent line returns 0 at its deadline, not before
    /// and not long after.
    async fn assert_silent(transport: &mut AsyncPtyTransport) {
        let mut buf = [0u8; 8];
        let start = Instant::now();
        let deadline = start + Duration::from_millis(50);
        assert_eq!(transport.receive(&mut buf, deadline).await.unwrap(), 0);
        let took = start.elapsed();
        assert!(
            took >= Duration::from_millis(45),
            "returned early: {took:?}"
        );
        assert!(took < Duration::from_secs(2), "returned late: {took:?}");
    }

    #[tokio::test]
    async fn talks_to_a_blocking_transport_on_the_slave_side() {
        let (mut master, mut slave) =
            AsyncPtyTransport::split(PseudoTerminal::open().unwrap()).unwrap();
        let bytes: Vec<u8> = (0u8..=0xFF).collect();
        master.send(&bytes).await.unwrap();
        // The blocking side answers from its own thread, as a served virtual drive would.
        let echo = thread::spawn(move || {
            let got = receive_exact_blocking(&mut slave, 256);
            slave.send(&got).unwrap();
            (slave, got)
        });
        assert_eq!(receive_exact(&mut master, bytes.len()).await, bytes);
        let (_slave, got) = echo.join().unwrap();
        assert_eq!(got, bytes);
    }

    #[tokio::test]
    async fn a_receive_leaves_the_thread_to_other_tasks() {
        let (mut master, mut slave) =
            AsyncPtyTransport::split(PseudoTerminal::open().unwrap()).unwrap();
        let mut buf = [0u8; 8];
        // On a current-thread runtime the sender only runs while the receive waits.
        let sender = async {
            tokio::time::sleep(Duration::from_millis(20)).await;
            slave.send(b"x").unwrap();
        };
        let (received, ()) = tokio::join!(master.receive(&mut buf, soon()), sender);
        assert_eq!(received.unwrap(), 1);
        assert_eq!(buf[0], b'x');
    }

    #[tokio::test]
    async fn a_silent_slave_gives_zero_at_the_deadline() {
        let (mut master, _slave) =
            AsyncPtyTransport::split(PseudoTerminal::open().unwrap()).unwrap();
        assert_silent(&mut master).await;
    }

    #[tokio::test]
    async fn a_closed_slave_is_waited_on_until_the_deadline_and_until_reopened() {
        let pty = PseudoTerminal::open().unwrap();
        let path = pty.slave_path().to_path_buf();
        let (mut master, slave) = AsyncPtyTransport::split(pty).unwrap();
        drop(slave);
        // The kernel reports EIO now: not an error, just nothing before the deadline.
        assert_silent(&mut master).await;
        let mut reopened = PtyTransport::open_path(&path).unwrap();
        let mut buf = [0u8; 8];
        let sender = async {
            tokio::time::sleep(Duration::from_millis(20)).await;
            reopened.send(b"back").unwrap();
        };
        let (received, ()) = tokio::join!(receive_exact(&mut master, 4), sender);
        assert_eq!(received, b"back");
        master.send(b"ok").await.unwrap();
        assert_eq!(reopened.receive(&mut buf, soon()).unwrap(), 2);
    }

    #[tokio::test]
    async fn clear_input_drops_stale_bytes() {
        let (mut master, mut slave) =
            AsyncPtyTransport::split(PseudoTerminal::open().unwrap()).unwrap();
        slave.send(b"stale").unwrap();
        tokio::time::sleep(Duration::from_millis(50)).await;
        master.clear_input().await.unwrap();
        assert_silent(&mut master).await;
        slave.send(b"fresh").unwrap();
        assert_eq!(receive_exact(&mut master, 5).await, b"fresh");
    }

    #[tokio::test]
    async fn opens_a_slave_path_like_a_program_talking_to_vfd_sim() {
        let pty = PseudoTerminal::open().unwrap();
        let path = pty.slave_path().to_path_buf();
        let mut served = pty.master().unwrap();
        let mut client = AsyncPtyTransport::open_path(&path).unwrap();
        client.send(b"request").await.unwrap();
        let answer = thread::spawn(move || {
            let got = receive_exact_blocking(&mut served, 7);
            served.send(b"reply").unwrap();
            (served, got)
        });
        assert_eq!(receive_exact(&mut client, 5).await, b"reply");
        let (_served, got) = answer.join().unwrap();
        assert_eq!(got, b"request");
        assert_silent(&mut client).await;
    }

    #[tokio::test]
    async fn the_master_keeps_the_slave_open_for_another_program() {
        let pty = PseudoTerminal::open().unwrap();
        let path = pty.slave_path().to_path_buf();
        let mut master = AsyncPtyTransport::master(pty).unwrap();
        assert_silent(&mut master).await;
        let mut program = PtyTransport::open_path(&path).unwrap();
        program.send(b"hi").unwrap();
        assert_eq!(receive_exact(&mut master, 2).await, b"hi");
        master.send(b"ok").await.unwrap();
        assert_eq!(receive_exact_blocking(&mut program, 2), b"ok");
    }

    #[test]
    fn the_transport_and_its_futures_are_send() {
        fn assert_send<T: Send>(_: &T) {}
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_io()
            .build()
            .unwrap();
        let _entered = runtime.enter();
        let (mut master, _slave) =
            AsyncPtyTransport::split(PseudoTerminal::open().unwrap()).unwrap();
        let mut buf = [0u8; 4];
        assert_send(&master.receive(&mut buf, Instant::now()));
        assert_send(&master);
    }
}
