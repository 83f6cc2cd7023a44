//! A connection to one drive on a line (the one-drive session of `vfd read`, `write`,
//! `watch`, `backup` and `restore`, and each station of `vfd serve`): a master on a line,
//! and raw reads and writes through the runtime's untyped request path, so any described
//! drive works.

use crate::session_error::SessionError;

use crate::{write_check, Line};
use vfd_runtime::serial::SerialSettings;
use vfd_runtime::transaction::Master;
use vfd_runtime::{
    CommandKind, DataType, DriveInfo, EncodeError, Port, Protocol, RegisterInfo, Request,
    TransactionError, TransactionErrorKind,
};

/// What a read returned.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    /// The raw word or double word (absent for text).
    pub raw: Option<u32>,
    /// Text, for text parameters.
    pub text: Option<String>,
    /// The reply said the drive is tripped.
    pub tripped: bool,
    /// The decimal places the reply stated (the Eaton unit digit), checked against the
    /// register's scales by the master.
    pub decimals: Option<u8>,
}

/// A master talking to one drive.
pub struct Session {
    /// The drive.
    pub drive: &'static DriveInfo,
    /// The protocol spoken.
    pub protocol: &'static Protocol,
    /// The line settings in use.
    pub settings: SerialSettings,
    master: Master<Line>,
    /// Requests sent so far (each read or write, a block of registers counting once).
    pub requests: usize,
    /// The station addressed (`None`: no address sent).
    address: Option<u8>,
    /// The command code reads and writes name (`--command`), where the protocol has
    /// several for their kind; `None`: the protocol's default.
    pub command: Option<u32>,
    /// The drive's port the line is on, when the drive has several and one was named.
    pub port: Option<Port>,
    /// How a command line names the drive so that it is found again (its id, or the path
    /// of its drive file).
    pub drive_name: String,
}

impl crate::OnLine for Session {
    fn master(&mut self) -> &mut Master<Line> {
        &mut self.master
    }
}

impl Session {
    /// `info` as this session reaches it: its copy on the session's port (itself when
    /// the register is not per port or no port was named).
    pub fn on_port(&self, info: &'static RegisterInfo) -> &'static RegisterInfo {
        self.port.map_or(info, |port| port.register(info))
    }

    /// `info` with the scale its selector register chooses now (`scale_by`), reading the
    /// selector first (or, when the selector cannot be read, the register itself, if its
    /// reply states its decimals); `info` itself when its scale is fixed.
    pub fn scaled(
        &mut self,
        info: &'static RegisterInfo,
    ) -> Result<&'static RegisterInfo, SessionError> {
        let Some(scale_by) = info.scale_by else {
            return Ok(info);
        };
        let Some(selector) = self.drive.register(scale_by.register) else {
            return Ok(info);
        };
        let value = match self.read(selector) {
            Ok(value) => value,
            Err(failure) => {
                // The selector may not be reachable over this protocol (DV1 00-08 has no
                // Eaton code): a read of the register itself whose reply states its
                // decimals (the Eaton unit digit) gives the scale instead.
                if info.access != vfd_runtime::kinds::Access::WriteOnly {
                    if let Some(chosen) = self
                        .read(info)
                        .ok()
                        .and_then(|own| own.decimals)
                        .and_then(|decimals| info.scaled_for_decimals(decimals))
                    {
                        return Ok(chosen);
                    }
                }
                return Err(failure.with_hint(format!(
                    "the scale of {} depends on {}, which could not be read",
                    info.code, selector.code
                )));
            }
        };
        match value.raw.and_then(|raw| scale_by.choice(raw)) {
            Some(chosen) => Ok(chosen),
            None => Err(SessionError::Said(
                crate::SetupError::new(format!(
                    "{} = {} chooses no scale the description knows for {}",
                    selector.code,
                    value
                        .raw
                        .map_or_else(|| "(no data)".to_owned(), |raw| raw.to_string()),
                    info.code
                ))
                .with_hint("the description's `scale_by` lists the values it knows"),
            )),
        }
    }

    /// A session over `master` (built by the caller: `vfd serve` builds one per station of
    /// a bus, whose [`crate::Bus`] lends each its line in turn).
    pub fn with_master(
        drive: &'static DriveInfo,
        protocol: &'static Protocol,
        settings: SerialSettings,
        master: Master<Line>,
        address: Option<u8>,
    ) -> Session {
        Session {
            drive,
            protocol,
            settings,
            master,
            requests: 0,
            address,
            command: None,
            port: None,
            drive_name: drive.id.to_owned(),
        }
    }

    /// A session over an in-process line (the demo's virtual drive).
    #[cfg_attr(not(all(unix, feature = "pty")), allow(dead_code))] // used by the demo only
    pub fn over(
        drive: &'static DriveInfo,
        protocol: &'static Protocol,
        line: Line,
        address: Option<u8>,
    ) -> Session {
        let settings = drive.serial.default_for(&protocol.id);
        let master = Master::for_protocol(line, protocol, settings, drive.serial.timing)
            .with_address(address);
        Session::with_master(drive, protocol, settings, master, address)
    }

    /// `request`, carried by the `--command` code when one was given.
    fn using(&self, request: Request) -> Request {
        match self.command {
            Some(code) => request.using(code),
            None => request,
        }
    }

    /// The protocol's command named by the `--command` code, if one was given.
    pub fn named_command(&self) -> Option<&'static vfd_runtime::CommandSpec> {
        let code = self.command?;
        self.protocol.commands.iter().find(|c| c.answers_to(code))
    }

    /// Reads `info`.
    pub fn read(&mut self, info: &'static RegisterInfo) -> Result<Value, SessionError> {
        let info = self.on_port(info);
        let text = info.data_type == DataType::Text;
        let kind = if text {
            CommandKind::ReadText
        } else {
            CommandKind::Read
        };
        let request = self.using(Request::for_register(kind, info, 0));
        self.requests += 1;
        let answer = self
            .master
            .transact(&request)
            .map_err(|e| self.failure(e))?;
        if text {
            let (start, len) = answer.text.unwrap_or((0, 0));
            let reply = self.master.last_reply();
            let text = reply
                .get(start..start + len)
                .map(|bytes| String::from_utf8_lossy(bytes).trim_end().to_owned())
                .unwrap_or_default();
            return Ok(Value {
                raw: None,
                text: Some(text),
                tripped: answer.tripped,
                decimals: None,
            });
        }
        let raw = answer.data.ok_or_else(|| {
            SessionError::said(format!(
                "the reply to the read of {} carries no data",
                info.label()
            ))
        })?;
        Ok(Value {
            raw: Some(raw),
            text: None,
            tripped: answer.tripped,
            decimals: answer.decimals,
        })
    }

    /// Writes the raw value `raw` to `info`, in RAM or, with `persist`, in RAM and
    /// EEPROM. Returns the value the drive reports written, when its reply carries one,
    /// and whether it said it is tripped.
    pub fn write(
        &mut self,
        info: &'static RegisterInfo,
        raw: u32,
        persist: bool,
    ) -> Result<(Option<u32>, bool), SessionError> {
        let info = self.on_port(info);
        write_check::writable(info, persist)?;
        self.check_combinations(info, raw)?;
        let kind = if persist {
            CommandKind::WritePersistent
        } else {
            CommandKind::WriteRam
        };
        let request = self.using(Request::for_register(kind, info, raw));
        self.requests += 1;
        let answer = self
            .master
            .transact(&request)
            .map_err(|error| match error.request {
                Some(step) if (step.space, step.register) != (request.space, request.register) => {
                    self.step_failure(info, persist, &step, error)
                }
                _ => self.failure(error),
            })?;
        Ok((answer.data, answer.tripped))
    }

    /// A write of `info` that failed at a step the master sends first (the persistence
    /// selector, a RAM/EEPROM or index selection): named after `info`, saying which step
    /// failed and why it is sent, with the drive's code and meaning.
    fn step_failure(
        &self,
        info: &'static RegisterInfo,
        persist: bool,
        step: &Request,
        error: TransactionError,
    ) -> SessionError {
        let step_name = self
            .drive
            .register_for(step.space, step.register, true)
            .map_or_else(|| format!("register {:04X}h", step.register), |r| r.label());
        let target = crate::storage::target(info, persist);
        let why = match &self.protocol.persistence {
            Some(selector) if (selector.space, selector.register) == (step.space, step.register) => {
                let to = if step.data == selector.ram {
                    "RAM only"
                } else {
                    "RAM and EEPROM"
                };
                format!("setting the persistence selector {step_name} to {} ({to}), which decides where the write goes", step.data)
            }
            _ => format!("writing {step_name} = {}, which the protocol sends first to choose where the write goes", step.data),
        };
        // Whether the drive refused the step as it refuses a write while the motor runs
        // (its code for that, where the description gives one); a step that got no
        // answer, or another refusal, has nothing to do with the motor.
        let refused_while_running = match &error.kind {
            TransactionErrorKind::Rejected { code, .. } => {
                let said = self.drive.behaviour.and_then(|b| {
                    b.refusals
                        .iter()
                        .find(|r| r.protocol == self.protocol.id)
                        .and_then(|r| r.while_running)
                });
                said.is_none_or(|while_running| while_running == *code)
            }
            _ => false,
        };
        let refused = matches!(error.kind, TransactionErrorKind::Rejected { .. });
        let cause = self.failure(error);
        let said = crate::SetupError::new(format!(
            "cannot write {} ({target}): the step before it {}: {why}; {}",
            info.label(),
            if refused { "was refused" } else { "failed" },
            cause.message()
        ));
        let said = if !info.writable_while_running
            && !info.while_running_unknown
            && refused_while_running
        {
            said.with_hint(format!(
                "the manual allows {} to change only while the motor is stopped: stop it first (the drive refuses the first frame of the write)",
                info.code
            ))
        } else if let Some(hint) = cause.hint() {
            said.with_hint(hint)
        } else {
            said
        };
        SessionError::Said(said)
    }

    /// Refuses a write of `raw` to `info` that would make a combination of values the
    /// manual forbids, reading the other registers of each combination first
    /// ([`crate::write_check::combinations`]).
    fn check_combinations(
        &mut self,
        info: &'static RegisterInfo,
        raw: u32,
    ) -> Result<(), SessionError> {
        let drive = self.drive;
        write_check::combinations(drive, info, raw, |other| self.read_if_readable(other))
            .map_err(SessionError::from)
    }

    /// The raw value of `info` when it can be read over this protocol and it reads; `None`
    /// otherwise (what a write check takes as unknown).
    pub fn read_if_readable(&mut self, info: &'static RegisterInfo) -> Option<u32> {
        if !self.can_read(info) {
            return None;
        }
        self.read(info).ok().and_then(|value| value.raw)
    }

    /// Runs one block transfer with `selection` (see `vfd block`).
    pub fn block_transfer(
        &mut self,
        selection: &vfd_runtime::BlockSelection,
        writes: &[u16],
        read_count: u8,
    ) -> Result<vfd_runtime::BlockTransfer, SessionError> {
        self.requests += 1;
        self.master
            .block_transfer(selection, writes, read_count)
            .map_err(|e| self.failure(e))
    }

    /// Broadcasts a write of `raw` to `info` (see `Master::broadcast`): returns the value
    /// the answering station reports written (when `reply_from` names one) and the station
    /// the description says answers, if any.
    pub fn broadcast_write(
        &mut self,
        info: &'static RegisterInfo,
        raw: u32,
        persist: bool,
        to: vfd_runtime::Broadcast,
        reply_from: Option<u8>,
    ) -> Result<(Option<u32>, Option<u8>), SessionError> {
        write_check::writable(info, persist)?;
        let kind = if persist {
            CommandKind::WritePersistent
        } else {
            CommandKind::WriteRam
        };
        let request = Request::for_register(kind, info, raw);
        let reply = match reply_from {
            Some(station) => vfd_runtime::transaction::BroadcastReply::From(station),
            None => vfd_runtime::transaction::BroadcastReply::None,
        };
        let responder = self.protocol.broadcast_responder(&request, &to);
        self.requests += 1;
        let answer = self
            .master
            .broadcast(&request, to, reply)
            .map_err(|e| self.failure(e))?;
        Ok((answer.and_then(|a| a.data), responder))
    }

    /// Reads every register of `registers`, consecutive ones together where the protocol
    /// reads several registers in one request (its `max_words_per_read`); the others, and a
    /// block the drive refuses, one request each. Results are in the order given.
    pub fn read_many(
        &mut self,
        registers: &[&'static RegisterInfo],
    ) -> Vec<Result<Value, SessionError>> {
        self.read_runs(registers, false)
    }

    /// [`Session::read_many`], stopping at the first request the drive does not answer
    /// (or answers only with damaged replies), or the line fails: the registers not yet
    /// read get that failure, without a request of their own, so a station that stopped
    /// answering costs one reply timeout per round, not one per register.
    pub fn read_many_until_silent(
        &mut self,
        registers: &[&'static RegisterInfo],
    ) -> Vec<Result<Value, SessionError>> {
        self.read_runs(registers, true)
    }

    fn read_runs(
        &mut self,
        registers: &[&'static RegisterInfo],
        stop_when_silent: bool,
    ) -> Vec<Result<Value, SessionError>> {
        let mut results: Vec<Option<Result<Value, SessionError>>> =
            registers.iter().map(|_| None).collect();
        let mut silent: Option<SessionError> = None;
        for run in vfd_runtime::read_runs::read_runs(self.protocol, registers) {
            if let Some(failure) = &silent {
                for index in &run {
                    results[*index] = Some(Err(failure.clone()));
                }
                continue;
            }
            if run.len() > 1 {
                match self.read_block(registers, &run) {
                    Ok(values) => {
                        for (index, value) in run.iter().zip(values) {
                            results[*index] = Some(Ok(value));
                        }
                        continue;
                    }
                    // The drive did not answer, or the line failed: reading the registers
                    // one by one would only wait as long again for each.
                    Err(failure) if !refused(&failure) => {
                        for index in &run {
                            results[*index] = Some(Err(failure.clone()));
                        }
                        if stop_when_silent {
                            silent = Some(failure);
                        }
                        continue;
                    }
                    // The drive refused the block (a register in it it will not read
                    // together): each one on its own.
                    Err(_) => {}
                }
            }
            for index in run {
                if let Some(failure) = &silent {
                    results[index] = Some(Err(failure.clone()));
                    continue;
                }
                let result = self.read(registers[index]);
                if stop_when_silent {
                    if let Err(failure) = &result {
                        if !refused(failure) {
                            silent = Some(failure.clone());
                        }
                    }
                }
                results[index] = Some(result);
            }
        }
        results
            .into_iter()
            .map(|r| r.unwrap_or_else(|| Err(SessionError::said("not read"))))
            .collect()
    }

    /// Reads the registers of one run in one request.
    fn read_block(
        &mut self,
        registers: &[&'static RegisterInfo],
        run: &[usize],
    ) -> Result<Vec<Value>, SessionError> {
        let widths: Vec<usize> = run
            .iter()
            .map(|i| vfd_runtime::read_runs::block_words(registers[*i]))
            .collect();
        let mut words = vec![0u16; widths.iter().sum()];
        self.requests += 1;
        let answer = self
            .master
            .read_words(registers[run[0]].address, &mut words)
            .map_err(|e| self.failure(e))?;
        let mut at = 0;
        Ok(widths
            .iter()
            .map(|width| {
                let raw = self.master.join_words(&words[at..at + width]);
                at += width;
                Value {
                    raw: Some(raw),
                    text: None,
                    tripped: answer.tripped,
                    decimals: None,
                }
            })
            .collect())
    }

    /// Changes how often a failed read is repeated from now on.
    pub fn set_retries(&mut self, retries: u8) {
        self.master.set_retries(retries);
    }

    /// Whether `info` can be read over the session's protocol ([`Protocol::can_read`]).
    pub fn can_read(&self, info: &RegisterInfo) -> bool {
        self.protocol.can_read(info)
    }

    /// For a protocol with variants, the one in use and the others (`, variant cr (the
    /// drive may be set to cr_lf: --variant)`); empty otherwise.
    fn variant_hint(&self) -> String {
        let Some(variants) = &self.protocol.variants else {
            return String::new();
        };
        let current = self.protocol.variant_id().unwrap_or("");
        let others: Vec<&str> = variants
            .choices
            .iter()
            .map(|v| v.id.as_ref())
            .filter(|id| *id != current)
            .collect();
        format!(
            ", variant {current} (the drive may be set to {}: --variant)",
            others.join(" or ")
        )
    }

    /// A transaction error for people, with a hint where one helps.
    fn failure(&self, error: TransactionError) -> SessionError {
        let hint = match &error.kind {
            TransactionErrorKind::Timeout { .. } => Some(format!(
                "check baud rate, parity and station address: {} baud {}, protocol {}, \
                 station {} (--baud, --parity, --data-bits, --stop-bits{}, --address){}, and the \
                 wiring; a slow drive may need --timeout",
                self.settings.baud,
                self.settings.format_label(),
                self.protocol.id,
                self.address_text(),
                // A drive of one protocol needs no --protocol.
                if self.drive.protocols.len() > 1 {
                    ", --protocol"
                } else {
                    ""
                },
                self.variant_hint()
            )),
            TransactionErrorKind::Encode(EncodeError::UnsupportedCommand {
                kind,
                space,
                data_type,
                ..
            }) => crate::storage::missing_write_hint(
                self.drive,
                self.protocol,
                *kind,
                *space,
                *data_type,
            )
            .or_else(|| {
                let others: Vec<&str> = self
                    .drive
                    .protocols
                    .iter()
                    .filter(|p| p.id != self.protocol.id)
                    .filter(|p| p.command_for(*kind, *space, *data_type).is_some())
                    .map(|p| p.id.as_ref())
                    .collect();
                (!others.is_empty()).then(|| format!("try --protocol {}", others.join(" or ")))
            }),
            TransactionErrorKind::Io(io)
                if matches!(
                    io.kind(),
                    std::io::ErrorKind::ConnectionAborted
                        | std::io::ErrorKind::ConnectionReset
                        | std::io::ErrorKind::NotConnected
                ) =>
            {
                Some(
                    "the connection to the device server was lost; the next request connects again"
                        .to_owned(),
                )
            }
            TransactionErrorKind::Io(_) => Some("is the port still there?".to_owned()),
            TransactionErrorKind::Decode(_) => Some(
                "the reply arrived damaged: check the wiring, termination, baud rate and parity"
                    .to_owned(),
            ),
            _ => None,
        };
        SessionError::Exchange(crate::Error::from_transaction(&error).with_hint_or_none(hint))
    }

    fn address_text(&self) -> String {
        match self.address {
            Some(address) => address.to_string(),
            None => "none".to_owned(),
        }
    }
}

impl Session {
    /// After a RAM write of `info`: one line saying that the protocol's persistence
    /// selector (the description's `persistence.selector`) was set to its RAM value on the
    /// way, where it governs the write (the master sets it and leaves it so). `None` where
    /// no selector is involved.
    pub fn selector_note(&self, info: &RegisterInfo) -> Option<String> {
        let selector = self.protocol.persistence.as_ref()?;
        if !selector.governs(info.space, info.address, info.ram_only) {
            return None;
        }
        let name = self
            .drive
            .register_at(selector.space, selector.register)
            .map_or_else(
                || format!("register {:04X}h", selector.register),
                |r| format!("{} ({})", r.code, r.name),
            );
        Some(format!(
            "note: a RAM write sets the persistence selector {name} to {} (RAM only), and the drive keeps it (in EEPROM too where it held {}): parameter writes from anywhere go to RAM only until it is set back",
            selector.ram, selector.persistent
        ))
    }
}

/// Whether a failed block read is the drive's refusal (an error reply) or a request the
/// protocol could not make, as opposed to no answer, a damaged one or a failed line.
fn refused(failure: &SessionError) -> bool {
    failure
        .exchange()
        .is_some_and(|error| error.kind().worth_splitting())
}
