//! Garbage never panics: random bytes and bit-flipped real frames go through every request
//! and reply decoder of every described drive, and through `find_reply`'s noise skipping.
//! The generator is seeded, so a failure reproduces.

use vfd_runtime::protocol::Found;

use vfd_tests::random::Random;

fn decode_everything(protocol: &'static vfd_runtime::Protocol, bytes: &[u8]) {
    let _ = protocol.decode_request(bytes);
    let _ = protocol.decode_request_exact(bytes);
    let _ = protocol.decode_reply(None, bytes);
    let _ = protocol.decode_reply_exact(None, bytes);
    for command in protocol.commands.iter() {
        if let Ok(Found::Frame { frame, .. }) = protocol.find_reply(Some(command), bytes) {
            assert!(frame.len() <= bytes.len());
        }
    }
}

/// Real frames: everything each protocol's own encoder produces for a few requests.
fn seeds(protocol: &'static vfd_runtime::Protocol) -> Vec<Vec<u8>> {
    let mut frames = Vec::new();
    for command in protocol.commands.iter() {
        let request = vfd_runtime::Request {
            space: command.space,
            data_type: command
                .data_types
                .first()
                .copied()
                .unwrap_or(vfd_runtime::DataType::Word),
            ..vfd_runtime::Request::raw(command.kind, 3, 0x1234)
        };
        let mut out = [0u8; 256];
        if let Ok(len) =
            protocol.encode_request(&request, Some(protocol.address_range.0.max(1)), &mut out)
        {
            frames.push(out[..len].to_vec());
        }
    }
    frames
}

#[test]
fn random_bytes_and_mutated_frames_never_panic() {
    let mut random = Random(0x5EED_1234_ABCD_0001);
    let mut frames_tried = 0usize;
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols {
            let seeds = seeds(protocol);
            assert!(
                !seeds.is_empty(),
                "{} {} encodes nothing",
                drive.id,
                protocol.id
            );
            for _ in 0..3000 {
                let len = random.below(48);
                let bytes: Vec<u8> = (0..len).map(|_| random.next_u64() as u8).collect();
                decode_everything(protocol, &bytes);
                let mut mutated = seeds[random.below(seeds.len())].clone();
                let bit = random.below(mutated.len() * 8);
                mutated[bit / 8] ^= 1 << (bit % 8);
                let cut = random.below(mutated.len() + 1);
                decode_everything(protocol, &mutated);
                decode_everything(protocol, &mutated[..cut]);
                frames_tried += 3;
            }
        }
    }
    assert!(frames_tried >= 3 * 3000 * 4);
}

#[test]
fn every_single_bit_flip_of_a_real_frame_is_caught() {
    // A one-bit error anywhere in a checksummed frame must not decode as a valid frame
    // with the same length (binary protocols: sum8, XOR and CRC-16 all catch one bit).
    for (drive, protocol) in [("yd1000", "binary"), ("fc51", "fc"), ("fc51", "modbus")] {
        let protocol = vfd_drives::drive(drive)
            .and_then(|d| d.protocol(protocol))
            .expect("protocol");
        for frame in seeds(protocol) {
            for bit in 0..frame.len() * 8 {
                let mut flipped = frame.clone();
                flipped[bit / 8] ^= 1 << (bit % 8);
                assert!(
                    protocol.decode_request_exact(&flipped).is_err(),
                    "{drive}/{}: flipping bit {bit} of {} still decodes",
                    protocol.id,
                    vfd_runtime::error::hex(&frame)
                );
            }
        }
    }
}
