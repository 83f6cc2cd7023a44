//! What differs between an example's reply and the virtual drive's, in the words of the
//! frame: the bytes that differ (where in the frame, the example's and the drive's), and
//! the fields whose values differ, as the protocol's decoder reads both frames.

use super::shown;
use crate::ir::FrameIr;
use vfd_runtime::meaning::{decode_meaning, Direction, FrameMeaning};
use vfd_runtime::Protocol;

/// `bytes 3-6 differ: the example "1770", the virtual drive "0000"; data: the example
/// 1770h, the virtual drive 0h`.
pub(super) fn difference(protocol: &Protocol, expected: &FrameIr, got: &[u8]) -> String {
    let mut said = vec![bytes_differing(expected, got)];
    if let Ok(heard) = decode_meaning(protocol, Direction::Reply, got) {
        said.extend(fields_differing(&expected.meaning, &heard));
    }
    said.join("; ")
}

/// The span of bytes that differ, counted from the start of the frame (the same start and
/// end kept out of it), with both versions of it.
fn bytes_differing(expected: &FrameIr, got: &[u8]) -> String {
    let want = &expected.bytes;
    let start = want.iter().zip(got).take_while(|(a, b)| a == b).count();
    let room = want.len().min(got.len()) - start;
    let same_end = want
        .iter()
        .rev()
        .zip(got.iter().rev())
        .take(room)
        .take_while(|(a, b)| a == b)
        .count();
    let (want_end, got_end) = (want.len() - same_end, got.len() - same_end);
    let span = if want.len() != got.len() {
        format!(
            "the frames differ from byte {start} on ({} bytes where the example has {})",
            got.len(),
            want.len()
        )
    } else if want_end > start + 1 {
        format!("bytes {start}-{} differ", want_end - 1)
    } else {
        format!("byte {start} differs")
    };
    format!(
        "{span}: the example {}, the virtual drive {}",
        shown(expected, &want[start..want_end]),
        shown(expected, &got[start..got_end])
    )
}

/// `data: the example 1770h, the virtual drive 0000h` for each field the two frames
/// give different values.
fn fields_differing(want: &FrameMeaning, got: &FrameMeaning) -> Vec<String> {
    let hex = |value: Option<u32>| value.map_or_else(|| "none".to_owned(), |v| format!("{v:X}h"));
    let fields: [(&str, String, String); 12] = [
        (
            "station",
            hex(want.address.map(u32::from)),
            hex(got.address.map(u32::from)),
        ),
        ("command", hex(want.code), hex(got.code)),
        (
            "register",
            hex(want.wire_register.map(u32::from)),
            hex(got.wire_register.map(u32::from)),
        ),
        (
            "index",
            hex(want.index.map(u32::from)),
            hex(got.index.map(u32::from)),
        ),
        ("data", hex(want.data), hex(got.data)),
        (
            "error code",
            hex(want.error_code.map(u32::from)),
            hex(got.error_code.map(u32::from)),
        ),
        (
            "process words",
            format!("{:X?}", want.process),
            format!("{:X?}", got.process),
        ),
        (
            "text",
            format!("{:?}", want.text),
            format!("{:?}", got.text),
        ),
        (
            "words",
            format!("{:X?}", want.words),
            format!("{:X?}", got.words),
        ),
        ("read count", hex(want.read_count), hex(got.read_count)),
        (
            "write status",
            hex(want.write_status),
            hex(got.write_status),
        ),
        (
            "tripped (lower case)",
            want.tripped.to_string(),
            got.tripped.to_string(),
        ),
    ];
    fields
        .into_iter()
        .filter(|(_, want, got)| want != got)
        .map(|(name, want, got)| format!("{name}: the example {want}, the virtual drive {got}"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(bytes: &[u8]) -> FrameIr {
        FrameIr {
            bytes: bytes.to_vec(),
            text: true,
            meaning: FrameMeaning::default(),
            printed: None,
        }
    }

    #[test]
    fn the_differing_span_is_named_with_both_versions() {
        assert_eq!(
            bytes_differing(&frame(b"\x02001770\x0361\r"), b"\x02000000\x03C0\r"),
            r#"bytes 3-9 differ: the example "1770\x0361", the virtual drive "0000\x03C0""#
        );
        assert_eq!(
            bytes_differing(&frame(b"(R00111F40)"), b"(R00111F41)"),
            r#"byte 9 differs: the example "0", the virtual drive "1""#
        );
        assert_eq!(
            bytes_differing(&frame(b"(R0011)"), b"(R00111F40)"),
            r#"the frames differ from byte 6 on (11 bytes where the example has 7): the example "", the virtual drive "1F40""#
        );
    }

    #[test]
    fn only_the_fields_that_differ_are_named() {
        let want = FrameMeaning {
            address: Some(1),
            data: Some(0x1770),
            ..FrameMeaning::default()
        };
        let got = FrameMeaning {
            address: Some(1),
            data: Some(0),
            ..FrameMeaning::default()
        };
        assert_eq!(
            fields_differing(&want, &got),
            vec!["data: the example 1770h, the virtual drive 0h".to_owned()]
        );
    }
}
