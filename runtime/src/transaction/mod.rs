//! Request/reply exchanges: run any steps a request needs first, encode, send, collect the
//! reply within a timeout derived from the baud rate, check it answers the request, and
//! map error replies to typed errors.
//!
//! The work is split as sans-IO protocol libraries split it:
//!
//! * **What to send, as bytes** (no I/O): an [`Exchange`] (a request and the kind of
//!   exchange it makes: a single request, a block read or write, a block transfer, a
//!   broadcast) becomes a [`Prepared`] frame with its reply expectation through one
//!   function, [`prepare`] (one command lookup, one encoding); [`script`] prepares all the
//!   frames of a transaction (the protocol's steps, a page switch, the request) before the
//!   first goes out.
//! * **What came back, judged** (no I/O): a [`Judge`] takes the bytes the line delivers
//!   and decides: stale input and the master's own request coming back (an echoing
//!   half-duplex adapter) are skipped, noise and frames that answer something else are
//!   passed over, a silence longer than a frame allows starts a new frame, and of
//!   overlapping frames the one starting last wins.
//! * **The line** (I/O): one engine, written once, carries prepared frames and feeds the
//!   judge; it keeps the frame gap, repeats reads as allowed, sends follow-ups, and never
//!   waits past a reply deadline. The blocking [`Master`] runs it over a
//!   [`crate::transport::Transport`]; the asynchronous master (feature `tokio`) over an
//!   asynchronous transport.
//!
//! A request that gets no reply (a command with `reply: none`, or a write of a register
//! with `no_reply: true`) is done once its frame is on the line: the master waits the
//! frame's wire time and the frame gap, looks for nothing and never repeats it.

mod answer;
#[cfg(feature = "tokio")]
mod asynchronous;
mod blocks;
mod broadcast;
mod engine;
mod error;
mod exchange;
mod judge;
mod line;
mod master;
mod persistence;
mod prepare;
mod reading;
mod run;
mod script;
mod session;
mod typed;

pub use answer::Answer;
#[cfg(feature = "tokio")]
pub use asynchronous::{Async, AsyncMaster};
pub use blocks::{block_word, BlockTransfer};
pub use broadcast::BroadcastReply;
pub use error::{ReplyField, TransactionError, TransactionErrorKind};
pub use exchange::{Exchange, ExchangeKind};
pub use judge::{EchoKnowledge, Judge};
pub use line::LOG_TARGET;
pub use master::{AnyDrive, Master};
pub use prepare::{prepare, FollowUpFrames, FrameBytes, Prepared, Station, MAX_FRAME};
pub use reading::Reading;
pub use script::{script, Script};
