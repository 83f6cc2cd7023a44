//! Serial line settings and the timings derived from them (character time, wire time,
//! reply timeout).

use crate::layout::List;
use std::time::Duration;

/// Parity bit setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Parity {
    /// No parity bit.
    None,
    /// Even parity.
    Even,
    /// Odd parity.
    Odd,
}

impl Parity {
    /// Every parity setting.
    pub const ALL: [Parity; 3] = [Parity::None, Parity::Even, Parity::Odd];

    /// Name as written in drive files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Parity::None => "none",
            Parity::Even => "even",
            Parity::Odd => "odd",
        }
    }
}

/// Settings of one serial line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SerialSettings {
    /// Bits per second.
    pub baud: u32,
    /// Data bits per character (7 or 8).
    pub data_bits: u8,
    /// Parity.
    pub parity: Parity,
    /// Stop bits (1 or 2).
    pub stop_bits: u8,
}

impl SerialSettings {
    /// Bits on the wire per character: start, data, parity and stop bits.
    pub fn bits_per_char(&self) -> u32 {
        1 + u32::from(self.data_bits)
            + u32::from(self.parity != Parity::None)
            + u32::from(self.stop_bits)
    }

    /// Time one character takes on the wire.
    pub fn char_time(&self) -> Duration {
        Duration::from_nanos(
            u64::from(self.bits_per_char()) * 1_000_000_000 / u64::from(self.baud.max(1)),
        )
    }

    /// Time `bytes` characters take on the wire.
    pub fn wire_time(&self, bytes: usize) -> Duration {
        self.char_time() * u32::try_from(bytes).unwrap_or(u32::MAX)
    }
}

/// Timing facts from a drive's manual.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DriveTiming {
    /// After power-on the drive does not answer for this long.
    pub startup_delay: Duration,
    /// Time the drive may take to start answering once a request has arrived.
    pub processing_allowance: Duration,
    /// The drive drops a frame that is not complete within this time of its start.
    pub frame_abandon: Duration,
}

impl DriveTiming {
    /// Reply timeout for one exchange: the request's and the longest reply's wire time
    /// plus the drive's processing allowance.
    pub fn reply_timeout(
        &self,
        settings: &SerialSettings,
        request_len: usize,
        max_reply_len: usize,
    ) -> Duration {
        settings.wire_time(request_len)
            + settings.wire_time(max_reply_len)
            + self.processing_allowance
    }
}

/// Timing rules of one protocol as one drive speaks it, beyond the frame gap in characters
/// (drive file: overrides on the drive's `protocols[]` entry, since protocol files are
/// shared with drives whose manuals lack these rules).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LinkTiming {
    /// The shortest silence between frames whatever the baud rate (VF-AS1: about 2 ms;
    /// DV1 Modbus RTU: 10 ms); the gap is the longer of this and the gap in characters.
    pub frame_gap_min: Duration,
    /// The longest silence allowed between two bytes of one frame, in character times
    /// (VF-AS1: 1.5): the drive drops a frame with a longer one. 0: no limit but the
    /// frame abandon time.
    pub max_inner_gap_chars: f32,
    /// What the drive makes of bytes before a frame's start sequence.
    pub before_start: BeforeStart,
    /// The registers whose value delays every reply, when the drive has them.
    pub reply_delay: Option<ReplyDelay>,
}

impl LinkTiming {
    /// No rule beyond the protocol file's: no gap floor, no inner-gap limit, bytes before
    /// the start skipped, no reply delay.
    pub const NONE: LinkTiming = LinkTiming {
        frame_gap_min: Duration::ZERO,
        max_inner_gap_chars: 0.0,
        before_start: BeforeStart::Skip,
        reply_delay: None,
    };
}

/// What a drive makes of bytes received before a frame's start sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum BeforeStart {
    /// They are skipped: the frame begins at its start sequence (YD1000, VF-A7).
    Skip,
    /// The frame they precede (up to the next silence) is rejected, unanswered (VF-AS1:
    /// every frame must begin with its start code).
    Reject,
}

impl BeforeStart {
    /// Every rule.
    pub const ALL: [BeforeStart; 2] = [BeforeStart::Skip, BeforeStart::Reject];

    /// The rule's name as description files write it.
    pub const fn as_str(self) -> &'static str {
        match self {
            BeforeStart::Skip => "skip",
            BeforeStart::Reject => "reject",
        }
    }
}

/// A wait before every reply that registers of the drive set (VF-AS1 F805 / F825: 0.00-2.00
/// s): the master adds it to the reply timeout, the virtual drive waits that long.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ReplyDelay {
    /// The registers (numbers before any address map). With several (one per port), the
    /// master does not know which applies and takes the longest.
    pub registers: List<u16>,
    /// The wait one raw step stands for (0.01 s).
    pub step: Duration,
    /// The wait at the registers' factory setting.
    pub default: Duration,
    /// The longest wait the registers can set.
    pub max: Duration,
}

impl ReplyDelay {
    /// The wait a raw register value sets.
    pub fn of_raw(&self, raw: u32) -> Duration {
        self.step.saturating_mul(raw).min(self.max.max(self.step))
    }
}

/// Latency a master adds to every reply timeout for the adapter and the host, beyond what
/// the drive's manual states: USB serial adapters hold received bytes for up to 16 ms, and a
/// loaded machine schedules a waiting thread late. `Master::with_host_latency` changes it.
pub const HOST_LATENCY: Duration = Duration::from_millis(50);

/// Serial facts of a drive: supported settings and their defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct SerialSpec {
    /// Supported baud rates.
    pub baud_rates: &'static [u32],
    /// Supported parities.
    pub parities: &'static [Parity],
    /// Factory settings (what the drive expects out of the box); a protocol whose
    /// character format a setting chooses has its own ([`SerialSpec::default_for`]).
    pub default: SerialSettings,
    /// The data bits the drive can use: one when fixed, `[7, 8]` when a setting chooses
    /// (the DV1's 07-03 and 07-07).
    pub data_bits: &'static [u8],
    /// The character formats a setting offers each protocol (the DV1's 07-07: Modbus RTU
    /// at 8N2, 8E1 or 8O1, 8E1 from the factory); a protocol not listed speaks
    /// [`SerialSpec::default`]'s format (or what `data_bits`, `parities` and the stop bits
    /// allow).
    pub protocol_lines: &'static [ProtocolLine],
    /// Stop bits the drive sends.
    pub stop_bits_sent: u8,
    /// Stop bits the drive needs to receive.
    pub stop_bits_received: u8,
    /// The stop bits the drive can be set to, when they are its choice ("1 or 2": `[1, 2]`;
    /// it then sends and needs what it is set to, `stop_bits_sent` and
    /// `stop_bits_received` being the factory setting); empty: fixed.
    pub stop_bits: &'static [u8],
    /// Timing facts.
    pub timing: DriveTiming,
}

/// A character format a setting of the drive offers a protocol: the DV1's 07-07 offers
/// Modbus RTU at 8N2, 8E1 and 8O1, 8E1 being its factory setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ProtocolLine {
    /// The protocol's id in the drive.
    pub protocol: &'static str,
    /// Data bits per character.
    pub data_bits: u8,
    /// Parity.
    pub parity: Parity,
    /// Stop bits.
    pub stop_bits: u8,
    /// The setting's factory value chooses this format.
    pub factory: bool,
}

impl ProtocolLine {
    /// `8E1`: data bits, parity letter, stop bits.
    pub fn label(&self) -> String {
        format_label(self.data_bits, self.parity, self.stop_bits)
    }

    /// Whether `settings` use this format.
    pub fn fits(&self, settings: &SerialSettings) -> bool {
        (settings.data_bits, settings.parity, settings.stop_bits)
            == (self.data_bits, self.parity, self.stop_bits)
    }
}

impl SerialSettings {
    /// The character format, `8E1`: data bits, parity letter, stop bits.
    pub fn format_label(&self) -> String {
        format_label(self.data_bits, self.parity, self.stop_bits)
    }
}

fn format_label(data_bits: u8, parity: Parity, stop_bits: u8) -> String {
    let parity = match parity {
        Parity::None => 'N',
        Parity::Even => 'E',
        Parity::Odd => 'O',
    };
    format!("{data_bits}{parity}{stop_bits}")
}

impl SerialSpec {
    /// The factory settings for speaking `protocol`: [`SerialSpec::default`] with the
    /// protocol's own character format where a setting chooses one (the DV1 speaks Eaton
    /// at 8N1 and Modbus RTU at 8E1 out of the box). When the setting's factory value
    /// chooses another protocol, the first format it offers this one (the DV1's Modbus
    /// ASCII: 7N2), an assumption a master starts from.
    pub fn default_for(&self, protocol: &str) -> SerialSettings {
        let offered = || {
            self.protocol_lines
                .iter()
                .filter(|l| l.protocol == protocol)
        };
        match offered().find(|l| l.factory).or_else(|| offered().next()) {
            Some(line) => SerialSettings {
                data_bits: line.data_bits,
                parity: line.parity,
                stop_bits: line.stop_bits,
                ..self.default
            },
            None => self.default,
        }
    }

    /// The formats a setting offers `protocol` (empty: any the drive's data bits, parities
    /// and stop bits allow).
    pub fn formats_for<'a>(&'a self, protocol: &'a str) -> impl Iterator<Item = &'a ProtocolLine> {
        self.protocol_lines
            .iter()
            .filter(move |l| l.protocol == protocol)
    }

    /// The stop bits the drive can be set to: its choices, or the fixed ones it needs.
    pub fn stop_bits_choices(&self) -> &[u8] {
        if self.stop_bits.is_empty() {
            std::slice::from_ref(&self.stop_bits_received)
        } else {
            self.stop_bits
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_e_one_at_9600_takes_about_1_15_ms_per_character() {
        let settings = SerialSettings {
            baud: 9600,
            data_bits: 8,
            parity: Parity::Even,
            stop_bits: 1,
        };
        assert_eq!(settings.bits_per_char(), 11);
        assert_eq!(settings.char_time(), Duration::from_nanos(1_145_833));
        // 8-byte request + 7-byte reply: about 17 ms on the wire.
        assert_eq!(settings.wire_time(15).as_millis(), 17);
    }

    #[test]
    fn reply_timeout_grows_as_the_baud_rate_falls() {
        let timing = DriveTiming {
            startup_delay: Duration::from_secs(1),
            processing_allowance: Duration::from_millis(100),
            frame_abandon: Duration::from_secs(1),
        };
        let fast = SerialSettings {
            baud: 9600,
            data_bits: 8,
            parity: Parity::Even,
            stop_bits: 1,
        };
        let slow = SerialSettings { baud: 1200, ..fast };
        assert!(timing.reply_timeout(&slow, 8, 15) > timing.reply_timeout(&fast, 8, 15));
        assert_eq!(
            timing.reply_timeout(&slow, 8, 15),
            slow.wire_time(23) + Duration::from_millis(100)
        );
    }
}
