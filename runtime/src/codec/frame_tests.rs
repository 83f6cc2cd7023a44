//! Frame-level tests of the field, bit-word, length and checksum decoders: whole frames
//! encoded and decoded through the codec (a test-only file above `decode`, so the decoders
//! below it need not use it).

mod decode_checks {
    use crate::codec::sample_layouts::*;
    use crate::codec::{decode, encode, DecodeStatus};
    use crate::error::DecodeError;
    use crate::layout::*;

    #[test]
    fn a_sum_may_stop_before_the_parts_ahead_of_it() {
        let frame = b"\x0200" as &[u8];
        let frame = [frame, b"17702\x0361\r"].concat();
        let layout = etx_outside_the_sum(Some(3));
        let DecodeStatus::Complete { values, len } = decode(&layout, &frame).unwrap() else {
            panic!("incomplete")
        };
        assert_eq!(len, frame.len());
        assert_eq!(values.get(&layout, Role::Data), Some(0x1770));
        let mut out = [0u8; 32];
        let n = encode(&layout, &values, &mut out).unwrap();
        assert_eq!(&out[..n], &frame[..]);
        // Summing through ETX as well gives 64h, not the 61h the manual prints.
        let error = decode(&etx_outside_the_sum(None), &frame).unwrap_err();
        assert_eq!(
            error.kind(),
            crate::error::DecodeErrorKind::ChecksumMismatch
        );
    }

    #[test]
    fn a_wrong_checksum_is_reported_with_both_values() {
        let layout = toshiba_ascii_read();
        let error = decode(&layout, b"(R0000&61)\r").unwrap_err();
        assert!(
            matches!(
                error,
                DecodeError::ChecksumMismatch {
                    computed: 0x60,
                    received: 0x61,
                    ..
                }
            ),
            "{error}"
        );
    }
}

mod decode_fields {
    use crate::codec::sample_layouts::*;
    use crate::codec::{decode, encode_with_payload, DecodeStatus};
    use crate::error::DecodeError;
    use crate::layout::*;

    #[test]
    fn a_command_outside_the_allowed_set_is_rejected_at_its_offset() {
        let layout = toshiba_ascii_read();
        let error = decode(&layout, b"(X0000)\r").unwrap_err();
        assert!(
            matches!(error, DecodeError::NotAllowed { offset: 1, .. }),
            "{error}"
        );
    }

    #[test]
    fn a_words_field_holds_as_many_words_as_its_length_says() {
        let layout = block_reply();
        let frame = [
            0x2F, 0x59, 0x05, 0x00, 0x64, 0x00, 0x17, 0x70, 0x1A, 0x8A, 0x24, 0xFD, 0x00, 0x00,
            0x3D,
        ];
        for end in 0..frame.len() {
            assert_eq!(decode(&layout, &frame[..end]), Ok(DecodeStatus::Incomplete));
        }
        let DecodeStatus::Complete { values, len } = decode(&layout, &frame).unwrap() else {
            panic!("incomplete")
        };
        assert_eq!(len, frame.len());
        let words = values.words(&layout, &frame);
        assert_eq!(words.as_slice(), [0x6400, 0x1770, 0x1A8A, 0x24FD, 0x0000]);
        assert_eq!(values.get(&layout, Role::WriteStatus), Some(0));
        // Encoding computes the count from the words.
        let mut built = FrameValues::default();
        built.set(&layout, Role::Command, u32::from(b'Y'));
        built.set(&layout, Role::WriteStatus, 0);
        let mut out = [0u8; 32];
        let n = encode_with_payload(&layout, &built, &words.payload(&layout), &mut out).unwrap();
        assert_eq!(&out[..n], &frame[..]);
        // No words at all: a count of 0.
        let empty = [0x2F, 0x59, 0x00, 0x00, 0x88];
        let DecodeStatus::Complete { values, .. } = decode(&layout, &empty).unwrap() else {
            panic!("incomplete")
        };
        assert!(values.words(&layout, &empty).as_slice().is_empty());
    }

    #[test]
    fn a_words_field_of_half_a_word_is_refused() {
        // A count is in words here, so a half word cannot arise from it: a length counting
        // bytes can.
        let mut layout = block_reply();
        if let Part::Length(length) = &mut layout.parts.to_mut()[2] {
            length.per = 1;
        }
        let error = decode(&layout, &[0x2F, 0x59, 0x03, 0x00, 0x01, 0x02, 0x03, 0x00]).unwrap_err();
        assert_eq!(error.kind(), crate::error::DecodeErrorKind::LengthMismatch);
    }
}
