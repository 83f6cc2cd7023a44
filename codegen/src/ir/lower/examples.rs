//! Lowers the manual's example frames and multi-step sequences, taking each frame's
//! meaning from the decoding done before validation.

use crate::frames::{register_of, DecodedFrame};
use crate::ir::types::*;
use crate::parse::model::FrameModel;
use crate::validate::Context;
use vfd_runtime::protocol::NotAnAnswer;

/// The sequences, as the checks left them valid (one call, one result, frames that parse).
pub(super) fn lower_sequences(drive: &Context, registers: &[RegisterIr]) -> Vec<SequenceIr> {
    drive
        .model
        .sequences
        .iter()
        .filter_map(|sequence| {
            let call = &sequence.call;
            let name = call.read.as_ref().or(call.write.as_ref())?;
            let id = &drive.model.registers.iter().find(|r| r.is_named(name))?.id;
            let register = registers.iter().find(|r| r.id == *id)?;
            let call_ir = match (&call.read, call.value, call.raw) {
                (Some(_), _, _) => SequenceCallIr::Read,
                (None, Some(value), _) => SequenceCallIr::Write(value),
                (None, None, Some(raw)) => SequenceCallIr::WriteRaw(raw),
                _ => return None,
            };
            let protocol = drive.protocols.iter().find(|p| p.id == sequence.protocol)?;
            let result = &sequence.result;
            let result = match (&result.error, result.value) {
                (Some(id), _) => {
                    let code = protocol
                        .runtime
                        .error_codes
                        .iter()
                        .find(|c| c.id == id.as_str())?;
                    SequenceResultIr::Error(code.code, id.clone())
                }
                (None, Some(value)) => SequenceResultIr::Value(value),
                (None, None) => SequenceResultIr::Written,
            };
            let steps = sequence
                .steps
                .iter()
                .map(|step| {
                    crate::frames::frame_bytes(&step.ascii, &step.hex)
                        .ok()
                        .map(|bytes| SequenceStepIr {
                            from: step.from,
                            bytes,
                            shown: step.shown,
                            note: step.note.clone(),
                        })
                })
                .collect::<Option<Vec<_>>>()?;
            Some(SequenceIr {
                id: sequence.id.clone(),
                protocol: sequence.protocol.clone(),
                source: sequence.source.clone(),
                description: sequence.description.trim().to_owned(),
                description_zh: sequence.description_zh.clone(),
                address: sequence.address,
                register: register.id.clone(),
                call: call_ir,
                persistent: call.persistent,
                selector_given: sequence.given.values().next().copied(),
                result,
                steps,
                variant: sequence.variant.clone(),
                reply_wait: sequence.reply_wait,
            })
        })
        .collect()
}

pub(super) fn lower_examples(drive: &Context, registers: &[RegisterIr]) -> Vec<ExampleIr> {
    drive
        .model
        .examples
        .iter()
        .zip(&drive.frames)
        .map(|(example, decoded)| {
            let frame = |model: &Option<FrameModel>,
                         frame: &Option<DecodedFrame>,
                         answers: Option<&Result<(), NotAnAnswer>>| {
                match (model, frame) {
                    (Some(model), Some(frame)) => lower_frame(model, frame, answers),
                    _ => None,
                }
            };
            let register = decoded
                .reply_then_request()
                .filter_map(DecodedFrame::as_stated)
                .find_map(|meaning| register_of(&drive.model, &meaning))
                .and_then(|found| registers.iter().find(|r| r.id == found.id));
            ExampleIr {
                id: example.id.clone(),
                protocol: example.protocol.clone(),
                source: example.source.clone(),
                description: example.description.clone(),
                description_zh: example.description_zh.clone(),
                request: frame(&example.request, &decoded.request, None),
                reply: frame(
                    &example.reply,
                    &decoded.reply,
                    decoded.printed_answers.as_ref(),
                ),
                answers: decoded.answers.as_ref().is_some_and(Result::is_ok),
                no_reply: example.no_reply,
                ignored_request: match (&example.unanswered_request, &decoded.unanswered) {
                    (Some(model), Some(frame)) => match (&frame.bytes, &frame.meaning) {
                        (Ok(bytes), Some(Err(error))) => Some(UnansweredIr {
                            bytes: bytes.clone(),
                            rejected_as: model.rejected_as,
                            rejection: error.to_string(),
                            reason: model.reason.clone(),
                        }),
                        _ => None,
                    },
                    _ => None,
                },
                value: example.value,
                register: register.map(|r| r.id.clone()),
                settings: example
                    .settings
                    .iter()
                    .map(|(name, value)| {
                        let code = drive
                            .model
                            .registers
                            .iter()
                            .find(|r| r.is_named(name))
                            .map_or_else(|| name.clone(), |r| r.code.clone());
                        (code, *value)
                    })
                    .collect(),
                not_simulated: example.not_simulated.clone(),
                variant: example.variant.clone(),
                page: example.page,
            }
        })
        .collect()
}

/// A frame that validation has accepted: its bytes decoded, and a printed erratum rejected
/// for its stated reason (`printed_answers`: whether the printed reply answers the
/// example's request).
fn lower_frame(
    model: &FrameModel,
    frame: &DecodedFrame,
    printed_answers: Option<&Result<(), NotAnAnswer>>,
) -> Option<FrameIr> {
    let bytes = frame.bytes.clone().ok()?;
    let meaning = frame.decoded()?.clone();
    let printed = match (&frame.printed, model.printed_rejected_as) {
        (Some(printed), Some(rejected_as)) => {
            let rejection = match (&printed.meaning, rejected_as, printed_answers) {
                (Some(Err(error)), _, _) => error.to_string(),
                (Some(Ok(_)), PrintedRejection::DoesNotAnswerRequest, Some(Err(why))) => {
                    why.to_string()
                }
                (Some(Ok(_)), PrintedRejection::ContradictsExpect, _) => {
                    "the frame decodes, but not to what the manual says it means".to_owned()
                }
                _ => return None,
            };
            Some(PrintedIr {
                bytes: printed.bytes.clone().ok()?,
                erratum: model.erratum.clone().unwrap_or_default(),
                rejected_as,
                rejection,
                written: model
                    .printed
                    .as_ref()
                    .and_then(|p| p.hex.as_deref())
                    .map(|hex| hex.split_whitespace().collect::<Vec<_>>().join(" "))
                    .unwrap_or_default(),
            })
        }
        _ => None,
    };
    Some(FrameIr {
        bytes,
        text: model.ascii.is_some(),
        meaning,
        printed,
    })
}
