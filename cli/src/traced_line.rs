//! A line that prints every frame it carries (`--trace`, and the demo's view of the line):
//! each request as it is sent, each reply once it is whole, in hex and decoded. The lines
//! themselves are the library's ([`vfd_bus::Line`]).

use std::time::{Duration, Instant};
use vfd_bus::Line;
use vfd_runtime::meaning::{decode_meaning, Direction};
use vfd_runtime::transport::Transport;
use vfd_runtime::{DriveInfo, Protocol};

/// A line that prints every frame it carries: each request as it is sent, each reply once
/// it is whole.
pub struct Traced {
    /// The line itself.
    pub inner: Line,
    /// The drive, to name registers.
    pub drive: &'static DriveInfo,
    /// The protocol, to decode frames.
    pub protocol: &'static Protocol,
    received: Vec<u8>,
    /// `--trace`: print on standard error with times (else, as the demo shows the line,
    /// on standard output).
    stderr: bool,
}

impl Traced {
    /// `inner`, traced.
    #[cfg_attr(not(all(unix, feature = "pty")), allow(dead_code))] // used by the demo only
    pub fn line(inner: Line, drive: &'static DriveInfo, protocol: &'static Protocol) -> Line {
        Line::other(Traced {
            inner,
            drive,
            protocol,
            received: Vec::new(),
            stderr: false,
        })
    }

    /// `inner`, traced on standard error with times (`--trace`).
    pub fn on_stderr(inner: Line, drive: &'static DriveInfo, protocol: &'static Protocol) -> Line {
        crate::trace::start();
        Line::other(Traced {
            inner,
            drive,
            protocol,
            received: Vec::new(),
            stderr: true,
        })
    }

    fn print(&self, arrow: &str, direction: Direction, bytes: &[u8]) {
        let hex = vfd_runtime::error::hex(bytes);
        let text = crate::frame_text::frame_text(self.drive, self.protocol, direction, bytes);
        if self.stderr {
            crate::trace::line(format_args!("{arrow} {hex}  [{text}]"));
        } else {
            crate::out::say!("    {arrow} {hex}  [{text}]");
        }
    }

    fn send_traced(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        if self.stderr && !self.received.is_empty() {
            // Bytes that never made a whole reply (noise, a garbled or partial reply).
            let hex = vfd_runtime::error::hex(&self.received);
            crate::trace::line(format_args!("<- {hex}  [not a whole reply]"));
        }
        self.received.clear();
        self.print("->", Direction::Request, bytes);
        self.inner.send(bytes)
    }

    fn receive_traced(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        self.received.extend_from_slice(&buf[..got]);
        if got > 0 && decode_meaning(self.protocol, Direction::Reply, &self.received).is_ok() {
            let reply = std::mem::take(&mut self.received);
            self.print("<-", Direction::Reply, &reply);
        }
        Ok(got)
    }
}

impl Transport for Traced {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.send_traced(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        self.receive_traced(buf, deadline)
    }
    fn clear_input(&mut self) -> std::io::Result<()> {
        self.inner.clear_input()
    }
    fn last_gap(&self) -> Option<Duration> {
        self.inner.last_gap()
    }
    fn allowance(&self) -> Duration {
        self.inner.allowance()
    }
}
