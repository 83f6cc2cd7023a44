//! `vfd encode`: the request frame of a read or a write, by register name with units, as it
//! would go on the line (with the frames the protocol needs first: a page switch, a
//! RAM/EEPROM selection), in hex and, where it is text, as ASCII.

use super::decode::escaped;
use crate::out::say;
use crate::Failure;
use vfd_bus::{lookup, values, Catalogue};
use vfd_runtime::transaction::{script, Exchange, Station};
use vfd_runtime::{CommandKind, DataType, Request};

/// What `vfd encode` builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Action {
    /// Read the register.
    Read,
    /// Write the value in RAM only.
    WriteRam,
    /// Write the value in RAM and EEPROM (EEPROM wears out).
    WritePersistent,
}

/// Options of `vfd encode`.
#[derive(Debug, Clone, Copy)]
pub struct EncodeArgs<'a> {
    /// Drive id or the path of a drive file.
    pub drive: &'a str,
    /// Protocol id.
    pub protocol: &'a str,
    /// What to do.
    pub action: Action,
    /// Register (code, address, id or name).
    pub register: &'a str,
    /// Value, for writes.
    pub value: Option<&'a str>,
    /// Station address.
    pub address: Option<u8>,
    /// A command instead of the protocol's default.
    pub command: Option<&'a str>,
}

/// Prints the request frame for `action` on `register`.
pub fn encode(catalogue: &Catalogue, args: &EncodeArgs) -> Result<(), Failure> {
    let EncodeArgs {
        drive,
        protocol,
        action,
        register,
        value,
        address,
        command,
    } = *args;
    let drive = catalogue.drive(drive)?;
    let protocol = lookup::protocol(drive, Some(protocol))?;
    let register = catalogue.register_for(drive, register, action != Action::Read)?;
    let code = command
        .map(crate::commands::watch::command_code)
        .transpose()?;
    // A command whose data is a percentage of another register takes the value as one.
    let percent_of = code
        .and_then(|code| protocol.commands.iter().find(|c| c.answers_to(code)))
        .and_then(|c| c.percent_of.as_ref());
    let request = match (action, value) {
        (Action::Read, None) => {
            let kind = if register.data_type == DataType::Text {
                CommandKind::ReadText
            } else {
                CommandKind::Read
            };
            Request::for_register(kind, register, 0)
        }
        (Action::Read, Some(_)) => {
            return Err(Failure::new("a read takes no value").hint("leave the value out"))
        }
        (_, None) => {
            return Err(Failure::new("a write needs a value")
                .hint("e.g. `vfd encode yd1000 binary write-ram FA01 60Hz`"))
        }
        (write, Some(value)) => {
            let persist = write == Action::WritePersistent;
            vfd_bus::write_check::writable(register, persist)?;
            let data = match percent_of {
                Some(percent_of) => vfd_bus::write_value::percentage(percent_of, value)?,
                None => values::parse(register, value).map_err(Failure::new)?,
            };
            let kind = if persist {
                CommandKind::WritePersistent
            } else {
                CommandKind::WriteRam
            };
            Request::for_register(kind, register, data)
        }
    };
    let request = match code {
        Some(code) => request.using(code),
        None => request,
    };
    // The frames a master sends for it, built as the master builds them: any step the
    // protocol needs first (array index, RAM/EEPROM, a page switch), then the request.
    let station = Station {
        address,
        reply_wait: 0,
    };
    let script = script(protocol, &Exchange::single(request), &station, None).map_err(|e| {
        let failure = Failure::new(e.to_string());
        if matches!(
            e.kind,
            vfd_runtime::TransactionErrorKind::Encode(
                vfd_runtime::EncodeError::AddressRequired { .. }
            )
        ) {
            failure.hint("give the drive's station address with --address N")
        } else {
            failure
        }
    })?;
    let steps = script.steps.iter().flatten();
    for step in steps.chain(script.page.as_ref().map(|(page, _)| page)) {
        say!("first: {}", step.request().describe());
        print_frame(step.bytes());
    }
    print_frame(script.main.bytes());
    say!("{}", request.describe());
    Ok(())
}

fn print_frame(bytes: &[u8]) {
    say!("hex:   {}", vfd_runtime::error::hex(bytes));
    if bytes
        .iter()
        .all(|b| b.is_ascii_graphic() || matches!(b, b' ' | b'\r' | b'\n'))
    {
        say!("ascii: {}", escaped(bytes));
    }
}
