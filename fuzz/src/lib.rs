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
