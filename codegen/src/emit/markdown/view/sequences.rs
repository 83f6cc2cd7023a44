//! Multi-step exchanges: the call, its result and every frame on the line.

use super::error_codes::printed_error;
use super::examples::shown;
use crate::emit::words::value_text;
use crate::ir::*;
use serde::Serialize;

#[derive(Serialize)]
pub(super) struct SequenceView<'a> {
    #[serde(flatten)]
    sequence: &'a crate::ir::SequenceIr,
    register_code: String,
    call_display: String,
    result_display: String,
    steps: Vec<SequenceStepView<'a>>,
}

#[derive(Serialize)]
struct SequenceStepView<'a> {
    number: usize,
    from: &'static str,
    shown: String,
    how: &'static str,
    note: &'a str,
}

pub(super) fn sequence_view<'a>(
    drive: &'a DriveIr,
    sequence: &'a crate::ir::SequenceIr,
) -> SequenceView<'a> {
    use crate::ir::{SequenceCallIr, SequenceResultIr};
    use crate::parse::model::{Sender, Shown};
    let register = drive.register(&sequence.register);
    let code = register.map_or_else(|| sequence.register.clone(), |r| r.code.clone());
    let value = |v: f64| register.map_or_else(|| v.to_string(), |r| value_text(r, v));
    SequenceView {
        sequence,
        call_display: match sequence.call {
            SequenceCallIr::Read => format!("read {code}"),
            SequenceCallIr::Write(v) => format!("write {} to {code}", value(v)),
            SequenceCallIr::WriteRaw(raw) => format!("write the raw word {raw:04X}h to {code}"),
        },
        result_display: match &sequence.result {
            SequenceResultIr::Value(v) => value(*v),
            SequenceResultIr::Written => "written".to_owned(),
            SequenceResultIr::Error(code, id) => {
                let shown = drive
                    .protocols
                    .iter()
                    .find(|p| p.id == sequence.protocol)
                    .map_or_else(
                        || format!("{code:02X}h"),
                        |p| printed_error(drive, p, *code),
                    );
                format!("refused with {shown} `{id}`")
            }
        },
        register_code: code,
        steps: sequence
            .steps
            .iter()
            .enumerate()
            .map(|(index, step)| SequenceStepView {
                number: index + 1,
                from: match step.from {
                    Sender::Master => "master",
                    Sender::Drive => "drive",
                },
                shown: shown(&step.bytes),
                how: match step.shown {
                    Shown::Printed => "printed",
                    Shown::Elided => "elided (略)",
                    Shown::Derived => "not printed",
                },
                note: &step.note,
            })
            .collect(),
    }
}
