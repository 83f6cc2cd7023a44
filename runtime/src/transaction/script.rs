//! The frames of one transaction, prepared before anything goes on the line: the steps the
//! protocol needs first (an array index, RAM or EEPROM), the page switch a paged register
//! needs, then the request itself. When the protocol cannot carry any of them, the
//! transaction fails before the first is sent.

use super::error::{TransactionError, TransactionErrorKind};
use super::exchange::{Exchange, ExchangeKind};
use super::prepare::{prepare, Prepared, Station};
use crate::kinds::{CommandKind, Space};
use crate::protocol::{PreStep, Protocol};
use crate::register::Request;

/// A transaction's frames, in the order they go out.
#[derive(Debug)]
pub struct Script {
    /// The protocol's steps before the request (at most one index and one persistence
    /// step), each with the request it carries: a failure names the step.
    pub steps: [Option<Prepared>; 2],
    /// The page switch, and the page it selects: a failure names the caller's request.
    pub page: Option<(Prepared, u16)>,
    /// The request itself, as sent (the steps may have taken its index or persistence):
    /// a failure names the caller's request.
    pub main: Prepared,
}

/// Prepares the frames `exchange` needs on `protocol` for `station`, whose page is
/// `known_page` (`None`: unknown, so a paged register selects its page first). Errors name
/// the caller's request, except a step's own, which names the step.
pub fn script(
    protocol: &'static Protocol,
    exchange: &Exchange,
    station: &Station,
    known_page: Option<u16>,
) -> Result<Script, TransactionError> {
    script_with(protocol, exchange, station, known_page, None)
}

/// [`script`], with the request's own frame already prepared (`main`, for the request as
/// sent: see [`main_request`]) when the caller has it.
pub(crate) fn script_with(
    protocol: &'static Protocol,
    exchange: &Exchange,
    station: &Station,
    known_page: Option<u16>,
    main: Option<Prepared>,
) -> Result<Script, TransactionError> {
    let request = &exchange.request;
    let named = |error| TransactionError::new(Some(request), TransactionErrorKind::Encode(error));
    let mut steps: [Option<Prepared>; 2] = [None, None];
    // A block exchange needs no step (it has neither an index nor a persistent kind).
    if exchange.kind == ExchangeKind::Single {
        let mut slots = steps.iter_mut();
        for step in protocol.pre_steps.iter() {
            let Some(step) = step_request(step, request) else {
                continue;
            };
            let prepared =
                prepare(protocol, &Exchange::single(step), station).map_err(|error| {
                    TransactionError::new(Some(&step), TransactionErrorKind::Encode(error))
                })?;
            if let Some(slot) = slots.next() {
                *slot = Some(prepared);
            }
        }
    }
    let page = match page_step(protocol, request, known_page) {
        Some((step, number)) => Some((
            prepare(protocol, &Exchange::single(step), station).map_err(named)?,
            number,
        )),
        None => None,
    };
    let main = match main {
        Some(main) => main,
        None => {
            let main = Exchange {
                request: main_request(protocol, request),
                kind: exchange.kind,
            };
            prepare(protocol, &main, station).map_err(named)?
        }
    };
    Ok(Script { steps, page, main })
}

/// The page switch `request` needs first, with the page it selects: `None` when the
/// register is not paged on this protocol, or its station is known to be on its page.
pub fn page_step(
    protocol: &Protocol,
    request: &Request,
    known_page: Option<u16>,
) -> Option<(Request, u16)> {
    let paging = protocol.paging.as_ref()?;
    if request.wire_register || request.space != Space::Parameter {
        return None;
    }
    let (page, _) = protocol.page_of(request.register)?;
    if known_page == Some(page) {
        return None;
    }
    // The page register's own type picks the command (a byte command's narrower layout
    // where the drive takes two data digits): its plain write, else its only write.
    let data_type = paging.select_data_type;
    let kind = [CommandKind::WriteRam, CommandKind::WritePersistent]
        .into_iter()
        .find(|kind| {
            protocol
                .command_for(*kind, Space::Parameter, data_type)
                .is_some()
        })
        .unwrap_or(CommandKind::WriteRam);
    let step = Request {
        wire_register: true,
        data_type,
        ..Request::raw(kind, paging.select_write, u32::from(page))
    };
    Some((step, page))
}

/// Whether `request` resets the drive's page ([`crate::protocol::Paging::forgotten_after`]).
pub fn resets_page(protocol: &Protocol, request: &Request) -> bool {
    request.kind.is_write()
        && !request.wire_register
        && protocol
            .paging
            .as_ref()
            .is_some_and(|p| p.forgotten_after.contains(&request.register))
}

/// `request` as sent once the protocol's steps have selected what it leaves out.
pub(crate) fn main_request(protocol: &Protocol, request: &Request) -> Request {
    let mut main = *request;
    let has = |kind: fn(&PreStep) -> bool| protocol.pre_steps.iter().any(kind);
    if has(|s| matches!(s, PreStep::Index { .. })) {
        main.index = None;
    }
    if has(|s| matches!(s, PreStep::Persistence { .. }))
        && request.kind == CommandKind::WritePersistent
        && request.space == Space::Parameter
    {
        main.kind = CommandKind::WriteRam;
    }
    main
}

/// The exchange `step` needs before `request`, if it needs one.
pub fn step_request(step: &PreStep, request: &Request) -> Option<Request> {
    match *step {
        PreStep::Index { register } => request.index.map(|index| Request {
            wire_register: true,
            index: None,
            info: None,
            ..Request::raw(CommandKind::WriteRam, register, u32::from(index))
        }),
        // Coil writes (process data) are not parameter writes: no selector for them.
        PreStep::Persistence {
            space,
            register,
            data_type,
            ram,
            persistent,
        } => (request.kind.is_write() && request.space == Space::Parameter).then(|| {
            let value = if request.kind == CommandKind::WritePersistent {
                persistent
            } else {
                ram
            };
            Request::raw(CommandKind::WriteRam, register, value)
                .in_space(space)
                .with_data_type(data_type)
        }),
    }
}
