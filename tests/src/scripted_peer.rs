//! A scripted peer for transaction tests: reads one request frame at a time with the
//! protocol's decoder and answers with whatever bytes the test supplies.

use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use vfd_runtime::protocol::Found;
use vfd_runtime::transport::Transport;
use vfd_runtime::Protocol;

/// Starts a thread that, for each entry of `replies`, waits for one complete request on
/// `transport`, records it, and sends the entry's bytes (nothing for an empty entry); then
/// it listens until the line has been quiet for 200 ms. The handle returns the requests
/// received, as raw bytes.
pub fn answer<T: Transport + Send + 'static>(
    mut transport: T,
    protocol: &'static Protocol,
    replies: Vec<Vec<u8>>,
) -> JoinHandle<Vec<Vec<u8>>> {
    std::thread::spawn(move || {
        let mut received = Vec::new();
        for reply in replies {
            let mut buffer = Vec::new();
            let deadline = Instant::now() + Duration::from_secs(5);
            loop {
                let mut chunk = [0u8; 64];
                let got = transport.receive(&mut chunk, deadline).unwrap_or(0);
                if got == 0 {
                    return received;
                }
                buffer.extend_from_slice(&chunk[..got]);
                // Bytes before the request (a master's follow-up to the last reply) are
                // skipped.
                if let Ok(Found::Frame { frame, skipped }) = protocol.decode_request(&buffer) {
                    received.push(buffer[skipped..skipped + frame.len].to_vec());
                    break;
                }
            }
            if !reply.is_empty() {
                let _ = transport.send(&reply);
            }
        }
        // Stay on the line until it is quiet, so the master's follow-up to the last reply
        // (an Eaton C) finds a listener.
        let mut chunk = [0u8; 64];
        while transport
            .receive(&mut chunk, Instant::now() + Duration::from_millis(200))
            .unwrap_or(0)
            > 0
        {}
        received
    })
}
