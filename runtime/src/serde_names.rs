//! Every enumeration a description file names serialises to, and deserialises from,
//! exactly the spelling its `as_str()` (or `symbol()`) gives.

use crate::error::DecodeErrorKind;
use crate::kinds::{Access, CommandKind, DataType, Space, Unit};
use crate::layout::{ChecksumAlgorithm, Format, Role, SizedBy};
use crate::serial::Parity;
use serde::{de::DeserializeOwned, Serialize};
use std::fmt::Debug;

#[track_caller]
fn assert_serde_names<T>(all: &[T], name: impl Fn(&T) -> &'static str)
where
    T: Serialize + DeserializeOwned + PartialEq + Debug,
{
    for value in all {
        let expected = name(value);
        let serialised = yaml_serde::to_value(value).expect("serialises");
        assert_eq!(
            serialised,
            yaml_serde::Value::String(expected.to_owned()),
            "{value:?}"
        );
        let back: T = yaml_serde::from_value(serialised).expect("deserialises");
        assert_eq!(&back, value);
        // As it would appear in a description file.
        let from_text: T = yaml_serde::from_str(&format!("{expected:?}")).expect("parses");
        assert_eq!(&from_text, value);
    }
}

#[test]
fn access() {
    assert_serde_names(&Access::ALL, |v| v.as_str());
    assert_eq!(
        yaml_serde::from_str::<Access>("read-only").unwrap(),
        Access::ReadOnly
    );
}

#[test]
fn data_type() {
    assert_serde_names(&DataType::ALL, |v| v.as_str());
}

#[test]
fn space() {
    assert_serde_names(&Space::ALL, |v| v.as_str());
}

#[test]
fn command_kind() {
    assert_serde_names(&CommandKind::ALL, |v| v.as_str());
}

#[test]
fn unit() {
    assert_serde_names(&Unit::ALL, |v| v.symbol());
    assert_eq!(yaml_serde::from_str::<Unit>("Hz").unwrap(), Unit::Hertz);
    assert_eq!(yaml_serde::from_str::<Unit>("'%'").unwrap(), Unit::Percent);
}

#[test]
fn role() {
    assert_serde_names(&Role::ALL, |v| v.as_str());
}

#[test]
fn format() {
    assert_serde_names(&Format::ALL, |v| v.as_str());
}

#[test]
fn checksum_algorithm() {
    assert_serde_names(&ChecksumAlgorithm::ALL, |v| v.as_str());
}

#[test]
fn sized_by() {
    assert_serde_names(&SizedBy::ALL, |v| v.as_str());
}

#[test]
fn parity() {
    assert_serde_names(&Parity::ALL, |v| v.as_str());
}

#[test]
fn decode_error_kind() {
    assert_serde_names(&DecodeErrorKind::ALL, |v| v.as_str());
}

#[test]
fn layout_data_serialises_with_borrowed_and_owned_lists() {
    use crate::info::ErrorCodeInfo;
    use crate::layout::{FieldSpec, FrameLayout, Part, Presence};
    let layout = FrameLayout {
        name: "read_request".into(),
        encoding: crate::layout::Encoding::Binary,
        plan: None,
        parts: vec![
            Part::Literal {
                name: "start".into(),
                bytes: std::borrow::Cow::Borrowed(b"("),
                optional: false,
            },
            Part::Field(FieldSpec {
                name: "register".into(),
                role: Role::Register,
                format: Format::Hex,
                width: 4,
                min_width: 4,
                optional: Some(Presence::IfByteAtMost(0x3F)),
                allowed: vec![].into(),
                fold_case: false,
                sized_by: SizedBy::Format,
                broadcast: None,
            }),
        ]
        .into(),
    };
    let text = yaml_serde::to_string(&layout).unwrap();
    assert!(text.contains("role: register"), "{text}");
    assert!(text.contains("format: hex"), "{text}");
    assert!(text.contains("!if_byte_at_most 63"), "{text}");
    assert!(text.contains("!literal"), "{text}");
    let entry = ErrorCodeInfo {
        code: 1,
        id: "data_error".into(),
        name: "Data error".into(),
        name_zh: "数据错误".into(),
        meaning: "".into(),
        printed_as: "".into(),
    };
    assert!(yaml_serde::to_string(&entry)
        .unwrap()
        .contains("id: data_error"));
}
