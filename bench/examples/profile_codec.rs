//! Runs the Modbus codec exchange of the benchmark 100,000 times, for profilers (callgrind,
//! perf): `profile_codec [read|write] [interpreter]`. `read` (the default) builds a read of
//! two holding registers and decodes its reply, `write` a write of one register and its
//! echo; `interpreter` does the same through the protocol without plans
//! (`Protocol::without_plans`). Divide callgrind's total by 100,000 for one exchange.

use vfd_runtime::protocol::Found;
use vfd_runtime::{CommandKind, DataType, Protocol, Request};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let generated = vfd_drives::fc51::protocols::MODBUS.protocol();
    let interpreter;
    let protocol: &Protocol = if args.iter().any(|a| a == "interpreter") {
        interpreter = generated.without_plans();
        &interpreter
    } else {
        generated
    };
    let (request, reply): (Request, &[u8]) = if args.iter().any(|a| a == "write") {
        (
            Request {
                wire_register: true,
                ..Request::raw(CommandKind::WriteRam, 0x03F1, 1)
            },
            &[0x01, 0x06, 0x03, 0xF1, 0x00, 0x01, 0x19, 0xBD],
        )
    } else {
        (
            Request {
                wire_register: true,
                ..Request::raw(CommandKind::Read, 0x0BD5, 0).with_data_type(DataType::DoubleWord)
            },
            &[0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B],
        )
    };
    let mut out = [0u8; 64];
    let mut total = 0u64;
    for _ in 0..100_000 {
        let len = protocol
            .encode_request(&request, Some(1), &mut out)
            .expect("encodes");
        total += len as u64;
        let command = protocol.command_for(request.kind, request.space, request.data_type);
        if let Ok(Found::Frame {
            frame: vfd_runtime::Reply::Data { data, .. },
            ..
        }) = protocol.find_reply(command, std::hint::black_box(reply))
        {
            total += u64::from(data);
        }
    }
    println!("{total}");
}
