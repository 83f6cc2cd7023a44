//! The manual's worked examples: values and their raw words, and example frames with what
//! they mean and how the manual misprinted them.

use crate::parse::model::PrintedRejection;
use serde::Serialize;
use vfd_runtime::meaning::FrameMeaning;
use vfd_runtime::DecodeErrorKind;

/// A worked value example (`80 Hz = 1F40h`).
#[derive(Debug, Clone, Serialize)]
pub struct ValueExampleIr {
    /// Id of the register.
    pub register: String,
    /// Engineering value.
    pub value: f64,
    /// Raw word.
    pub raw: u32,
    /// Manual section.
    pub source: String,
    /// The manual's words.
    pub description: String,
    /// Values of other registers the example assumes: (code, value).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub given: Vec<(String, u32)>,
}

/// One example exchange from the manual.
#[derive(Debug, Clone, Serialize)]
pub struct ExampleIr {
    /// Identifier.
    pub id: String,
    /// Id of the protocol (within the drive).
    pub protocol: String,
    /// Manual section.
    pub source: String,
    /// The manual's words.
    pub description: String,
    /// The manual's Chinese words.
    pub description_zh: String,
    /// The request, when the example has one.
    pub request: Option<FrameIr>,
    /// The reply, when the example has one.
    pub reply: Option<FrameIr>,
    /// The data's value in the register's unit.
    pub value: Option<f64>,
    /// Id of the described register the example's data belongs to, if any.
    pub register: Option<String>,
    /// The example has both frames, and its reply answers its request.
    pub answers: bool,
    /// The manual says nothing comes back to the request (`no_reply: true`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub no_reply: bool,
    /// A request the drive does not answer (the decoder refuses it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ignored_request: Option<UnansweredIr>,
    /// The drive settings the frames assume: (register code, value in its unit).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub settings: Vec<(String, f64)>,
    /// Why the virtual drive cannot give the example's reply, when it cannot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_simulated: Option<String>,
    /// The protocol variant the frames are in (`None`: the first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// The page the drive is on for the frames, on a protocol with pages.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub page: Option<u16>,
}

/// One frame of an example.
#[derive(Debug, Clone, Serialize)]
pub struct FrameIr {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Written as text in the description (`ascii:`).
    pub text: bool,
    /// What the bytes mean, as the runtime's decoder reads them.
    pub meaning: FrameMeaning,
    /// The manual's misprint, when there is an erratum.
    pub printed: Option<PrintedIr>,
}

/// A request the manual prints as one the drive does not answer.
#[derive(Debug, Clone, Serialize)]
pub struct UnansweredIr {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// The decoder's reason for refusing them.
    pub rejected_as: DecodeErrorKind,
    /// The decoder's message.
    pub rejection: String,
    /// Why the drive does not answer, as the manual says.
    pub reason: String,
}

/// Bytes a manual printed wrong.
#[derive(Debug, Clone, Serialize)]
pub struct PrintedIr {
    /// The printed bytes.
    pub bytes: Vec<u8>,
    /// Why they are wrong.
    pub erratum: String,
    /// The decoder's reason for rejecting them, or why they are wrong in their exchange.
    pub rejected_as: PrintedRejection,
    /// The decoder's message.
    pub rejection: String,
    /// The printed bytes as the description writes them (`2F 52 00 10 0064 FA`, the
    /// manual's spacing), for the page; not part of the snapshot.
    #[serde(skip)]
    pub written: String,
}
