//! In-process use: a [`Transport`] that hands the master's bytes to a virtual drive and
//! returns its replies, so a typed `Master` talks to the simulator without any device.

use super::faults::Fault;
use super::{Simulator, Transmission};
use crate::protocol::{DriveProtocol, Protocol};
use crate::transaction::Master;
use crate::transport::Transport;
use std::collections::VecDeque;
use std::io;
use std::time::{Duration, Instant};

/// A transport whose far end is a virtual drive ([`Simulator::link`]).
#[derive(Debug)]
pub struct SimLink {
    simulator: Simulator,
    protocol: &'static Protocol,
    input: Vec<u8>,
    pending: VecDeque<u8>,
    /// Replies the drive sends late: they arrive after the master's deadline.
    late: VecDeque<u8>,
    single_bytes: bool,
    /// When the pending reply may be received: the drive's reply delay after the request.
    available_at: Option<Instant>,
}

impl SimLink {
    pub(crate) fn new(simulator: Simulator, protocol: &'static Protocol) -> SimLink {
        SimLink {
            simulator,
            protocol,
            input: Vec::new(),
            pending: VecDeque::new(),
            late: VecDeque::new(),
            single_bytes: false,
            available_at: None,
        }
    }
}

impl Transport for SimLink {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.input.extend_from_slice(bytes);
        let transmissions = {
            let mut drive = self.simulator.lock();
            // Each send is one burst after a silence (the master keeps the frame gap), and
            // the line is silent after it while the master waits for the reply.
            drive.line_silent();
            drive.receive_before_silence(self.protocol, &mut self.input)
        };
        // The master sends whole frames: what is left cannot become one.
        self.input.clear();
        for transmission in transmissions {
            let Transmission {
                bytes,
                delayed,
                split,
                wait,
                ..
            } = transmission;
            self.single_bytes = split.is_some();
            self.available_at = (!wait.is_zero()).then(|| Instant::now() + wait);
            if delayed {
                self.late.extend(bytes);
            } else {
                self.pending.extend(bytes);
            }
        }
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        if self.pending.is_empty() {
            if self.simulator.has_fault(&Fault::Noise) {
                if Instant::now() >= deadline {
                    return Ok(0);
                }
                std::thread::sleep(Duration::from_millis(1));
                let noise = [0x00u8, 0xFF, 0x55, 0xAA];
                let count = buf.len().min(noise.len());
                buf[..count].copy_from_slice(&noise[..count]);
                return Ok(count);
            }
            // Nothing more is coming before the deadline: late replies come after it.
            self.pending.extend(self.late.drain(..));
            return Ok(0);
        }
        if let Some(at) = self.available_at {
            // The drive waits before replying (its reply-delay registers).
            let now = Instant::now();
            if now < at {
                std::thread::sleep(at.min(deadline).saturating_duration_since(now));
                if deadline < at {
                    return Ok(0);
                }
            }
            self.available_at = None;
        }
        let count = if self.single_bytes {
            1
        } else {
            buf.len().min(self.pending.len())
        };
        for (slot, byte) in buf.iter_mut().zip(self.pending.drain(..count)) {
            *slot = byte;
        }
        Ok(count)
    }

    fn clear_input(&mut self) -> io::Result<()> {
        self.pending.clear();
        self.late.clear();
        Ok(())
    }
}

impl Simulator {
    /// An in-process transport to the drive, speaking `protocol`.
    pub fn link(&self, protocol: &'static Protocol) -> SimLink {
        SimLink::new(self.clone(), protocol)
    }

    /// A typed master connected to the drive over `protocol`, with the drive's default
    /// serial settings and timing, addressing the drive's station.
    pub fn master<D: 'static>(&self, protocol: &'static DriveProtocol<D>) -> Master<SimLink, D> {
        let info = self.lock().drive;
        let address = self.lock().address;
        Master::new(
            self.link(protocol.protocol()),
            protocol,
            info.serial.default,
            info.serial.timing,
        )
        .with_address(Some(address))
    }
}
