//! Replies are judged from bytes alone: a [`Judge`] takes what the line delivers after a
//! prepared frame and says when the exchange is decided, with no I/O and no clock of its
//! own (the caller says when the deadline has come).
//!
//! Finding the reply is generic: the master's own request coming back (an echoing
//! half-duplex adapter) is skipped, noise and frames that answer something else are passed
//! over, a silence longer than a frame allows starts a new frame (where the transport can
//! tell), and of overlapping frames the one starting last wins.

use super::answer::{check_reply, Answer};
use super::error::{ReplyField, TransactionError, TransactionErrorKind};
use super::prepare::{Prepared, MAX_FRAME};
use crate::error::DecodeError;
use crate::layout::Role;
use crate::protocol::{Difference, Protocol, Search};
use crate::register::Request;
use std::time::{Duration, Instant};

/// What the line is known to do with the master's own frames.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EchoKnowledge {
    /// `Some(true)`: every request comes back before its reply; `Some(false)`: none does;
    /// `None`: not known yet.
    pub echo: Option<bool>,
    /// The caller stated it, so replies teach nothing.
    pub fixed: bool,
}

impl EchoKnowledge {
    /// Records what a reply showed about the line, unless the caller stated it.
    fn learn(&mut self, echoes: bool) {
        if !self.fixed {
            self.echo = Some(echoes);
        }
    }
}

/// The judgement of one exchange's reply, fed the bytes as they come.
pub struct Judge<'p> {
    protocol: &'static Protocol,
    prepared: &'p Prepared,
    /// The bytes that went out (the request, or the follow-up asking for the reply again).
    sent: &'p [u8],
    line: EchoKnowledge,
    silence_limit: Option<Duration>,
    reply: [u8; MAX_FRAME],
    /// Bytes in the reply buffer.
    filled: usize,
    /// Bytes were dropped since the request went out: no echo can be ahead any more.
    echo_passed: bool,
    /// An answer to give at the deadline if no better one comes.
    fallback: Option<Result<Answer, TransactionError>>,
    /// The fallback is a copy of the request on a line not known to echo.
    copy_fallback: bool,
    /// A frame whose checksum did not match.
    corrupt: Option<DecodeError>,
    /// A frame that answered something else.
    foreign: Option<Difference>,
    /// The furthest decode error seen.
    last_error: Option<DecodeError>,
}

impl<'p> Judge<'p> {
    /// A judge of the reply to `prepared`, after `sent` went out, on a line known to do
    /// what `line` says; a silence longer than `silence_limit` inside what arrives starts a
    /// new frame (where the transport reports silences).
    pub fn new(
        protocol: &'static Protocol,
        prepared: &'p Prepared,
        sent: &'p [u8],
        line: EchoKnowledge,
        silence_limit: Option<Duration>,
    ) -> Judge<'p> {
        Judge {
            protocol,
            prepared,
            sent,
            line,
            silence_limit,
            reply: [0; MAX_FRAME],
            filled: 0,
            echo_passed: false,
            fallback: None,
            copy_fallback: false,
            corrupt: None,
            foreign: None,
            last_error: None,
        }
    }

    /// What the line is known to do after what this exchange showed.
    pub fn line(&self) -> EchoKnowledge {
        self.line
    }

    /// The bytes received so far.
    pub fn received(&self) -> &[u8] {
        &self.reply[..self.filled]
    }

    /// Where the next bytes go. When only noise has filled the buffer, its last half is
    /// kept and looked through again.
    pub fn space(&mut self) -> &mut [u8] {
        if self.filled == MAX_FRAME {
            log::debug!(
                target: super::line::LOG_TARGET,
                "resync: {} byte(s) held no reply; looking on from the last half",
                MAX_FRAME
            );
            self.reply.copy_within(MAX_FRAME / 2.., 0);
            self.filled = MAX_FRAME - MAX_FRAME / 2;
            self.echo_passed = true;
        }
        &mut self.reply[self.filled..]
    }

    /// The `got` bytes just written into [`Judge::space`], before [`Judge::take`].
    pub fn arrived(&self, got: usize) -> &[u8] {
        let end = (self.filled + got).min(MAX_FRAME);
        &self.reply[self.filled..end]
    }

    /// `got` bytes arrived in [`Judge::space`], after a silence of `gap` on the line where
    /// the transport can tell. `Some` when the exchange is decided.
    pub fn take(
        &mut self,
        got: usize,
        gap: Option<Duration>,
    ) -> Option<Result<Answer, TransactionError>> {
        if let (Some(limit), Some(gap)) = (self.silence_limit, gap) {
            if self.filled > 0 && gap > limit {
                // A silence no frame holds: what came before is not part of the reply (a
                // false start, noise, our own echo).
                log::debug!(
                    target: super::line::LOG_TARGET,
                    "resync: a silence of {:.1} ms ends {} byte(s) that are not the reply",
                    gap.as_secs_f64() * 1000.0,
                    self.filled
                );
                let filled = self.filled;
                self.reply.copy_within(filled..filled + got, 0);
                self.filled = 0;
                self.echo_passed = true;
            }
        }
        self.filled += got;
        self.settle()
    }

    /// How long to wait before reading again at `now` (`None`: read at once), so that a
    /// line delivering a byte at a time (a UART, a paced link) does not wake the master for
    /// every byte: until nearly all the bytes the reply still needs at the least can have
    /// arrived, one `char_time` each. Neither a reply nor an error reply is shorter than
    /// the prepared frame's shortest answer (plus the echo of the request, where the line
    /// is known to echo); once the error reply is ruled out, the reply's expected size.
    /// Never past `deadline`; it never changes a decision, which is taken on the bytes.
    pub fn read_ahead(
        &self,
        char_time: Duration,
        now: Instant,
        deadline: Instant,
    ) -> Option<Duration> {
        let echo = if self.line.echo == Some(true) && !self.echo_passed {
            self.sent.len()
        } else {
            0
        };
        let shortest = if self.error_reply_ruled_out() {
            self.prepared.shortest_own_reply()
        } else {
            self.prepared.shortest_reply()
        };
        let needed = (shortest + echo).saturating_sub(self.filled);
        read_ahead_wait(needed, char_time, now, deadline)
    }

    /// How long to wait at `now`, before the first read, for a request sent at `sent_at`:
    /// the command's own reply cannot be complete before the request is on the line, the
    /// silence between frames `gap` has passed and its shortest form has followed (an echo
    /// comes while the request goes out), so a line that cannot report silences takes a
    /// prompt reply in one read. The error reply, which a
    /// sound exchange does not get, may be shorter: it is read as late as the command's
    /// own reply would be whole (within the deadline, and no decision changes). Never past
    /// `deadline`; `None` once bytes have come.
    pub fn first_wait(
        &self,
        char_time: Duration,
        gap: Duration,
        sent_at: Instant,
        now: Instant,
        deadline: Instant,
    ) -> Option<Duration> {
        if self.filled > 0 {
            return None;
        }
        let chars = self.sent.len() + self.prepared.shortest_own_reply();
        first_wait(chars, char_time, gap, sent_at, now, deadline)
    }

    /// Whether the bytes so far cannot begin the protocol's error reply (a Modbus reply
    /// whose function code lacks the exception bit), so that only the command's own reply
    /// can still come. Only on a line known not to echo, where the reply starts at the first
    /// byte; a wrong guess costs at most a longer wait within the deadline.
    fn error_reply_ruled_out(&self) -> bool {
        if self.line.echo != Some(false) || self.filled == 0 {
            return false;
        }
        self.protocol.error_reply.as_ref().is_some_and(|error| {
            crate::codec::decode_prefix(error, &self.reply[..self.filled]).is_err()
        })
    }

    /// The outcome at the reply deadline, `waited` after the request: the best answer held
    /// back, else what went wrong (a timeout when nothing decoded).
    pub fn at_deadline(&mut self, waited: Duration) -> Result<Answer, TransactionError> {
        if let Some(answer) = self.fallback.take() {
            if self.copy_fallback {
                // Only the one copy came: the line does not echo.
                self.line.learn(false);
            }
            return answer;
        }
        let kind = if let Some(error) = self.corrupt.take() {
            TransactionErrorKind::Decode(Box::new(error))
        } else if let Some(difference) = self.foreign {
            mismatch_of(difference, self.prepared.request())
        } else {
            TransactionErrorKind::Timeout {
                waited,
                received: self.reply[..self.filled.min(64)].to_vec(),
                received_len: self.filled,
                last_error: self.last_error.take().map(Box::new),
            }
        };
        Err(self.fail(kind))
    }

    fn fail(&self, kind: TransactionErrorKind) -> TransactionError {
        TransactionError::new(Some(self.prepared.request()), kind)
    }

    /// The answer `frame`, found `offset` bytes into the buffer, gives the request.
    fn answer(
        &self,
        frame: crate::protocol::Reply<'static>,
        offset: usize,
    ) -> Result<Answer, TransactionError> {
        check_reply(self.prepared.request(), self.prepared.block_size(), frame)
            .map(|answer| answer.shifted(offset))
    }

    /// Searches `reply[from..to]` for the reply.
    fn search(&self, from: usize, to: usize) -> Search<'static> {
        self.protocol.search_reply(
            self.prepared.command(),
            self.prepared.expectation(),
            &self.reply[from..to],
        )
    }

    /// Looks at the bytes received so far: `Some` when the exchange is decided.
    fn settle(&mut self) -> Option<Result<Answer, TransactionError>> {
        let (filled, len) = (self.filled, self.sent.len());
        let shared = filled.min(len);
        let echo_possible = !self.echo_passed
            && self.line.echo != Some(false)
            && self.reply[..shared] == self.sent[..shared];
        if !echo_possible {
            let search = self.search(0, filled);
            if !self.echo_passed
                && search
                    .found
                    .as_ref()
                    .is_some_and(|(_, skipped)| *skipped == 0)
            {
                // The first bytes back are a reply, not our request: the line does not echo.
                self.line.learn(false);
            }
            return self.decide(search, 0);
        }
        if filled < len {
            // Perhaps our own request coming back: wait for the rest of it (or, should these
            // bytes be a whole reply after all, for the deadline).
            let found = self
                .line
                .echo
                .is_none()
                .then(|| self.search(0, filled).found)
                .flatten();
            if let Some((frame, skipped)) = found {
                self.fallback = Some(self.answer(frame, skipped));
            }
            return None;
        }
        // A whole copy of the request. Is it a reply too (Modbus answers a single write with
        // the request's own bytes)?
        let copy = self
            .search(0, len)
            .found
            .filter(|(frame, skipped)| *skipped == 0 && frame.len() == len)
            .map(|(frame, _)| self.answer(frame, 0));
        let after = (filled > len).then(|| self.search(len, filled));
        let Some(copy) = copy else {
            // It cannot be a reply: it is our own request coming back.
            self.line.learn(true);
            return after.and_then(|search| self.decide(search, len));
        };
        if let Some(search) = after {
            if search.found.is_some() || search.corrupt.is_some() || search.foreign.is_some() {
                // A frame follows the copy: the copy was our own request coming back.
                self.line.learn(true);
                return self.decide(search, len);
            }
            if self.line.echo == Some(true) || search.waiting {
                self.fallback = self.fallback.take().or(match self.line.echo {
                    Some(true) => None,
                    _ => Some(copy),
                });
                return self.decide(search, len);
            }
            if self.line.echo == Some(false) {
                // Noise after a reply on a line that does not echo.
                return Some(copy);
            }
        }
        match self.line.echo {
            // The line does not echo: the copy is the reply.
            Some(false) => Some(copy),
            // It does: the reply is still to come.
            Some(true) => None,
            // Not known yet: the copy answers only if no second one comes by the deadline.
            None => {
                if self.fallback.is_none() {
                    self.fallback = Some(copy);
                    self.copy_fallback = true;
                }
                None
            }
        }
    }

    /// What a search over the bytes after `base` means for the exchange: `Some` when it is
    /// decided, `None` to read on (remembering what was seen, for the deadline).
    fn decide(
        &mut self,
        search: Search<'static>,
        base: usize,
    ) -> Option<Result<Answer, TransactionError>> {
        if let Some((frame, skipped)) = search.found {
            let answer = self.answer(frame, base + skipped);
            if search.waiting {
                // A frame that would answer may start inside this one: read on a little.
                self.fallback = Some(answer);
                return None;
            }
            return Some(answer);
        }
        self.corrupt = self.corrupt.take().or(search.corrupt);
        self.foreign = self.foreign.or(search.foreign);
        if search.last_error.is_some() {
            self.last_error = search.last_error;
        }
        if search.waiting {
            return None;
        }
        // Nothing more can come of these bytes: a damaged frame decides now (the drive
        // answered, garbled). Noise, and a frame that answers something else (another
        // station's reply, a late reply to an earlier request), may still be followed by
        // the reply: the mismatch is reported at the deadline if nothing better comes.
        if let Some(error) = self.corrupt.take() {
            return Some(Err(self.fail(TransactionErrorKind::Decode(Box::new(error)))));
        }
        None
    }
}

/// How long to wait at `now` for `needed` more bytes of `char_time` each before reading
/// again: one character less than they take, so the wait ends before the last of them can
/// have arrived even when the master woke up to a character late for the bytes it has;
/// never past `deadline`. `None` when fewer than two are needed (reading at once costs no
/// more).
fn read_ahead_wait(
    needed: usize,
    char_time: Duration,
    now: Instant,
    deadline: Instant,
) -> Option<Duration> {
    if needed < 2 {
        return None;
    }
    let wait = char_time
        .saturating_mul(u32::try_from(needed - 1).unwrap_or(u32::MAX))
        .min(deadline.saturating_duration_since(now));
    (!wait.is_zero()).then_some(wait)
}

/// How long to wait at `now` until `chars` characters of `char_time` each, with a silence
/// of `gap` among them, can have crossed the line since `sent_at` and been handed on, half
/// a character later (the kernel hands a received byte on a fraction of a character after
/// its stop bit: 0.4-0.5 ms on a paced pseudo-terminal at 9600 baud); never past
/// `deadline`. `None` when that time has come. The whole of them: the request's own bytes
/// and the silence put the wait's start behind any byte of the answer, so a master woken on
/// time finds a prompt answer whole and reads it once, without a further wake-up for its
/// last byte.
fn first_wait(
    chars: usize,
    char_time: Duration,
    gap: Duration,
    sent_at: Instant,
    now: Instant,
    deadline: Instant,
) -> Option<Duration> {
    let until = sent_at
        + gap
        + char_time.saturating_mul(u32::try_from(chars).unwrap_or(u32::MAX))
        + char_time / 2;
    let wait = until.min(deadline).saturating_duration_since(now);
    (!wait.is_zero()).then_some(wait)
}

/// The mismatch error for a frame that answers something else than `request`.
fn mismatch_of(difference: Difference, request: &Request) -> TransactionErrorKind {
    TransactionErrorKind::Mismatch {
        field: match difference.role {
            Role::Address => ReplyField::Address,
            Role::Index => ReplyField::Index,
            Role::Data if request.kind.is_write() => ReplyField::Written,
            Role::Data => ReplyField::DataSize,
            _ => ReplyField::Register,
        },
        expected: difference.expected,
        found: difference.found,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_ahead_waits_one_character_less_than_the_bytes_still_needed() {
        let now = Instant::now();
        let char_time = Duration::from_micros(1146);
        let far = now + Duration::from_secs(1);
        assert_eq!(read_ahead_wait(0, char_time, now, far), None);
        assert_eq!(read_ahead_wait(1, char_time, now, far), None);
        assert_eq!(read_ahead_wait(2, char_time, now, far), Some(char_time));
        assert_eq!(read_ahead_wait(7, char_time, now, far), Some(char_time * 6));
        // Never past the deadline, and not at all once it has come.
        let soon = now + Duration::from_millis(2);
        assert_eq!(
            read_ahead_wait(7, char_time, now, soon),
            Some(Duration::from_millis(2))
        );
        assert_eq!(read_ahead_wait(7, char_time, soon, now), None);
    }

    #[test]
    fn first_wait_lasts_until_request_gap_and_shortest_answer_can_have_crossed() {
        let sent = Instant::now();
        let char_time = Duration::from_micros(1146);
        let gap = Duration::from_micros(4010);
        let far = sent + Duration::from_secs(1);
        // 8 request bytes and a 5-byte answer: 13 characters, the gap and half a character.
        assert_eq!(
            first_wait(13, char_time, gap, sent, sent, far),
            Some(gap + char_time * 13 + char_time / 2)
        );
        // Later, what is left; never past the deadline; nothing once the time has come.
        let later = sent + Duration::from_millis(10);
        assert_eq!(
            first_wait(13, char_time, gap, sent, later, far),
            Some(gap + char_time * 13 + char_time / 2 - Duration::from_millis(10))
        );
        let soon = sent + Duration::from_millis(2);
        assert_eq!(
            first_wait(13, char_time, gap, sent, sent, soon),
            Some(Duration::from_millis(2))
        );
        assert_eq!(first_wait(13, char_time, gap, sent, far, far), None);
    }
}
