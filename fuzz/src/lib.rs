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
