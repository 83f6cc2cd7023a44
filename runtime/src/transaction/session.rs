//! What a master knows between exchanges, apart from its transport: the protocol and line
//! settings, the station it talks to, what it asks of the drive, and what the line and the
//! drive have shown so far (echo, pages, the persistence selector, a late reply still due).
//! Both masters hold one; the engine works on it.

use super::judge::EchoKnowledge;
use super::prepare::{Station, MAX_FRAME};
use crate::layout::Role;
use crate::protocol::Protocol;
use crate::serial::{DriveTiming, SerialSettings};
use std::time::{Duration, Instant};

/// What the master knows about the drive's persistence selector.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SelectorState {
    /// The selector's value in the drive's RAM, when known.
    pub value: Option<u32>,
    /// The caller stated the value: the next persistent write trusts it without reading
    /// the selector.
    pub assumed: bool,
}

/// The state a master carries from one exchange to the next.
pub(crate) struct Session {
    pub protocol: &'static Protocol,
    pub settings: SerialSettings,
    pub timing: DriveTiming,
    pub address: Option<u8>,
    /// The last reply taken as an answer, and its length.
    pub reply: [u8; MAX_FRAME],
    pub reply_len: usize,
    pub last_activity: Option<Instant>,
    pub retries: u8,
    pub line: EchoKnowledge,
    /// Added to the drive's processing time in every reply timeout: the adapter's and the
    /// host's latency, which no manual can know.
    pub host_latency: Duration,
    /// The shortest silence the master keeps between frames, where the caller asks for
    /// more than the protocol's own (a slow gateway or USB adapter).
    pub min_gap: Duration,
    /// After a timeout: until when a late reply may still arrive (the next exchange waits
    /// for it and drops it, so it cannot be taken for the next reply).
    pub late_reply_until: Option<Instant>,
    /// The drive's wait before replying as the caller stated or read it; `None`: the
    /// description's factory setting.
    pub reply_delay: Option<Duration>,
    /// The wait the master asks the drive to make before each reply, in requests whose
    /// layout carries one ([`Role::ReplyWait`], in tens of milliseconds).
    pub reply_wait: u8,
    /// What the master knows about the drive's persistence selector, if it has one.
    pub selector: SelectorState,
    /// The port the master talks to, for drives with several.
    pub port: Option<crate::drive::Port>,
    /// The page each station is known to be on, on a protocol with pages.
    pub pages: Vec<(u8, u16)>,
}

impl Session {
    pub fn new(protocol: &'static Protocol, settings: SerialSettings, timing: DriveTiming) -> Self {
        Session {
            protocol,
            settings,
            timing,
            address: None,
            reply: [0; MAX_FRAME],
            reply_len: 0,
            last_activity: None,
            retries: 0,
            line: EchoKnowledge::default(),
            host_latency: crate::serial::HOST_LATENCY,
            min_gap: Duration::ZERO,
            late_reply_until: None,
            reply_delay: None,
            reply_wait: 0,
            selector: SelectorState::default(),
            port: None,
            pages: Vec::new(),
        }
    }

    /// Talks in the protocol's variant `id` (see [`super::Master::with_variant`]).
    pub fn set_variant(&mut self, id: &str) -> Result<(), crate::error::EncodeError> {
        self.protocol = self.protocol.variant_or_error(id)?;
        Ok(())
    }

    /// Addresses requests to station `address`; another station's persistence selector is
    /// not known.
    pub fn set_address(&mut self, address: Option<u8>) {
        self.address = address;
        self.selector.value = None;
    }

    /// States whether the line echoes the master's requests (`None`: detect it).
    pub fn set_local_echo(&mut self, echo: Option<bool>) {
        self.line = EchoKnowledge {
            echo,
            fixed: echo.is_some(),
        };
    }

    /// The station side of the next exchange.
    pub fn station(&self) -> Station {
        Station {
            address: self.address,
            reply_wait: self.reply_wait,
        }
    }

    /// The last reply taken as an answer.
    pub fn last_reply(&self) -> &[u8] {
        &self.reply[..self.reply_len.min(MAX_FRAME)]
    }

    /// Keeps `bytes` as the last reply.
    pub fn keep_reply(&mut self, bytes: &[u8]) {
        let len = bytes.len().min(MAX_FRAME);
        self.reply[..len].copy_from_slice(&bytes[..len]);
        self.reply_len = len;
    }

    /// The page station `address` is known to be on.
    pub fn known_page(&self, address: Option<u8>) -> Option<u16> {
        let station = address.unwrap_or(0);
        self.pages
            .iter()
            .find(|(s, _)| *s == station)
            .map(|(_, page)| *page)
    }

    /// Remembers the page of the current station (`None`: not known).
    pub fn remember_page(&mut self, page: Option<u16>) {
        let station = self.address.unwrap_or(0);
        self.pages.retain(|(s, _)| *s != station);
        if let Some(page) = page {
            self.pages.push((station, page));
        }
    }

    /// The reply timeout for a request of `request_len` bytes: both frames' wire time, the
    /// drive's processing time, its wait before replying and the host latency (the
    /// transport's own allowance comes on top).
    pub fn reply_timeout(&self, request_len: usize) -> Duration {
        self.timing.reply_timeout(
            &self.settings,
            request_len,
            usize::from(self.protocol.max_frame_len),
        ) + self.reply_delay()
            + self.reply_wait()
            + self.host_latency
    }

    /// Sets the wait asked of the drive before each reply (rounded up to 10 ms, kept within
    /// what the protocol's wait field can carry).
    pub fn set_reply_wait(&mut self, wait: Duration) {
        let tens = wait.as_millis().div_ceil(10);
        let most = self
            .protocol
            .commands
            .iter()
            .filter_map(|c| c.request.field(Role::ReplyWait))
            .map(|field| field.format.max_value(field.width))
            .max()
            .unwrap_or(0);
        self.reply_wait = tens.min(u128::from(most)).min(255) as u8;
    }

    /// The wait each reply is asked for.
    pub fn reply_wait(&self) -> Duration {
        Duration::from_millis(10 * u64::from(self.reply_wait))
    }

    /// The drive's wait before replying that the master allows for.
    pub fn reply_delay(&self) -> Duration {
        self.reply_delay.unwrap_or_else(|| {
            self.protocol
                .timing
                .reply_delay
                .as_ref()
                .map_or(Duration::ZERO, |delay| delay.default)
        })
    }

    /// How long after a timeout a late reply may still arrive: the longest frame's wire
    /// time, the frame gap and the host latency.
    pub fn late_reply_window(&self) -> Duration {
        self.settings
            .wire_time(usize::from(self.protocol.max_frame_len))
            + self.frame_gap()
            + self.host_latency
    }

    /// The silence the master keeps between frames: the protocol's own, or the caller's
    /// minimum where that is longer.
    pub fn frame_gap(&self) -> Duration {
        self.protocol_gap().max(self.min_gap)
    }

    /// The protocol's silence between frames (what the drive keeps before replying).
    pub fn protocol_gap(&self) -> Duration {
        self.settings
            .char_time()
            .mul_f32(self.protocol.frame_gap_chars)
            .max(self.protocol.timing.frame_gap_min)
    }

    /// The longest silence a frame may hold, from the protocol's gap alone (`None`: the
    /// protocol states no gap); the caller's longer gap between the master's frames does not
    /// loosen it.
    pub fn silence_limit(&self) -> Option<Duration> {
        let gap = self.protocol_gap();
        (!gap.is_zero()).then_some(gap)
    }
}
