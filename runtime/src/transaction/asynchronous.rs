//! The asynchronous master (feature `tokio`): the same typed API as the blocking one, whose
//! requests are futures. It runs the engine both masters share over an
//! [`AsyncTransport`], so every protocol decision (framing, reply search, retries, steps,
//! pages, follow-ups, deadlines from the baud rate) is the blocking master's own.
//!
//! Wrap the transport in [`Async`] to build one: `Master::new(Async(port), ...)`, or name
//! it [`AsyncMaster`].

use super::answer::Answer;
use super::blocks::BlockTransfer;
use super::broadcast::BroadcastReply;
use super::error::TransactionError;
use super::line::Line;
use super::master::{AnyDrive, Master};
use super::reading::Reading;
use crate::broadcast::Broadcast;
use crate::protocol::BlockSelection;
use crate::register::{Persistable, Register, Request, Writable};
use crate::transport::AsyncTransport;
use std::future::Future;
use std::io;
use std::time::{Duration, Instant};

/// Waits shorter than this are not left to tokio's timer, which rounds them up to the next
/// whole millisecond.
const TIMER_RESOLUTION: Duration = Duration::from_millis(1);

/// Lets the runtime run other tasks once (`tokio::task::yield_now` without tokio's `rt`
/// feature, which the library does not need).
struct YieldOnce(bool);

impl Future for YieldOnce {
    type Output = ();

    fn poll(
        mut self: std::pin::Pin<&mut Self>,
        context: &mut std::task::Context<'_>,
    ) -> std::task::Poll<()> {
        if self.0 {
            return std::task::Poll::Ready(());
        }
        self.0 = true;
        context.waker().wake_by_ref();
        std::task::Poll::Pending
    }
}

/// An asynchronous transport, as a [`Master`] takes it: `Master<Async<T>, D>` has the
/// typed API as futures.
#[derive(Debug)]
pub struct Async<T>(pub T);

/// A master over the asynchronous transport `T` (see [`Async`]).
pub type AsyncMaster<T, D = AnyDrive> = Master<Async<T>, D>;

impl<T: AsyncTransport> Line for Async<T> {
    fn send(&mut self, bytes: &[u8]) -> impl Future<Output = io::Result<()>> {
        self.0.send(bytes)
    }

    fn receive(
        &mut self,
        buf: &mut [u8],
        deadline: Instant,
    ) -> impl Future<Output = io::Result<usize>> {
        self.0.receive(buf, deadline)
    }

    fn clear_input(&mut self) -> impl Future<Output = io::Result<()>> {
        self.0.clear_input()
    }

    /// tokio's timer counts whole milliseconds and rounds a wait up to the next one, so a
    /// silence shorter than [`TIMER_RESOLUTION`] (a Modbus RTU gap at 115200 baud is
    /// 0.33 ms) is kept by yielding to the runtime until it has passed.
    async fn sleep(&mut self, duration: Duration) {
        if duration >= TIMER_RESOLUTION {
            tokio::time::sleep(duration).await;
            return;
        }
        let until = Instant::now() + duration;
        while Instant::now() < until {
            YieldOnce(false).await;
        }
    }

    /// A wait shorter than the timer's resolution would cost more than it saves: the
    /// engine reads at once instead.
    async fn nap(&mut self, duration: Duration) {
        if duration >= TIMER_RESOLUTION {
            tokio::time::sleep(duration).await;
        }
    }

    fn last_gap(&self) -> Option<Duration> {
        self.0.last_gap()
    }

    fn allowance(&self) -> Duration {
        self.0.allowance()
    }
}

/// The requests, asynchronously: each runs the shared engine over the asynchronous
/// transport, waiting on the runtime.
impl<T: AsyncTransport, D: 'static> Master<Async<T>, D> {
    /// [`Master::reply_timeout`], asynchronously.
    pub fn reply_timeout(&self, request_len: usize) -> Duration {
        self.session.reply_timeout(request_len) + self.transport.0.allowance()
    }

    /// [`Master::read_reply_delay`], asynchronously.
    pub async fn read_reply_delay(&mut self) -> Result<Duration, TransactionError> {
        self.session.read_reply_delay(&mut self.transport).await
    }

    /// [`Master::read`], asynchronously.
    pub async fn read<R: Register<Drive = D>>(
        &mut self,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>();
        self.session
            .read_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::read_using`], asynchronously.
    pub async fn read_using<R: Register<Drive = D>>(
        &mut self,
        code: u32,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>().using(code);
        self.session
            .read_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::write_percent_of`], asynchronously.
    pub async fn write_percent_of<R: Writable<Drive = D>, F: Register<Drive = D>>(
        &mut self,
        code: u32,
        value: R::Value,
        reference: F::Value,
    ) -> Result<u32, TransactionError> {
        let line = &mut self.transport;
        self.session
            .write_percent_of::<R, F>(line, code, value, reference)
            .await
    }

    /// [`Master::read_at`], asynchronously.
    pub async fn read_at<R: Register<Drive = D>>(
        &mut self,
        index: u16,
    ) -> Result<Reading<R::Value>, TransactionError> {
        let request = Request::read::<R>().at_index(index)?;
        self.session
            .read_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::read_text`], asynchronously.
    pub async fn read_text<R: Register<Drive = D>>(&mut self) -> Result<String, TransactionError> {
        self.session.read_text::<R>(&mut self.transport).await
    }

    /// [`Master::write_ram`], asynchronously.
    pub async fn write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_ram::<R>(value)?;
        self.session
            .write_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::write_ram_at`], asynchronously.
    pub async fn write_ram_at<R: Writable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_ram::<R>(value)?.at_index(index)?;
        self.session
            .write_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::write_persistent`], asynchronously.
    pub async fn write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_persistent::<R>(value)?;
        self.session
            .write_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::write_persistent_at`], asynchronously.
    pub async fn write_persistent_at<R: Persistable<Drive = D>>(
        &mut self,
        index: u16,
        value: R::Value,
    ) -> Result<Option<R::Value>, TransactionError> {
        let request = Request::write_persistent::<R>(value)?.at_index(index)?;
        self.session
            .write_value::<R>(&mut self.transport, &request)
            .await
    }

    /// [`Master::exchange_process`], asynchronously.
    pub async fn exchange_process(
        &mut self,
        control: u16,
        reference: u16,
    ) -> Result<[u16; 2], TransactionError> {
        let line = &mut self.transport;
        self.session
            .exchange_process(line, control, reference)
            .await
    }

    /// [`Master::echo`], asynchronously.
    pub async fn echo(&mut self, data: u16) -> Result<u16, TransactionError> {
        self.session.echo(&mut self.transport, data).await
    }

    /// [`Master::read_words`], asynchronously.
    pub async fn read_words(
        &mut self,
        start: u16,
        words: &mut [u16],
    ) -> Result<Answer, TransactionError> {
        self.session
            .read_words(&mut self.transport, start, words)
            .await
    }

    /// [`Master::write_words`], asynchronously.
    pub async fn write_words(
        &mut self,
        start: u16,
        words: &[u16],
    ) -> Result<Answer, TransactionError> {
        self.session
            .write_words(&mut self.transport, start, words)
            .await
    }

    /// [`Master::block_transfer`], asynchronously.
    pub async fn block_transfer(
        &mut self,
        selection: &BlockSelection,
        writes: &[u16],
        read_count: u8,
    ) -> Result<BlockTransfer, TransactionError> {
        let line = &mut self.transport;
        self.session
            .block_transfer(line, selection, writes, read_count)
            .await
    }

    /// [`Master::transact`], asynchronously.
    pub async fn transact(&mut self, request: &Request) -> Result<Answer, TransactionError> {
        self.session.transact(&mut self.transport, request).await
    }

    /// [`Master::broadcast`], asynchronously.
    pub async fn broadcast(
        &mut self,
        request: &Request,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<Answer>, TransactionError> {
        let line = &mut self.transport;
        self.session.broadcast(line, request, to, reply).await
    }

    /// [`Master::broadcast_write_ram`], asynchronously.
    pub async fn broadcast_write_ram<R: Writable<Drive = D>>(
        &mut self,
        value: R::Value,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self
            .broadcast(&Request::write_ram::<R>(value)?, to, reply)
            .await?;
        super::reading::value_written::<R>(answer.unwrap_or(Answer::NONE))
    }

    /// [`Master::broadcast_write_persistent`], asynchronously.
    pub async fn broadcast_write_persistent<R: Persistable<Drive = D>>(
        &mut self,
        value: R::Value,
        to: Broadcast,
        reply: BroadcastReply,
    ) -> Result<Option<R::Value>, TransactionError> {
        let answer = self
            .broadcast(&Request::write_persistent::<R>(value)?, to, reply)
            .await?;
        super::reading::value_written::<R>(answer.unwrap_or(Answer::NONE))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::CommandKind;

    /// Compiles only if the master's futures can move between threads (`tokio::spawn`).
    #[allow(dead_code)]
    fn futures_are_send<T: AsyncTransport>(master: &mut AsyncMaster<T>) {
        fn send<F: Send>(_: F) {}
        send(master.transact(&Request::raw(CommandKind::Read, 1, 0)));
    }
}
