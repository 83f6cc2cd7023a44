//! What the fuzz targets run: each decoder of a protocol on arbitrary bytes, and the
//! description reader on arbitrary text. A panic, a hang or an out-of-memory is a finding;
//! errors are the expected outcome for most inputs.

use std::path::Path;
use vfd_runtime::Protocol;

/// Every request decoder of `protocol` on `data`.
pub fn requests(protocol: &'static Protocol, data: &[u8]) {
    let _ = protocol.decode_request(data);
    let _ = protocol.decode_request_exact(data);
}

/// Every reply decoder of `protocol` on `data`: without an expected command, with each
/// command expected, and the search that skips noise before a reply.
pub fn replies(protocol: &'static Protocol, data: &[u8]) {
    let _ = protocol.decode_reply(None, data);
    let _ = protocol.find_reply(None, data);
    if let Some((&selector, rest)) = data.split_first() {
        if !protocol.commands.is_empty() {
            let command = &protocol.commands[usize::from(selector) % protocol.commands.len()];
            let _ = protocol.decode_reply(Some(command), rest);
            let _ = protocol.find_reply(Some(command), rest);
            let _ = protocol.decode_reply_exact(Some(command), rest);
        }
    }
}

/// The description reader, validator and IR on `data` as a drive file (with the described
/// protocol files), then the Rust and Markdown emitters when it is valid.
pub fn description(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let protocols = Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives/protocols");
    if let Ok(drive) =
        vfd_codegen::compile_text(Path::new("fuzz.yaml"), text.to_owned(), Some(&protocols))
    {
        let _ = vfd_codegen::rust_tokens(&drive);
    }
}

/// The virtual drive's request handling on `data`: the first byte picks the drive and the
/// protocol, the rest is the line input, answered whole and as a stream.
pub fn virtual_drive(data: &[u8]) {
    let Some((&selector, frame)) = data.split_first() else {
        return;
    };
    let drives = &vfd_drives::ALL_DRIVES;
    let drive = drives[usize::from(selector) % drives.len()];
    if drive.protocols.is_empty() {
        return;
    }
    let protocol = drive.protocols[usize::from(selector >> 4) % drive.protocols.len()];
    let mut simulated = vfd_runtime::virtual_drive::VirtualDrive::new(drive);
    let _ = simulated.respond(protocol, frame);
    let mut input = frame.to_vec();
    let _ = simulated.receive(protocol, &mut input);
    simulated.advance(std::time::Duration::from_millis(u64::from(selector) * 100));
    let _ = simulated.respond(protocol, frame);
}

/// Every protocol of every described drive in each of its variants, with the same
/// protocol without plans (the interpreter alone), built once.
fn protocol_pairs() -> &'static [(&'static Protocol, Protocol)] {
    static PAIRS: std::sync::OnceLock<Vec<(&'static Protocol, Protocol)>> =
        std::sync::OnceLock::new();
    PAIRS.get_or_init(|| {
        vfd_drives::ALL_DRIVES
            .iter()
            .flat_map(|drive| drive.protocols.iter())
            .flat_map(|protocol| protocol.all_variants())
            .map(|protocol| (protocol, protocol.without_plans()))
            .collect()
    })
}

/// The fast path (the layouts' plans) against the interpreter on the same bytes: the first
/// byte picks the protocol, the second the command; the rest is decoded as a reply and as a
/// request by both, and a request made from the first bytes is encoded by both. Any
/// difference panics (a finding), as does a plan that decodes a frame the interpreter
/// decodes otherwise.
pub fn plan_agreement(data: &[u8]) {
    let [selector, pick, rest @ ..] = data else {
        return;
    };
    let pairs = protocol_pairs();
    let (fast, slow) = &pairs[usize::from(*selector) % pairs.len()];
    let (fast, slow): (&'static Protocol, &Protocol) = (fast, slow);
    assert_eq!(fast.decode_request(rest), slow.decode_request(rest));
    assert_eq!(fast.decode_reply(None, rest), slow.decode_reply(None, rest));
    assert_eq!(fast.find_reply(None, rest), slow.find_reply(None, rest));
    if fast.commands.is_empty() {
        return;
    }
    let index = usize::from(*pick) % fast.commands.len();
    // The request's flags and data type from what `pick` left after choosing the command,
    // so that every command meets every flag.
    let flags = (usize::from(*pick) / fast.commands.len()) as u8;
    let (a, b) = (&fast.commands[index], &slow.commands[index]);
    assert_eq!(fast.decode_reply(Some(a), rest), slow.decode_reply(Some(b), rest));
    assert_eq!(fast.find_reply(Some(a), rest), slow.find_reply(Some(b), rest));
    assert_eq!(
        fast.decode_reply_exact(Some(a), rest),
        slow.decode_reply_exact(Some(b), rest)
    );
    let expectation = vfd_runtime::protocol::Expectation::default();
    assert_eq!(
        fast.search_reply(a, &expectation, rest),
        slow.search_reply(b, &expectation, rest)
    );
    let layouts = [Some(&a.request), Some(&a.reply), fast.error_reply.as_ref()];
    for layout in layouts.into_iter().flatten() {
        let Some(plan) = &layout.plan else { continue };
        let planned = plan.decode(layout, rest);
        assert_eq!(planned, plan.decode_steps(layout, rest));
        if let Some(frame) = planned {
            assert_eq!(
                vfd_runtime::codec::decode(layout, rest),
                Ok(vfd_runtime::codec::DecodeStatus::Complete {
                    values: frame.values,
                    len: frame.len
                })
            );
            assert_eq!(frame.roles, frame.values.roles(layout));
        }
    }
    // A request of the picked command, its numbers taken from the bytes.
    let number = |at: usize| {
        rest.get(at..at + 4)
            .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let data_type = a
        .data_types
        .get(usize::from(flags >> 4) % a.data_types.len().max(1))
        .copied()
        .unwrap_or(vfd_runtime::DataType::Word);
    let request = vfd_runtime::Request {
        wire_register: flags & 0x08 != 0,
        index: (flags & 0x04 != 0).then_some(number(8) as u16),
        command: (flags & 0x02 != 0).then_some(a.code),
        ..vfd_runtime::Request::raw(a.kind, number(0) as u16, number(4))
            .in_space(a.space)
            .with_data_type(data_type)
    };
    let address = (flags & 0x01 != 0).then(|| rest.first().copied().unwrap_or(0));
    let size = rest.get(1).map_or(64, |n| usize::from(*n % 64));
    let (mut x, mut y) = (vec![0u8; size], vec![0u8; size]);
    let encoded = fast.encode_request(&request, address, &mut x);
    assert_eq!(encoded, slow.encode_request(&request, address, &mut y));
    if let Ok(len) = encoded {
        assert_eq!(x[..len], y[..len]);
    }
}
