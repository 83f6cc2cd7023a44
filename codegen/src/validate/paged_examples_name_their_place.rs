//! Check: an example on a protocol with pages whose request carries an offset on a page
//! (not a register's own number, not the page register) states which page it is on
//! (`page`), the register the offset reaches there (`expect.register`, compared with what
//! the frame decodes to on that page by `examples_decode`) and, where a frame carries the
//! register's data in an exchange the drive carries out (not refused), its value
//! (`value`); and a `page` is one the protocol lays registers on, given only for such a
//! request.

use crate::diagnostics::Diagnostics;
use crate::frames::{frame_bytes, page_offset};
use crate::validate::Context;

/// Paged examples name their page, register and value.
pub fn paged_examples_name_their_place(drive: &Context, out: &mut Diagnostics) {
    for (index, example) in drive.model.examples.iter().enumerate() {
        let base = format!("examples[{index}]");
        let Some(at) = drive.frames[index].protocol else {
            continue; // an unknown protocol is reported where it is named
        };
        let protocol = &drive.protocols[at].runtime;
        let runtime = example
            .variant
            .as_deref()
            .and_then(|id| crate::frames::in_variant(protocol, id));
        let runtime = runtime.as_ref().unwrap_or(protocol);
        let mut problem = |key: &str, message: String, hint: &str| {
            out.push(
                drive
                    .source
                    .error(&format!("{base}{key}"), message)
                    .hint(hint),
            );
        };
        let Some(paging) = &runtime.paging else {
            if example.page.is_some() {
                problem(
                    ".page",
                    format!("protocol `{}` has no pages", example.protocol),
                    "leave `page` out: the protocol reaches every register by its number",
                );
            }
            continue;
        };
        let offset = example
            .request
            .as_ref()
            .and_then(|frame| frame_bytes(&frame.ascii, &frame.hex).ok())
            .and_then(|bytes| page_offset(runtime, &bytes));
        match (example.page, offset) {
            (Some(page), _) if !paging.has_page(page) => problem(
                ".page",
                format!("page {page} is not one of the protocol's pages"),
                "name a page the drive's `pages.ranges` lay registers on",
            ),
            (Some(_), None) => problem(
                ".page",
                "the request carries no offset on a page (a register's own number, the page register, or no request)".to_owned(),
                "leave `page` out, or give the request whose register field is an offset on the page",
            ),
            (None, Some(offset)) => problem(
                "",
                format!(
                    "the request's register field is an offset on a page ({offset:02X}h after the address map), but the example does not say which page"
                ),
                "state the page the manual's example is on (`page: 1`), the register the offset reaches there (`expect.register`) and, where a frame carries data, its value (`value`)",
            ),
            (Some(page), Some(offset)) => {
                let Some(register) = paging.register(page, offset) else {
                    problem(
                        ".page",
                        format!("offset {offset:02X}h on page {page} reaches no register of the protocol's page ranges"),
                        "check the page against the manual's page table",
                    );
                    continue;
                };
                let stated = example.request.as_ref().and_then(|f| f.expect.register);
                if stated.is_none() {
                    problem(
                        ".request.expect",
                        format!("the request reaches register {register:04X}h on page {page}, which `expect` does not name"),
                        &format!("name it: `register: {register:#06X}` (before the address map)"),
                    );
                }
                // The data of an exchange the drive carries out (a refused write's data is
                // no value of the register).
                let frames = &drive.frames[index];
                let refused = frames
                    .reply
                    .as_ref()
                    .and_then(crate::frames::DecodedFrame::decoded)
                    .is_some_and(|reply| reply.error_code.is_some());
                let carries_data = frames
                    .reply_then_request()
                    .filter_map(crate::frames::DecodedFrame::decoded)
                    .any(|meaning| meaning.data.is_some());
                if carries_data && !refused && example.value.is_none() {
                    problem(
                        "",
                        format!("the frames carry register {register:04X}h's data on page {page}, but the example states no `value`"),
                        "give the data's value in the register's unit (`value: 60.0`), as the manual's example says it",
                    );
                }
            }
            (None, None) => {}
        }
    }
}
