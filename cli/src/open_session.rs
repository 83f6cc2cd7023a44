//! The one-drive session of `vfd read`, `write`, `watch`, `backup` and `restore`, opened
//! from the options every bus command shares ([`crate::line_args`]).

use crate::line_args::{line_settings, LineArgs};
use crate::traced_line::Traced;
use crate::Failure;
use std::time::Duration;
use vfd_bus::session::Session;
use vfd_bus::{lookup, Catalogue};
use vfd_runtime::transaction::Master;

/// A session with the drive the options name, on the line they open (traced on standard
/// error with `--trace`).
pub fn open_session(args: &LineArgs, catalogue: &Catalogue) -> Result<Session, Failure> {
    let drive = catalogue.drive(&args.drive)?;
    let protocol = lookup::protocol(drive, args.protocol.as_deref())?;
    let protocol = lookup::variant(protocol, args.variant.as_deref())?;
    let settings = line_settings(drive, &protocol.id, args.format())?;
    let mut line = vfd_bus::line::open(&args.port, &settings)?;
    if args.trace {
        line = Traced::on_stderr(line, drive, protocol);
    }
    let mut timing = drive.serial.timing;
    if let Some(ms) = args.timeout {
        timing.processing_allowance = Duration::from_millis(ms);
    }
    let address = match args.address {
        Some(address) => Some(address),
        None => protocol.default_address(),
    };
    let port = lookup::port(drive, args.port_kind.as_deref())?;
    let mut master = Master::for_protocol(line, protocol, settings, timing)
        .with_address(address)
        .with_port(port)
        .with_retries(args.retries.unwrap_or(0));
    if let Some(ms) = args.gap_ms {
        master = master.with_min_gap(Duration::from_millis(ms));
    }
    if let Some(ms) = args.host_latency_ms {
        master = master.with_host_latency(Duration::from_millis(ms));
    }
    let mut session = Session::with_master(drive, protocol, settings, master, address);
    session.port = port;
    session.drive_name = catalogue.name_for(drive);
    Ok(session)
}
