//! The exchange log of `vfd sim --verbose`: a transport that logs what it carries, the
//! bytes received since the last reply as the request and each reply, in hex and decoded
//! by the station that answered (named when the line has several).

use crate::frame_text::frame_text;
use crate::sim_station::SimStation;
use std::io::Write;
use std::time::{Duration, Instant};
use vfd_runtime::meaning::Direction;
use vfd_runtime::protocol::Found;
use vfd_runtime::transport::Transport;
use vfd_runtime::Protocol;

/// A transport that logs each exchange on standard error when `verbose`.
pub struct Logged<'a, T> {
    inner: T,
    stations: &'a [SimStation],
    verbose: bool,
    received: Vec<u8>,
    start: Instant,
}

impl<'a, T: Transport> Logged<'a, T> {
    /// Logs what `inner` carries for `stations` (only when `verbose`).
    pub fn new(inner: T, stations: &'a [SimStation], verbose: bool) -> Self {
        Logged {
            inner,
            stations,
            verbose,
            received: Vec::new(),
            start: Instant::now(),
        }
    }

    /// The station a request is for: the one at the address it carries, else the first.
    fn station_for(&self, request: &[u8]) -> &'a SimStation {
        let first = &self.stations[0];
        let address = match first.bus.protocol.decode_request(request) {
            Ok(Found::Frame { frame, .. }) => frame.address,
            _ => None,
        };
        address
            .and_then(|a| self.stations.iter().find(|s| s.address == a))
            .unwrap_or(first)
    }

    fn log(&self, station: &SimStation, direction: Direction, bytes: &[u8]) {
        let who = if self.stations.len() > 1 {
            format!("[{}] ", station.address)
        } else {
            String::new()
        };
        let _ = writeln!(
            std::io::stderr(),
            "{:>8.3}s {:<7} {who}{}  {}",
            self.start.elapsed().as_secs_f64(),
            direction.as_str(),
            vfd_runtime::error::hex(bytes),
            frame_text(station.drive, station.bus.protocol, direction, bytes)
        );
    }
}

/// The master's follow-up to a reply at the start of `bytes` (`true`: acknowledged), with
/// the station it names and its length.
fn follow_up_at(protocol: &Protocol, bytes: &[u8]) -> Option<(bool, Option<u8>, usize)> {
    protocol
        .commands
        .iter()
        .filter_map(|c| c.follow_up.as_ref())
        .find_map(|f| f.recognise(bytes))
}

impl<T: Transport> Transport for Logged<'_, T> {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        if self.verbose && !self.stations.is_empty() {
            let mut request = std::mem::take(&mut self.received);
            let protocol = self.stations[0].bus.protocol;
            // The master's follow-ups to earlier replies (C, F) come before its request.
            while let Some((sound, address, len)) = follow_up_at(protocol, &request) {
                let _ = writeln!(
                    std::io::stderr(),
                    "{:>8.3}s {:<7} {}  {}{}",
                    self.start.elapsed().as_secs_f64(),
                    "follow",
                    vfd_runtime::error::hex(&request[..len]),
                    if sound {
                        "the master acknowledges the reply"
                    } else {
                        "the master asks for the reply again"
                    },
                    address.map_or_else(String::new, |a| format!(", station {a}")),
                );
                request.drain(..len);
            }
            let station = self.station_for(&request);
            if !request.is_empty() {
                self.log(station, Direction::Request, &request);
            }
            self.log(station, Direction::Reply, bytes);
        }
        self.inner.send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if self.verbose {
            self.received.extend_from_slice(&buf[..got]);
            if self.received.len() > 4096 {
                self.received.clear();
            }
        }
        Ok(got)
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
