//! Writes whose storage a register of the drive chooses ([`PersistenceSelector`], the
//! description's `persistence:`; DV1 07-11: 0 RAM and EEPROM, 1 RAM only).
//!
//! The master remembers the selector's value (unknown at first, forgotten after a failed
//! write it governs and when the station changes) and sets it around each governed write:
//!
//! - **RAM write**: unless the selector is known to hold `ram`, write `ram` to it first.
//!   Writing the selector is a parameter write governed by its value before the write, so
//!   when it held `persistent` the EEPROM's copy becomes `ram` too: from then on the drive
//!   starts with parameter writes going to RAM only. No sequence avoids that (the only way
//!   to have RAM-only writes is to write `ram` while `persistent` is in force), and reading
//!   the selector first would not change it, so the master writes without reading.
//! - **Persistent write**: unless the selector is known to hold `ram`, read it. When it
//!   holds `persistent`, the write goes to RAM and EEPROM as it is. Otherwise write
//!   `persistent` (to RAM only, since `ram` is in force), then the value (RAM and EEPROM),
//!   then the selector's old value back (stored in RAM and EEPROM, since `persistent` is in
//!   force; the EEPROM held that value already: the selector can hold `ram` only after
//!   `ram` was written while `persistent` was in force, which stored it, or after a
//!   power-up from the EEPROM). The EEPROM's copy of the selector ends as it was.
//! - A write of the selector itself follows the same rule for its own kind, without
//!   writing the old value back: the caller chose the new one.
//!
//! The master assumes it is the only one changing the selector while it runs
//! ([`super::Master::forget_persistence_selector`] makes it look again). A power cycle keeps a
//! remembered `ram` right (the EEPROM holds it, see above); a remembered `persistent` is
//! read again before each persistent write. Broadcasts are sent as they are.

use super::answer::Answer;
use super::error::{ReplyField, TransactionError, TransactionErrorKind};
use super::line::Line;
use super::prepare::Prepared;
use super::session::Session;
use crate::kinds::CommandKind;
use crate::protocol::PersistenceSelector;
use crate::register::Request;

impl Session {
    /// The drive's persistence selector, when `request` is a write it governs.
    pub(crate) fn governing_selector(
        &self,
        request: &Request,
    ) -> Option<&'static PersistenceSelector> {
        let selector = self.protocol.persistence.as_ref()?;
        selector.governs_request(request).then_some(selector)
    }

    /// Runs the governed write `request` with the selector set around it (see the module
    /// documentation); forgets the selector's value when anything fails.
    pub(crate) async fn transact_governed(
        &mut self,
        line: &mut impl Line,
        request: &Request,
        selector: &PersistenceSelector,
    ) -> Result<Answer, TransactionError> {
        let outcome = self.governed(line, request, selector).await;
        if outcome.is_err() {
            self.selector.value = None;
            self.selector.assumed = false;
        }
        outcome
    }

    async fn governed(
        &mut self,
        line: &mut impl Line,
        request: &Request,
        selector: &PersistenceSelector,
    ) -> Result<Answer, TransactionError> {
        let own = selector.is_selector(request);
        let persistent = request.kind == CommandKind::WritePersistent;
        let assumed = std::mem::take(&mut self.selector.assumed);
        let known = self.selector.value;
        // Every frame this write may send is prepared before the first goes out (page
        // switches excepted: which a paged drive needs follows from the replies before).
        let frames = GovernedFrames::prepare(self, request, selector, known, assumed)?;
        if !persistent {
            if let Some(ram) = frames.ram {
                self.set_selector(line, ram, selector.ram).await?;
            }
            let answer = self.transact_prepared(line, frames.main).await?;
            if own {
                self.selector.value = Some(request.data);
            }
            return Ok(answer);
        }
        if let Some(read) = frames.read {
            self.read_selector(line, read).await?;
        }
        let before = self.selector.value.unwrap_or(selector.ram);
        let (Some(to_persistent), false) = (frames.persistent, before == selector.persistent)
        else {
            let answer = self.transact_prepared(line, frames.main).await?;
            if own {
                self.selector.value = Some(request.data);
            }
            return Ok(answer);
        };
        self.set_selector(line, to_persistent, selector.persistent)
            .await?;
        let answer = self.transact_prepared(line, frames.main).await;
        if own {
            self.selector.value = answer.as_ref().ok().map(|_| request.data);
            return answer;
        }
        // The old value back, also when the drive refused the write (it is still there);
        // after any other failure the drive's state is not known.
        match &answer {
            Ok(_)
            | Err(TransactionError {
                kind: TransactionErrorKind::Rejected { .. },
                ..
            }) => {
                let back = match frames.ram {
                    Some(ram) if before == selector.ram => ram,
                    // A value the description names neither way: prepared when read.
                    _ => self
                        .prepare_plain(&selector.write(before))
                        .map_err(|error| renamed(error, request))?,
                };
                self.set_selector(line, back, before).await?;
            }
            Err(_) => {}
        }
        answer
    }

    /// Sends the selector's write `frame`, of `value`, and remembers the value.
    async fn set_selector(
        &mut self,
        line: &mut impl Line,
        frame: Prepared,
        value: u32,
    ) -> Result<(), TransactionError> {
        self.selector.value = None;
        self.transact_prepared(line, frame).await?;
        self.selector.value = Some(value);
        Ok(())
    }

    /// Sends the selector's read `frame` and remembers the value it reads.
    async fn read_selector(
        &mut self,
        line: &mut impl Line,
        frame: Prepared,
    ) -> Result<(), TransactionError> {
        let answer = self.transact_prepared(line, frame).await?;
        let value = answer.data.ok_or_else(|| {
            TransactionError::new(
                Some(frame.request()),
                TransactionErrorKind::Mismatch {
                    field: ReplyField::Data,
                    expected: 1,
                    found: 0,
                },
            )
        })?;
        self.selector.value = Some(value);
        Ok(())
    }
}

/// The frames a governed write may send, each prepared once before the first is sent.
struct GovernedFrames {
    /// The write itself, as the protocol's plain write.
    main: Prepared,
    /// The selector set to `ram` (before a RAM write; after a persistent one, back).
    ram: Option<Prepared>,
    /// The selector set to `persistent`, before a persistent write.
    persistent: Option<Prepared>,
    /// The selector read, before a persistent write when its value is not known.
    read: Option<Prepared>,
}

impl GovernedFrames {
    /// Prepares what the write `request` may need when the selector is `known` to hold a
    /// value (or the caller `assumed` it); an error names the caller's request.
    fn prepare(
        session: &Session,
        request: &Request,
        selector: &PersistenceSelector,
        known: Option<u32>,
        assumed: bool,
    ) -> Result<GovernedFrames, TransactionError> {
        let prepare = |step: &Request| {
            session
                .prepare_plain(step)
                .map_err(|error| renamed(error, request))
        };
        let main = prepare(&Request {
            kind: CommandKind::WriteRam,
            ..*request
        })?;
        let own = selector.is_selector(request);
        let known_ram = known == Some(selector.ram);
        let ram_write = || prepare(&selector.write(selector.ram));
        let (ram, persistent, read) = if request.kind != CommandKind::WritePersistent {
            ((!known_ram).then(ram_write).transpose()?, None, None)
        } else {
            let read = (!known_ram && !assumed)
                .then(|| prepare(&selector.read()))
                .transpose()?;
            if read.is_none() && known == Some(selector.persistent) {
                // Stated to hold `persistent`: the write goes as it is.
                (None, None, None)
            } else {
                let back = (!own).then(ram_write).transpose()?;
                let persistent = prepare(&selector.write(selector.persistent))?;
                (back, Some(persistent), read)
            }
        };
        Ok(GovernedFrames {
            main,
            ram,
            persistent,
            read,
        })
    }
}

/// `error`, about a frame of the governed write `request`, reported as the write's.
fn renamed(error: TransactionError, request: &Request) -> TransactionError {
    TransactionError {
        request: Some(*request),
        ..error
    }
}
