//! The exchange log of `vfd sim --verbose`: a transport that logs what it carries, each
//! frame once it is whole, decoded by the station it is for (named when the line has
//! several): a request by the station it addresses, in that station's protocol; a reply
//! by the station whose number it carries; the master's follow-ups (Eaton C, F) as what
//! they are; a request no station answers (an inverter reset, a broadcast, an absent
//! station) on its own line, not run into the next.

use crate::frame_text::{follow_up_text, frame_text};
use crate::sim::station::SimStation;
use std::io::Write;
use std::time::{Duration, Instant};
use vfd_runtime::meaning::Direction;
use vfd_runtime::protocol::{Found, Reply};
use vfd_runtime::transport::Transport;

/// A transport that logs each exchange on standard error when `verbose`.
pub struct Logged<'a, T> {
    inner: T,
    stations: &'a [SimStation],
    verbose: bool,
    received: Vec<u8>,
    /// The station the last request logged addressed (a reply's fallback).
    last: Option<usize>,
    start: Instant,
}

/// Who a frame is for, as the log tags it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Whom {
    /// A station of the line (its index).
    Station(usize),
    /// A station number no station of the line has, decoded by the station at `index`.
    Absent(u8, usize),
    /// Every station (a broadcast), decoded by the station at the index.
    All(usize),
}

impl<'a, T: Transport> Logged<'a, T> {
    /// Logs what `inner` carries for `stations` (only when `verbose`).
    pub fn new(inner: T, stations: &'a [SimStation], verbose: bool) -> Self {
        Logged {
            inner,
            stations,
            verbose,
            received: Vec::new(),
            last: None,
            start: Instant::now(),
        }
    }

    /// The whole request at the start of `bytes`, if one is there: the station it is for
    /// (by the number it carries, decoded in that station's protocol) and its length;
    /// noise skipped before it is counted in the length.
    fn request_at(&self, bytes: &[u8]) -> Option<(Whom, usize, usize)> {
        let mut decoded = None;
        for (index, station) in self.stations.iter().enumerate() {
            let Ok(Found::Frame { frame, skipped }) = station.bus.protocol.decode_request(bytes)
            else {
                continue;
            };
            match frame.address {
                Some(address) if address == station.address => {
                    return Some((Whom::Station(index), skipped, frame.len));
                }
                Some(address) => {
                    decoded.get_or_insert((Whom::Absent(address, index), skipped, frame.len));
                }
                None => {
                    decoded.get_or_insert((Whom::All(index), skipped, frame.len));
                }
            }
        }
        // Another station's number decodes in every protocol of its framing: the station
        // at that number, if the line has it, is the one it is for.
        decoded.map(|(whom, skipped, len)| match whom {
            Whom::Absent(address, index) => (
                self.stations
                    .iter()
                    .position(|s| s.address == address)
                    .map_or(Whom::Absent(address, index), Whom::Station),
                skipped,
                len,
            ),
            other => (other, skipped, len),
        })
    }

    /// The master's follow-up (C, F) at the start of `bytes`, in any station's protocol:
    /// its text and length.
    fn follow_up_at(&self, bytes: &[u8]) -> Option<(String, usize)> {
        self.stations.iter().find_map(|station| {
            station
                .bus
                .protocol
                .commands
                .iter()
                .filter_map(|c| c.follow_up.as_ref())
                .find_map(|f| f.recognise(bytes))
                .map(|(_, _, len)| {
                    let text =
                        follow_up_text(station.bus.protocol, &bytes[..len]).unwrap_or_default();
                    (text, len)
                })
        })
    }

    /// The station a reply comes from: the one whose number it carries, in its protocol;
    /// else the one the last request addressed.
    fn replying(&self, bytes: &[u8]) -> usize {
        self.stations
            .iter()
            .position(|station| {
                let address = match station.bus.protocol.decode_reply(None, bytes) {
                    Ok(Found::Frame {
                        frame: Reply::Data { address, .. } | Reply::Error { address, .. },
                        ..
                    }) => address,
                    _ => None,
                };
                address == Some(station.address)
            })
            .or(self.last)
            .unwrap_or(0)
    }

    /// Logs and drops every whole frame at the start of what was received: follow-ups and
    /// requests, each as soon as it is whole.
    fn log_whole_frames(&mut self) {
        loop {
            if let Some((text, len)) = self.follow_up_at(&self.received) {
                let frame: Vec<u8> = self.received.drain(..len).collect();
                self.line("follow", None, &frame, &text);
                continue;
            }
            let Some((whom, skipped, len)) = self.request_at(&self.received) else {
                break;
            };
            if skipped > 0 {
                let noise: Vec<u8> = self.received.drain(..skipped).collect();
                self.line("noise", None, &noise, "bytes before a request's start");
            }
            let frame: Vec<u8> = self.received.drain(..len).collect();
            self.request(whom, &frame);
        }
    }

    fn request(&mut self, whom: Whom, bytes: &[u8]) {
        let (index, tag) = match whom {
            Whom::Station(index) => (index, self.stations[index].address.to_string()),
            Whom::Absent(address, index) => (index, format!("{address}: no such station")),
            Whom::All(index) => (index, "all".to_owned()),
        };
        let station = &self.stations[index];
        let mut text = frame_text(
            station.drive,
            station.bus.protocol,
            Direction::Request,
            bytes,
        );
        if !matches!(whom, Whom::Station(_)) {
            text.push_str("; no station of this line answers it");
        }
        self.last = matches!(whom, Whom::Station(_)).then_some(index);
        self.line(Direction::Request.as_str(), Some(tag), bytes, &text);
    }

    fn line(&self, what: &str, tag: Option<String>, bytes: &[u8], text: &str) {
        let who = match tag {
            Some(tag) if self.stations.len() > 1 || !tag.chars().all(|c| c.is_ascii_digit()) => {
                format!("[{tag}] ")
            }
            _ => String::new(),
        };
        let _ = writeln!(
            std::io::stderr(),
            "{:>8.3}s {:<7} {who}{}  {text}",
            self.start.elapsed().as_secs_f64(),
            what,
            vfd_runtime::error::hex(bytes),
        );
    }
}

impl<T: Transport> Transport for Logged<'_, T> {
    fn send(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        if self.verbose && !self.stations.is_empty() {
            self.log_whole_frames();
            // What is left is no whole frame (noise, a broken request).
            let rest = std::mem::take(&mut self.received);
            let index = self.replying(bytes);
            let station = &self.stations[index];
            if !rest.is_empty() {
                let text = frame_text(
                    station.drive,
                    station.bus.protocol,
                    Direction::Request,
                    &rest,
                );
                self.line(Direction::Request.as_str(), None, &rest, &text);
            }
            let text = frame_text(station.drive, station.bus.protocol, Direction::Reply, bytes);
            self.line(
                Direction::Reply.as_str(),
                Some(station.address.to_string()),
                bytes,
                &text,
            );
        }
        self.inner.send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], deadline: Instant) -> std::io::Result<usize> {
        let got = self.inner.receive(buf, deadline)?;
        if self.verbose && got > 0 {
            self.received.extend_from_slice(&buf[..got]);
            self.log_whole_frames();
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
