//! The typed requests both masters offer, written once: reads and writes of a register of
//! the drive as its typed value, text reads, percentages of another register, process
//! data, the diagnostic echo, and reading the drive's wait before replying.

use super::error::{ReplyField, TransactionError, TransactionErrorKind};
use super::line::Line;
use super::reading::{value_read, value_written, Reading};
use super::session::Session;
use crate::error::{EncodeError, ValueError};
use crate::kinds::CommandKind;
use crate::register::{Register, RegisterValue, Request, Writable};
use std::time::Duration;

impl Session {
    /// Reads `request` (of register `R`) and converts the reply's value.
    pub(crate) async fn read_value<R: Register>(
        &mut self,
        line: &mut impl Line,
        request: &Request,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let answer = self.transact(line, request).await?;
        value_read::<R>(request, answer)
    }

    /// Writes `request` (of register `R`) and converts the value the reply reports.
    pub(crate) async fn write_value<R: Register>(
        &mut self,
        line: &mut impl Line,
        request: &Request,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self.transact(line, request).await?;
        value_written::<R>(answer)
    }

    /// Reads the text register `R`.
    pub(crate) async fn read_text<R: Register>(
        &mut self,
        line: &mut impl Line,
    ) -> Result<String, TransactionError> {
        let answer = self.transact(line, &Request::read::<R>()).await?;
        let (start, len) = answer.text.unwrap_or((0, 0));
        let text = self.last_reply().get(start..start + len).unwrap_or(&[]);
        Ok(String::from_utf8_lossy(text).into_owned())
    }

    /// Sends `value` of register `R` as a percentage of `reference`, register `F`'s value
    /// (see [`super::Master::write_percent_of`]).
    pub(crate) async fn write_percent_of<R: Writable, F: Register>(
        &mut self,
        line: &mut impl Line,
        code: u32,
        value: R::Value,
        reference: F::Value,
    ) -> Result<u32, TransactionError> {
        let protocol = self.protocol;
        let command = protocol
            .commands
            .iter()
            .find(|c| c.answers_to(code) && c.percent_of.is_some());
        let Some((command, percent_of)) =
            command.and_then(|c| c.percent_of.as_ref().map(|p| (c, p)))
        else {
            let request = Request::for_register(CommandKind::WriteRam, R::INFO, 0).using(code);
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::NoSuchCommand {
                    protocol: protocol.id.clone(),
                    code,
                    kind: CommandKind::WriteRam,
                }),
            ));
        };
        let request = Request::for_register(command.kind, R::INFO, 0).using(code);
        if percent_of.register != F::INFO.code && percent_of.register != F::INFO.id {
            return Err(TransactionError::new(
                Some(&request),
                TransactionErrorKind::Encode(EncodeError::NotPercentOf {
                    protocol: protocol.id.clone(),
                    code,
                    register: F::INFO.code,
                }),
            ));
        }
        let value = engineering(value.to_raw(R::INFO)?, R::INFO);
        let reference = engineering(reference.to_raw(F::INFO)?, F::INFO);
        let raw = percent_of
            .to_raw(value, reference)
            .ok_or(ValueError::NotAPercentage {
                register: R::INFO,
                value,
                reference,
            })?;
        self.transact(
            line,
            &Request {
                data: raw,
                ..request
            },
        )
        .await?;
        Ok(raw)
    }

    /// Sends process words and returns those the drive answers with.
    pub(crate) async fn exchange_process(
        &mut self,
        line: &mut impl Line,
        control: u16,
        reference: u16,
    ) -> Result<[u16; 2], TransactionError> {
        let request = Request::process(control, reference);
        let answer = self.transact(line, &request).await?;
        answer.process.ok_or_else(|| {
            TransactionError::new(
                Some(&request),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::ProcessWords,
                    expected: 2,
                    found: 0,
                },
            )
        })
    }

    /// A diagnostic echo of `data` (see [`super::Master::echo`]).
    pub(crate) async fn echo(
        &mut self,
        line: &mut impl Line,
        data: u16,
    ) -> Result<u16, TransactionError> {
        let mut request = Request::raw(CommandKind::Echo, 0, u32::from(data));
        request.wire_register = true;
        request.command = self
            .protocol
            .commands
            .iter()
            .find(|c| c.kind == CommandKind::Echo)
            .map(|c| c.code);
        let answer = self.transact(line, &request).await?;
        Ok(answer.data.map_or(data, |d| d as u16))
    }

    /// Reads the protocol's reply-delay registers (see
    /// [`super::Master::read_reply_delay`]).
    pub(crate) async fn read_reply_delay(
        &mut self,
        line: &mut impl Line,
    ) -> Result<Duration, TransactionError> {
        let Some(delay) = self.protocol.timing.reply_delay.clone() else {
            return Ok(Duration::ZERO);
        };
        let before = self.reply_delay;
        self.reply_delay = Some(delay.max);
        let mut longest = Duration::ZERO;
        for register in delay.registers.iter() {
            let request = Request::raw(CommandKind::Read, *register, 0);
            match self.transact(line, &request).await {
                Ok(answer) => longest = longest.max(delay.of_raw(answer.data.unwrap_or(0))),
                Err(error) => {
                    self.reply_delay = before;
                    return Err(error);
                }
            }
        }
        self.reply_delay = Some(longest);
        Ok(longest)
    }
}

/// A raw value in `info`'s engineering unit (unsigned; for percentages of positive values).
fn engineering(raw: u32, info: &crate::info::RegisterInfo) -> f64 {
    f64::from(raw) * info.scale
}
