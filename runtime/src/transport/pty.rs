//! Pseudo-terminal transports: a raw-mode pty pair whose slave side looks like a serial
//! port to other programs, used to test drive code and simulators without hardware.

use std::fs::{File, OpenOptions};
use std::io::{self, Read, Write};
use std::os::fd::{AsFd, OwnedFd};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::thread;
use std::time::{Duration, Instant};

use nix::errno::Errno;
use nix::fcntl::OFlag;
use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
use nix::pty::{openpty, OpenptyResult};
use nix::sys::termios::{cfmakeraw, tcflush, tcgetattr, tcsetattr, FlushArg, SetArg};
use nix::unistd::ttyname;

use super::Transport;

/// How long a master waits before looking again when its slave side is closed (the
/// kernel reports `EIO` immediately in that state, so polling would not block).
pub(crate) const CLOSED_SLAVE_RETRY: Duration = Duration::from_millis(10);

/// An open pseudo-terminal pair, both sides in raw mode (no echo, no line editing, no
/// character translation, no software flow control).
///
/// Other processes can open [`PseudoTerminal::slave_path`] as if it were a serial port.
#[derive(Debug)]
pub struct PseudoTerminal {
    master: OwnedFd,
    slave: OwnedFd,
    slave_path: PathBuf,
}

impl PseudoTerminal {
    /// Opens a new pseudo-terminal pair and puts both sides in raw mode.
    pub fn open() -> io::Result<PseudoTerminal> {
        let OpenptyResult { master, slave } = openpty(None, None).map_err(|errno| {
            io::Error::new(
                io::Error::from(errno).kind(),
                format!("cannot open a pseudo-terminal: {errno}"),
            )
        })?;
        make_raw(&master)?;
        make_raw(&slave)?;
        let slave_path = ttyname(&slave).map_err(|errno| {
            io::Error::new(
                io::Error::from(errno).kind(),
                format!("cannot get the pseudo-terminal slave path: {errno}"),
            )
        })?;
        Ok(PseudoTerminal {
            master,
            slave,
            slave_path,
        })
    }

    /// Path of the slave side, e.g. `/dev/pts/3`, which other programs can open like a
    /// serial port (see also [`PtyTransport::open_path`]).
    pub fn slave_path(&self) -> &Path {
        &self.slave_path
    }

    /// Splits the pair into `(master, slave)` transports: bytes sent on one are received
    /// on the other.
    pub fn into_transports(self) -> io::Result<(PtyTransport, PtyTransport)> {
        let master = PtyTransport::new(self.master, Side::Master, None);
        let slave = PtyTransport::new(self.slave, Side::Other, None);
        Ok((master, slave))
    }

    /// Returns the master side as a transport, for talking to another program that
    /// opens [`PseudoTerminal::slave_path`].
    ///
    /// The returned transport keeps the slave side open too, so the master keeps
    /// working while the other program opens, closes or reopens the slave path.
    pub fn master(self) -> io::Result<PtyTransport> {
        Ok(PtyTransport::new(
            self.master,
            Side::Master,
            Some(self.slave),
        ))
    }
}

/// Which end of a pseudo-terminal a transport reads from; decides what `EIO` means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    /// A pty master: `EIO` means no process has the slave open right now.
    Master,
    /// A slave side or any other terminal device: `EIO` is a real error.
    Other,
}

/// A [`Transport`] over a terminal file descriptor: either side of a
/// [`PseudoTerminal`], or a terminal device opened with [`PtyTransport::open_path`].
#[derive(Debug)]
pub struct PtyTransport {
    file: File,
    side: Side,
    /// The slave side of the pair, held open so a master never sees a closed slave.
    _slave: Option<OwnedFd>,
}

impl PtyTransport {
    fn new(fd: OwnedFd, side: Side, slave: Option<OwnedFd>) -> PtyTransport {
        PtyTransport {
            file: File::from(fd),
            side,
            _slave: slave,
        }
    }

    /// A second handle on the same terminal (for a thread reading while another writes).
    /// The clone does not keep the slave side open; the original does.
    pub fn try_clone(&self) -> io::Result<PtyTransport> {
        Ok(PtyTransport {
            file: self.file.try_clone()?,
            side: self.side,
            _slave: None,
        })
    }

    /// Opens an existing terminal device (for example a [`PseudoTerminal::slave_path`])
    /// for reading and writing without making it the controlling terminal, and puts it
    /// in raw mode.
    pub fn open_path(path: &Path) -> io::Result<PtyTransport> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(OFlag::O_NOCTTY.bits())
            .open(path)
            .map_err(|err| {
                io::Error::new(err.kind(), format!("cannot open {}: {err}", path.display()))
            })?;
        make_raw(&file)
            .map_err(|err| io::Error::new(err.kind(), format!("{}: {err}", path.display())))?;
        Ok(PtyTransport {
            file,
            side: Side::Other,
            _slave: None,
        })
    }

    /// Takes the transport apart (the terminal, which end it is, the slave side it keeps
    /// open), for the asynchronous pseudo-terminal transport (feature `tokio`).
    #[cfg(feature = "tokio")]
    pub(crate) fn into_parts(self) -> (File, Side, Option<OwnedFd>) {
        (self.file, self.side, self._slave)
    }

    /// Waits until the descriptor is readable or `remaining` passes; returns whether it
    /// became ready (readable, hung up or in error, which the following read reports).
    fn wait_readable(&self, remaining: Duration) -> io::Result<bool> {
        let mut fds = [PollFd::new(self.file.as_fd(), PollFlags::POLLIN)];
        match wait(&mut fds, remaining) {
            Ok(0) => Ok(false),
            Ok(_) => {
                let revents = fds[0].revents().unwrap_or_else(PollFlags::empty);
                if revents.contains(PollFlags::POLLNVAL) {
                    return Err(io::Error::from(Errno::EBADF));
                }
                Ok(true)
            }
            Err(Errno::EINTR) => Ok(false),
            Err(errno) => Err(errno.into()),
        }
    }

    /// Blocks until the descriptor accepts more output.
    fn wait_writable(&self) -> io::Result<()> {
        loop {
            let mut fds = [PollFd::new(self.file.as_fd(), PollFlags::POLLOUT)];
            match poll(&mut fds, PollTimeout::NONE) {
                Ok(_) => return Ok(()),
                Err(Errno::EINTR) => continue,
                Err(errno) => return Err(errno.into()),
            }
        }
    }
}

impl Transport for PtyTransport {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        let mut rest = bytes;
        while !rest.is_empty() {
            match self.file.write(rest) {
                Ok(0) => {
                    return Err(io::Error::new(
                        io::ErrorKind::WriteZero,
                        "pseudo-terminal accepted no bytes",
                    ))
                }
                Ok(written) => rest = &rest[written..],
                Err(err) if err.kind() == io::ErrorKind::Interrupted => {}
                Err(err) if err.kind() == io::ErrorKind::WouldBlock => self.wait_writable()?,
                Err(err) => return Err(err),
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
            if !self.wait_readable(remaining)? {
                if remaining.is_zero() {
                    return Ok(0);
                }
                // Interrupted, or woke up at (or a hair before) the deadline: look again.
                continue;
            }
            match self.file.read(buf) {
                Ok(0) => {
                    // End of file: the other side of the terminal hung up for good.
                    return Err(io::Error::new(
                        io::ErrorKind::BrokenPipe,
                        "pseudo-terminal: the other side was closed",
                    ));
                }
                Ok(count) => return Ok(count),
                Err(err)
                    if matches!(
                        err.kind(),
                        io::ErrorKind::Interrupted | io::ErrorKind::WouldBlock
                    ) => {}
                Err(err)
                    if self.side == Side::Master
                        && err.raw_os_error() == Some(Errno::EIO as i32) =>
                {
                    // No process has the slave open: nothing can arrive until one opens it.
                    let remaining = deadline.saturating_duration_since(Instant::now());
                    if remaining.is_zero() {
                        return Ok(0);
                    }
                    thread::sleep(remaining.min(CLOSED_SLAVE_RETRY));
                }
                Err(err) => return Err(err),
            }
        }
    }

    fn clear_input(&mut self) -> io::Result<()> {
        tcflush(&self.file, FlushArg::TCIFLUSH).map_err(io::Error::from)
    }
}

/// Puts a terminal in raw mode: bytes pass through unchanged, nothing is echoed.
fn make_raw<Fd: AsFd>(fd: Fd) -> io::Result<()> {
    let fd = fd.as_fd();
    let mut termios = tcgetattr(fd).map_err(|errno| {
        io::Error::new(
            io::Error::from(errno).kind(),
            format!("cannot read terminal settings: {errno}"),
        )
    })?;
    cfmakeraw(&mut termios);
    tcsetattr(fd, SetArg::TCSANOW, &termios).map_err(|errno| {
        io::Error::new(
            io::Error::from(errno).kind(),
            format!("cannot set raw mode: {errno}"),
        )
    })
}

/// Waits for `fds` at most `remaining`. On Linux `ppoll` takes the time to the nanosecond,
/// so a wait for a few character times at 115200 baud (under 0.1 ms each) is not rounded
/// up to a whole millisecond; elsewhere `poll` rounds up ([`poll_timeout`]).
#[cfg(any(target_os = "linux", target_os = "android"))]
fn wait(fds: &mut [PollFd], remaining: Duration) -> nix::Result<nix::libc::c_int> {
    let timeout = nix::sys::time::TimeSpec::from_duration(remaining);
    nix::poll::ppoll(fds, Some(timeout), None)
}

/// Waits for `fds` at most `remaining`, rounded up to whole milliseconds ([`poll_timeout`]).
#[cfg(not(any(target_os = "linux", target_os = "android")))]
fn wait(fds: &mut [PollFd], remaining: Duration) -> nix::Result<nix::libc::c_int> {
    poll(fds, poll_timeout(remaining))
}

/// Converts the time left until a deadline to a `poll` timeout, rounding up to whole
/// milliseconds (so a wake-up is never early) and clamping to what `poll` accepts; the
/// caller loops when a clamped wait ends before the deadline.
#[cfg_attr(any(target_os = "linux", target_os = "android"), allow(dead_code))]
fn poll_timeout(remaining: Duration) -> PollTimeout {
    let mut millis = remaining.as_millis();
    if !remaining.subsec_nanos().is_multiple_of(1_000_000) {
        millis += 1;
    }
    PollTimeout::from(u16::try_from(millis).unwrap_or(u16::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soon() -> Instant {
        Instant::now() + Duration::from_secs(5)
    }

    fn short_deadline() -> Instant {
        Instant::now() + Duration::from_millis(20)
    }

    /// Reads exactly `len` bytes, failing the test if the deadline passes first.
    fn receive_exact(transport: &mut PtyTransport, len: usize) -> Vec<u8> {
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

    fn all_bytes() -> Vec<u8> {
        (0u8..=0xFF).collect()
    }

    #[test]
    fn slave_path_is_a_device() {
        let pty = PseudoTerminal::open().unwrap();
        assert!(
            pty.slave_path().starts_with("/dev"),
            "{:?}",
            pty.slave_path()
        );
        assert!(pty.slave_path().exists());
    }

    #[test]
    fn all_bytes_pass_master_to_slave_unchanged() {
        let (mut master, mut slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        let bytes = all_bytes();
        master.send(&bytes).unwrap();
        assert_eq!(receive_exact(&mut slave, bytes.len()), bytes);
        // Raw mode: nothing was echoed back to the master.
        let mut buf = [0u8; 16];
        assert_eq!(master.receive(&mut buf, short_deadline()).unwrap(), 0);
    }

    #[test]
    fn all_bytes_pass_slave_to_master_unchanged() {
        let (mut master, mut slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        let bytes = all_bytes();
        slave.send(&bytes).unwrap();
        assert_eq!(receive_exact(&mut master, bytes.len()), bytes);
        let mut buf = [0u8; 16];
        assert_eq!(slave.receive(&mut buf, short_deadline()).unwrap(), 0);
    }

    #[test]
    fn control_characters_pass_unchanged() {
        let (mut master, mut slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        let bytes = [0x0D, 0x0A, 0x11, 0x13, 0x7F, 0x03, 0x04, 0x1A, 0x0D];
        master.send(&bytes).unwrap();
        assert_eq!(receive_exact(&mut slave, bytes.len()), bytes);
        slave.send(&bytes).unwrap();
        assert_eq!(receive_exact(&mut master, bytes.len()), bytes);
    }

    #[test]
    fn receive_times_out_with_zero() {
        let (mut master, mut slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        let mut buf = [0u8; 16];
        assert_eq!(master.receive(&mut buf, short_deadline()).unwrap(), 0);
        assert_eq!(slave.receive(&mut buf, short_deadline()).unwrap(), 0);
    }

    #[test]
    fn master_with_closed_slave_times_out_with_zero() {
        let (mut master, slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        drop(slave);
        let mut buf = [0u8; 16];
        assert_eq!(master.receive(&mut buf, short_deadline()).unwrap(), 0);
    }

    #[test]
    fn slave_reports_an_error_after_master_closes() {
        let (master, mut slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        drop(master);
        let mut buf = [0u8; 16];
        assert!(slave.receive(&mut buf, soon()).is_err());
    }

    #[test]
    fn open_path_on_slave_talks_to_master() {
        let pty = PseudoTerminal::open().unwrap();
        let path = pty.slave_path().to_path_buf();
        let mut master = pty.master().unwrap();
        let mut device = PtyTransport::open_path(&path).unwrap();

        master.send(b"\x02ping\x0D").unwrap();
        assert_eq!(receive_exact(&mut device, 6), b"\x02ping\x0D");
        device.send(b"\x02pong\x0D").unwrap();
        assert_eq!(receive_exact(&mut master, 6), b"\x02pong\x0D");

        // The master keeps working after the device closes and is reopened.
        drop(device);
        let mut buf = [0u8; 16];
        assert_eq!(master.receive(&mut buf, short_deadline()).unwrap(), 0);
        let mut device = PtyTransport::open_path(&path).unwrap();
        device.send(&[0x11, 0x13, 0x7F]).unwrap();
        assert_eq!(receive_exact(&mut master, 3), [0x11, 0x13, 0x7F]);
    }

    #[test]
    fn open_path_rejects_missing_device() {
        let err = PtyTransport::open_path(Path::new("/dev/pts/definitely-not-here")).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::NotFound);
    }

    #[test]
    fn clear_input_drops_pending_bytes() {
        let (mut master, mut slave) = PseudoTerminal::open().unwrap().into_transports().unwrap();
        slave.send(b"stale").unwrap();
        // Wait until the bytes reached the master's input queue without reading them.
        let mut fds = [PollFd::new(master.file.as_fd(), PollFlags::POLLIN)];
        assert_eq!(poll(&mut fds, PollTimeout::from(5000u16)).unwrap(), 1);
        master.clear_input().unwrap();
        let mut buf = [0u8; 16];
        assert_eq!(master.receive(&mut buf, short_deadline()).unwrap(), 0);

        slave.send(b"fresh").unwrap();
        assert_eq!(receive_exact(&mut master, 5), b"fresh");
    }

    #[test]
    fn transports_are_send() {
        fn assert_send<T: Send>() {}
        assert_send::<PtyTransport>();
        assert_send::<PseudoTerminal>();
    }

    #[test]
    fn poll_timeout_rounds_up_and_clamps() {
        assert_eq!(poll_timeout(Duration::ZERO), PollTimeout::ZERO);
        assert_eq!(
            poll_timeout(Duration::from_micros(1)),
            PollTimeout::from(1u16)
        );
        assert_eq!(
            poll_timeout(Duration::from_millis(20)),
            PollTimeout::from(20u16)
        );
        assert_eq!(
            poll_timeout(Duration::from_secs(3600)),
            PollTimeout::from(u16::MAX)
        );
    }
}
