//! Check: an example's reply answers its request, as the master judges a reply it receives.

use crate::diagnostics::Diagnostics;
use crate::validate::Context;
use vfd_runtime::protocol::NotAnAnswer;

/// An example giving both frames shows an exchange: its reply must answer its request (the
/// same station, register and index, and the value written). A manual that prints the
/// reply to another request is recorded with `printed:` and
/// `printed_rejected_as: does_not_answer_request`.
pub fn replies_answer_requests(drive: &Context, out: &mut Diagnostics) {
    for (index, decoded) in drive.frames.iter().enumerate() {
        let both_decode = [&decoded.request, &decoded.reply]
            .iter()
            .all(|frame| frame.as_ref().is_some_and(|f| f.decoded().is_some()));
        match &decoded.answers {
            Some(Err(why)) if both_decode && !matches!(why, NotAnAnswer::Request(_)) => out.push(
                drive
                    .source
                    .error(
                        &format!("examples[{index}].reply"),
                        format!("the reply does not answer the request: {why}"),
                    )
                    .hint("if the manual prints the reply to another request, put the right reply here and the printed one under `printed:` with `printed_rejected_as: does_not_answer_request`; if the two frames are separate examples, split them"),
            ),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::replies_answer_requests;
    use crate::validate::testing::{check_yaml, only, valid_with};

    /// The valid drive's example reply, answering a read of 0011h.
    const REPLY: &str = r#"reply: { ascii: "(R00111F40)\r", expect: { command: R, register: 0x0011, data: 0x1F40 } }"#;

    #[test]
    fn a_reply_to_another_register_is_reported_at_the_reply() {
        let yaml = valid_with(&[(
            REPLY,
            r#"reply: { ascii: "(R00121F40)\r", expect: { command: R, register: 0x0012, data: 0x1F40 } }"#,
        )]);
        let diagnostics = check_yaml(replies_answer_requests, &yaml);
        let diagnostic = only(&diagnostics);
        assert_eq!(diagnostic.path, "examples[0].reply");
        assert!(
            diagnostic
                .message
                .contains("register 12h where the request expects 11h"),
            "{}",
            diagnostic.message
        );
    }

    #[test]
    fn the_valid_drives_reply_answers_its_request() {
        assert!(check_yaml(replies_answer_requests, &valid_with(&[])).is_empty());
    }
}
