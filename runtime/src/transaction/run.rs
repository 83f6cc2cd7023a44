//! A transaction from start to end: the write a persistence selector governs goes its own
//! way ([`super::persistence`]); any other request's frames are all prepared first
//! ([`super::script`]), then carried one after the other, and the station's page is
//! remembered or forgotten by what happened.

use super::answer::Answer;
use super::error::TransactionError;
use super::exchange::Exchange;
use super::line::Line;
use super::script::{resets_page, script};
use super::session::Session;
use crate::register::Request;

impl Session {
    /// Runs one request, with any steps the protocol needs first (selecting an array
    /// index, choosing RAM or EEPROM, setting the drive's persistence selector around a
    /// write it governs).
    pub(crate) async fn transact(
        &mut self,
        line: &mut impl Line,
        request: &Request,
    ) -> Result<Answer, TransactionError> {
        if let Some(selector) = self.governing_selector(request) {
            return self.transact_governed(line, request, selector).await;
        }
        self.transact_plain(line, request).await
    }

    /// [`Session::transact`] for a request no persistence selector governs (or whose
    /// selector the caller has set).
    pub(crate) async fn transact_plain(
        &mut self,
        line: &mut impl Line,
        request: &Request,
    ) -> Result<Answer, TransactionError> {
        let request = &match self.port {
            Some(port) => port.map(*request),
            None => *request,
        };
        self.run(line, &Exchange::single(*request)).await
    }

    /// Prepares every frame `exchange` needs, then carries them; the page is forgotten
    /// when anything fails or the request resets it.
    pub(crate) async fn run(
        &mut self,
        line: &mut impl Line,
        exchange: &Exchange,
    ) -> Result<Answer, TransactionError> {
        let request = &exchange.request;
        let known_page = self.known_page(self.address);
        let script = script(self.protocol, exchange, &self.station(), known_page)?;
        let renamed = |error: TransactionError| TransactionError {
            request: Some(*request),
            ..error
        };
        let outcome = async {
            for step in script.steps.iter().flatten() {
                self.exchange(line, step).await?;
            }
            if let Some((step, number)) = &script.page {
                // A failed page switch is reported as the caller's request failing (the
                // page register is not one the caller named).
                self.exchange(line, step).await.map_err(renamed)?;
                self.remember_page(Some(*number));
            }
            self.exchange(line, &script.main).await.map_err(renamed)
        }
        .await;
        if outcome.is_err() || resets_page(self.protocol, request) {
            // A drive that refused, was not heard or was reset may be on any page now.
            self.remember_page(None);
        }
        outcome
    }
}
