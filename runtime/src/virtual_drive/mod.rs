//! The virtual drive: the slave side of every described drive and protocol, generated from
//! the same description as the master. It decodes requests with the protocol's layouts and
//! encodes replies with them; the register table gives ranges, access and "writable while
//! running"; the drive's `behaviour:` section ([`crate::behaviour`]) drives a simulated
//! motor on a clock that tests advance. Nothing here names a drive or a protocol.
//!
//! One concern per file: `storage` (RAM, EEPROM, values in effect), `power` (factory state,
//! the simulated clock, power cycles), `panel` (what the operator panel sets and shows),
//! `motor` (the behaviour model), `held` (registers shown at a value), `station` (the
//! station number held in a register), `line` (bytes from the line cut into frames),
//! `whole_frame` (one whole frame handed over), `variants` (the protocol variant in force),
//! `respond` (one request, one reply), `outcome` (a reply or silence, and why a request is
//! refused), `reply` (encoding replies and error replies), `transmission` (what goes on the
//! line for a reply: its wait and faults), `bad_checksum` (requests whose checksum does not
//! match), `unreadable` (frames the drive cannot read, answered with its manual's codes),
//! `data_width` (data of another width than the register's), `broadcast`, `consecutive`
//! (runs of registers), `block` (block transfers), `pages` (paged registers),
//! `unsupported` (function codes the drive does not know), `faults` (misbehaviour on
//! request), `tally` (what a station saw on its line), `simulator` (a drive shared behind a
//! lock), `link` (in-process transport) and `serve` (a loop over any transport, in wall
//! time, for one drive or several stations of a multi-drop bus).
//!
//! In process, a typed master is two lines away:
//!
//! ```text
//! let sim = Simulator::new(&my_drive::DRIVE);
//! let mut master = sim.master(&my_drive::protocols::BINARY);
//! ```
//!
//! (see `vfd_drives::guide` for a complete, tested example).

mod bad_checksum;
mod block;
mod broadcast;
mod consecutive;
mod data_width;
mod faults;
mod held;
mod line;
mod link;
mod motor;
mod outcome;
mod pages;
mod panel;
mod power;
mod reply;
mod respond;
mod serve;
mod simulator;
mod station;
mod storage;
mod tally;
mod transmission;
mod unreadable;
mod unsupported;
mod variants;
mod whole_frame;

pub use faults::Fault;
pub use link::SimLink;
pub use outcome::{Outcome, Refusal};
pub use serve::{same_framing, serve, serve_bus, BusStation};
pub use simulator::Simulator;
pub use tally::Tally;
pub use transmission::Transmission;

use crate::drive::DriveInfo;
use crate::info::RegisterInfo;
use motor::Motor;
use std::collections::VecDeque;
use std::time::Duration;
use storage::Storage;

/// A simulated drive: its registers, its motor, its clock and the faults it is told to
/// commit. Use it through a [`Simulator`] (shared between a test and its master).
#[derive(Debug)]
pub struct VirtualDrive {
    drive: &'static DriveInfo,
    address: u8,
    storage: Storage,
    motor: Motor,
    now: Duration,
    selected_index: u16,
    persistent_writes: bool,
    faults: VecDeque<Fault>,
    noise: bool,
    echo: bool,
    requests: u64,
    /// What happened on the line to this station ([`Tally`]).
    tally: Tally,
    /// Unplugged from its bus: it neither answers nor acts on frames.
    unplugged: bool,
    /// The simulated time until which it starts up after a power cycle, answering nothing.
    silent_until: Duration,
    /// The last request of a command whose lower case speaks of its sender said the sender
    /// (a master inverter) has tripped.
    sender_tripped: bool,
    /// Bytes that were no frame came since the line was last silent: where the protocol
    /// says so, they reject the frame that follows ([`crate::serial::BeforeStart`]).
    garbage: bool,
    /// The serial port it serves (a port id of the description's `ports`): that port's
    /// copies of the behaviour's registers act. `None`: the registers as the behaviour
    /// names them.
    port: Option<&'static str>,
    /// The page it is on, on a protocol with pages (`None`: the protocol's initial page).
    page: Option<u16>,
    /// The command code and bytes of the last reply, while its master's follow-up is
    /// awaited ([`crate::protocol::FollowUp`]).
    awaiting_follow_up: Option<(u32, Vec<u8>)>,
    /// Registers shown at a value whatever the behaviour model computes
    /// ([`VirtualDrive::hold`]), until a power cycle.
    held: Vec<(&'static RegisterInfo, u32)>,
    /// Unreadable frames for this station in a row, since the last it could read
    /// ([`crate::behaviour::Refusals::retries_exceeded`]).
    unreadable_in_a_row: u32,
}
