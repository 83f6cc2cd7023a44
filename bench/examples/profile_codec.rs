//! Runs the Modbus codec exchange in a loop, for profilers (callgrind, perf).

use vfd_runtime::protocol::Found;
use vfd_runtime::{CommandKind, DataType, Request};

fn main() {
    let protocol = vfd_drives::fc51::protocols::MODBUS.protocol();
    let read = Request {
        wire_register: true,
        ..Request::raw(CommandKind::Read, 0x0BD5, 0).with_data_type(DataType::DoubleWord)
    };
    let reply = [0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B];
    let mut out = [0u8; 64];
    let mut total = 0u64;
    for _ in 0..100_000 {
        let len = protocol
            .encode_request(&read, Some(1), &mut out)
            .expect("encodes");
        total += len as u64;
        let command = protocol.command_for(read.kind, read.space, read.data_type);
        if let Ok(Found::Frame {
            frame: vfd_runtime::Reply::Data { data, .. },
            ..
        }) = protocol.find_reply(command, std::hint::black_box(&reply))
        {
            total += u64::from(data);
        }
    }
    println!("{total}");
}
