//! The line engine both masters share: carries a prepared frame over a [`Line`] and lets
//! a [`Judge`] decide on what comes back. It keeps the frame gap, drops stale input (and a
//! late reply still due after a timeout) before a request goes out, waits for a reply no
//! longer than its deadline, repeats reads as the master allows and sends follow-ups.
//!
//! A request that gets no reply is done once its frame is on the line: the engine waits
//! the frame's wire time and the frame gap, looks for nothing and never repeats it.
//!
//! What it does is reported through the `log` facade (target `vfd_runtime::line`): each
//! frame sent and each batch of bytes received at trace level (hex, with the milliseconds
//! since the request went out); retries, input dropped before a request and what the line
//! showed about echoes at debug level.

use super::answer::Answer;
use super::error::{TransactionError, TransactionErrorKind};
use super::judge::{EchoKnowledge, Judge};
use super::line::Line;
use super::line::LOG_TARGET;
use super::prepare::{Prepared, MAX_FRAME};
use super::session::Session;
use crate::error::hex;
use std::time::Instant;

impl Session {
    /// One prepared frame, repeated as the master's retries allow (reads only), and the
    /// command's follow-up after a sound reply.
    pub(crate) async fn exchange(
        &mut self,
        line: &mut impl Line,
        prepared: &Prepared,
    ) -> Result<Answer, TransactionError> {
        let mut retries = if prepared.repeatable() {
            self.retries
        } else {
            0
        };
        let mut ask_again = false;
        loop {
            match self.exchange_once(line, prepared, ask_again).await {
                Err(error) if retries > 0 && error.kind.worth_repeating() => {
                    retries -= 1;
                    log::debug!(
                        target: LOG_TARGET,
                        "retrying register {:04X}h after: {error} ({retries} retr{} left)",
                        prepared.request().register,
                        if retries == 1 { "y" } else { "ies" }
                    );
                    // A garbled reply to a command with a follow-up is asked for again (the
                    // drive repeats it); anything else is sent again.
                    ask_again = prepared.follow_up().is_some() && error.kind.garbled_reply();
                }
                Ok(answer) => {
                    if let Some(follow_up) = prepared.follow_up() {
                        self.send_only(line, follow_up.sound.as_slice())
                            .await
                            .map_err(|kind| {
                                TransactionError::new(Some(prepared.request()), kind)
                            })?;
                    }
                    return Ok(answer);
                }
                outcome => return outcome,
            }
        }
    }

    /// Sends a frame nothing answers: done once it is on the line and the gap kept.
    pub(crate) async fn send_only(
        &mut self,
        line: &mut impl Line,
        bytes: &[u8],
    ) -> Result<(), TransactionErrorKind> {
        self.keep_frame_gap(line).await;
        let sent = Instant::now();
        log::trace!(target: LOG_TARGET, "sent {} (no reply expected)", hex(bytes));
        line.send(bytes).await.map_err(TransactionErrorKind::Io)?;
        self.wait_on_line(line, sent, bytes.len()).await;
        Ok(())
    }

    /// One frame out, one reply judged. `ask_again`: in place of the request, the
    /// command's follow-up asking for the last reply again.
    pub(crate) async fn exchange_once(
        &mut self,
        line: &mut impl Line,
        prepared: &Prepared,
        ask_again: bool,
    ) -> Result<Answer, TransactionError> {
        let fail = |kind| TransactionError::new(Some(prepared.request()), kind);
        let sent = match (ask_again, prepared.follow_up()) {
            (true, Some(follow_up)) => follow_up.again.as_slice(),
            _ => prepared.bytes(),
        };
        self.keep_frame_gap(line).await;
        self.discard_stale_input(line)
            .await
            .map_err(|error| fail(TransactionErrorKind::Io(error)))?;
        let sent_at = Instant::now();
        log::trace!(target: LOG_TARGET, "sent {}", hex(sent));
        line.send(sent)
            .await
            .map_err(|error| fail(TransactionErrorKind::Io(error)))?;
        if !prepared.answered() {
            // Nothing comes back: done once the frame is on the line and the gap kept.
            self.wait_on_line(line, sent_at, sent.len()).await;
            self.reply_len = 0;
            return Ok(Answer::NONE);
        }
        let timeout = self.reply_timeout(sent.len()) + line.allowance();
        let deadline = Instant::now() + timeout;
        let mut judge = Judge::new(
            self.protocol,
            prepared,
            sent,
            self.line,
            self.silence_limit(),
        );
        // Where the line reports no silences, the first read waits until a prompt answer
        // can be whole (where it does, frames are split at a silence a batch would hide).
        if line.last_gap().is_none() {
            let (char_time, gap) = (self.settings.char_time(), self.protocol_gap());
            let now = Instant::now();
            if let Some(wait) = judge.first_wait(char_time, gap, sent_at, now, deadline) {
                line.nap(wait).await;
            }
        }
        let outcome = loop {
            // The deadline bounds the loop, however readily the line delivers bytes.
            if Instant::now() >= deadline {
                break judge.at_deadline(timeout);
            }
            let got = line
                .receive(judge.space(), deadline)
                .await
                .map_err(|error| fail(TransactionErrorKind::Io(error)));
            let got = match got {
                Ok(got) => got,
                Err(error) => {
                    self.note_echo(judge.line());
                    return Err(error);
                }
            };
            if got == 0 {
                // A line returns nothing only once the deadline has passed.
                break judge.at_deadline(timeout);
            }
            let now = Instant::now();
            self.last_activity = Some(now);
            log::trace!(
                target: LOG_TARGET,
                "received {} (+{:.1} ms)",
                hex(judge.arrived(got)),
                now.duration_since(sent_at).as_secs_f64() * 1000.0
            );
            if let Some(outcome) = judge.take(got, line.last_gap()) {
                break outcome;
            }
            // Where the line reports silences, bytes are not batched: the engine splits
            // frames at such a silence, which a batch would hide.
            if line.last_gap().is_none() {
                if let Some(wait) = judge.read_ahead(self.settings.char_time(), now, deadline) {
                    line.nap(wait).await;
                }
            }
        };
        self.note_echo(judge.line());
        match &outcome {
            Ok(_) => self.keep_reply(judge.received()),
            Err(TransactionError {
                kind: TransactionErrorKind::Timeout { .. },
                ..
            }) => {
                // What the transport allows for (a network) delays a late reply as well.
                let window = self.late_reply_window() + line.allowance();
                self.late_reply_until = Some(Instant::now() + window);
            }
            Err(_) => {}
        }
        outcome
    }

    /// Takes what an exchange showed about the line's echo, saying so when it changed.
    fn note_echo(&mut self, line: EchoKnowledge) {
        if line.echo != self.line.echo {
            if let Some(echo) = line.echo {
                log::debug!(
                    target: LOG_TARGET,
                    "the line {} the master's requests",
                    if echo { "echoes" } else { "does not echo" }
                );
            }
        }
        self.line = line;
    }

    /// Waits until the frame gap since the last activity on the line has passed.
    pub(crate) async fn keep_frame_gap(&self, line: &mut impl Line) {
        if let Some(last) = self.last_activity {
            let gap = self.frame_gap();
            let since = last.elapsed();
            if since < gap {
                line.sleep(gap - since).await;
            }
        }
    }

    /// Waits until a frame of `len` bytes sent at `sent` is on the line and the frame gap
    /// after it has passed. The line's last activity is the frame's end, so the next frame
    /// does not keep the gap a second time.
    pub(crate) async fn wait_on_line(&mut self, line: &mut impl Line, sent: Instant, len: usize) {
        let on_line = sent + self.settings.wire_time(len);
        let done = on_line + self.frame_gap();
        let now = Instant::now();
        if now < done {
            line.sleep(done - now).await;
        }
        self.last_activity = Some(on_line.min(Instant::now()));
    }

    /// Drops what arrived before the request: a late reply still due (waited for until its
    /// window passes), what the transport can clear, then whatever it still holds (a bounded
    /// amount, so a line full of noise cannot keep it here).
    async fn discard_stale_input(&mut self, line: &mut impl Line) -> std::io::Result<()> {
        let mut scratch = [0u8; MAX_FRAME];
        if let Some(until) = self.late_reply_until.take() {
            let mut dropped = 0usize;
            while Instant::now() < until && dropped < 4 * MAX_FRAME {
                let got = line.receive(&mut scratch, until).await?;
                if got == 0 {
                    break;
                }
                log::trace!(target: LOG_TARGET, "received {} (late)", hex(&scratch[..got]));
                dropped += got;
            }
            if dropped > 0 {
                log::debug!(
                    target: LOG_TARGET,
                    "dropped {dropped} byte(s) of a late reply before the request"
                );
            }
        }
        line.clear_input().await?;
        let now = Instant::now();
        let mut dropped = 0usize;
        while dropped < 4 * MAX_FRAME {
            let got = line.receive(&mut scratch, now).await?;
            if got == 0 {
                break;
            }
            log::trace!(target: LOG_TARGET, "received {} (stale)", hex(&scratch[..got]));
            dropped += got;
        }
        if dropped > 0 {
            log::debug!(
                target: LOG_TARGET,
                "dropped {dropped} stale byte(s) before the request"
            );
        }
        Ok(())
    }
}
