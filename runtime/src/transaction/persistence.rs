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
use super::exchange::Exchange;
use super::line::Line;
use super::prepare::prepare;
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
        // Nothing goes on the line unless the write and the selector's requests can.
        let main = Request {
            kind: CommandKind::WriteRam,
            ..*request
        };
        for step in [main, selector.write(selector.ram), selector.read()] {
            prepare(self.protocol, &Exchange::single(step), &self.station()).map_err(|error| {
                TransactionError::new(Some(request), TransactionErrorKind::Encode(error))
            })?;
        }
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
        // The write itself goes as the protocol's plain write: the selector says where.
        let main = Request {
            kind: CommandKind::WriteRam,
            ..*request
        };
        if request.kind != CommandKind::WritePersistent {
            if self.selector.value != Some(selector.ram) {
                self.set_selector(line, selector, selector.ram).await?;
            }
            let answer = self.transact_plain(line, &main).await?;
            if own {
                self.selector.value = Some(request.data);
            }
            return Ok(answer);
        }
        let assumed = std::mem::take(&mut self.selector.assumed);
        if self.selector.value != Some(selector.ram) && !assumed {
            self.read_selector(line, selector).await?;
        }
        let before = self.selector.value.unwrap_or(selector.ram);
        if before == selector.persistent {
            let answer = self.transact_plain(line, &main).await?;
            if own {
                self.selector.value = Some(request.data);
            }
            return Ok(answer);
        }
        self.set_selector(line, selector, selector.persistent)
            .await?;
        let answer = self.transact_plain(line, &main).await;
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
                self.set_selector(line, selector, before).await?;
            }
            Err(_) => {}
        }
        answer
    }

    /// Writes `value` to the selector and remembers it.
    async fn set_selector(
        &mut self,
        line: &mut impl Line,
        selector: &PersistenceSelector,
        value: u32,
    ) -> Result<(), TransactionError> {
        self.selector.value = None;
        self.transact_plain(line, &selector.write(value)).await?;
        self.selector.value = Some(value);
        Ok(())
    }

    /// Reads the selector and remembers its value.
    async fn read_selector(
        &mut self,
        line: &mut impl Line,
        selector: &PersistenceSelector,
    ) -> Result<(), TransactionError> {
        let read = selector.read();
        let answer = self.transact_plain(line, &read).await?;
        let value = answer.data.ok_or_else(|| {
            TransactionError::new(
                Some(&read),
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
