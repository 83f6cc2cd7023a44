//! A transaction from start to end: the write a persistence selector governs goes its own
//! way ([`super::persistence`]); any other request's frames are all prepared first
//! ([`super::script`]), then carried one after the other, and the station's page is
//! remembered or forgotten by what happened.

use super::answer::Answer;
use super::error::{TransactionError, TransactionErrorKind};
use super::exchange::Exchange;
use super::line::Line;
use super::prepare::{prepare, Prepared};
use super::script::{main_request, resets_page, script_with};
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
        let request = self.on_port(request);
        self.run(line, &Exchange::single(request), None).await
    }

    /// `request` as addressed to the master's port, for drives with several.
    pub(crate) fn on_port(&self, request: &Request) -> Request {
        match self.port {
            Some(port) => port.map(*request),
            None => *request,
        }
    }

    /// The frame [`Session::transact_plain`] sends for `request` (without the page switch or
    /// the steps it may need first), prepared now to be carried later by
    /// [`Session::transact_prepared`].
    pub(crate) fn prepare_plain(&self, request: &Request) -> Result<Prepared, TransactionError> {
        let request = self.on_port(request);
        let main = Exchange::single(main_request(self.protocol, &request));
        prepare(self.protocol, &main, &self.station()).map_err(|error| {
            TransactionError::new(Some(&request), TransactionErrorKind::Encode(error))
        })
    }

    /// [`Session::transact_plain`] for a frame [`Session::prepare_plain`] prepared.
    pub(crate) async fn transact_prepared(
        &mut self,
        line: &mut impl Line,
        prepared: Prepared,
    ) -> Result<Answer, TransactionError> {
        let exchange = Exchange::single(*prepared.request());
        self.run(line, &exchange, Some(prepared)).await
    }

    /// Prepares every frame `exchange` needs (but `main`, when the caller prepared the
    /// request's own frame), then carries them; the page is forgotten when anything fails
    /// or the request resets it.
    pub(crate) async fn run(
        &mut self,
        line: &mut impl Line,
        exchange: &Exchange,
        main: Option<Prepared>,
    ) -> Result<Answer, TransactionError> {
        let request = &exchange.request;
        let known_page = self.known_page(self.address);
        let script = script_with(self.protocol, exchange, &self.station(), known_page, main)?;
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
                log::debug!(
                    target: super::line::LOG_TARGET,
                    "switching station {} to page {number} (was {})",
                    self.address.map_or_else(|| "-".to_owned(), |a| a.to_string()),
                    known_page.map_or_else(|| "not known".to_owned(), |p| p.to_string())
                );
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
