//! Codec speed: encode a request and decode its reply, per protocol family, and the same
//! Modbus RTU work done by rmodbus, in one run (`cargo bench -p vfd-bench --bench codec`).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rmodbus::client::ModbusRequest;
use rmodbus::ModbusProto;
use vfd_drives::{fc51, yd1000};
use vfd_runtime::protocol::Found;
use vfd_runtime::{CommandKind, DataType, Protocol, Register, RegisterValue, Request};

/// Encodes `request`, decodes `reply`, converts the data: one transaction's codec work.
fn exchange(
    protocol: &'static Protocol,
    request: &Request,
    address: Option<u8>,
    reply: &[u8],
    out: &mut [u8],
) -> u32 {
    let len = protocol
        .encode_request(request, address, out)
        .expect("encodes");
    black_box(&out[..len]);
    let command = protocol.command_for(request.kind, request.space, request.data_type);
    match protocol.find_reply(command, reply).expect("decodes") {
        Found::Frame {
            frame: vfd_runtime::Reply::Data { data, .. },
            ..
        } => data,
        _ => panic!("unexpected reply"),
    }
}

fn per_protocol(c: &mut Criterion) {
    let mut group = c.benchmark_group("codec: encode request + decode reply");
    let mut out = [0u8; 64];
    let read_fd00 = Request::read::<yd1000::registers::OutputFrequencyNow>();
    group.bench_function("toshiba ascii read FD00", |b| {
        b.iter(|| {
            let raw = exchange(
                &yd1000::protocols::ASCII,
                black_box(&read_fd00),
                None,
                b"(RFD001770)\r",
                &mut out,
            );
            <yd1000::registers::OutputFrequencyNow as Register>::Value::from_raw(
                raw,
                yd1000::registers::OutputFrequencyNow::INFO,
            )
        })
    });
    group.bench_function("toshiba binary read FD00", |b| {
        b.iter(|| {
            exchange(
                &yd1000::protocols::BINARY,
                black_box(&read_fd00),
                None,
                &[0x2F, 0x52, 0xFD, 0x00, 0x17, 0x70, 0x05],
                &mut out,
            )
        })
    });
    let read_303 = Request::read::<fc51::registers::MaximumReference>();
    let fc_reply = [
        0x02, 0x0E, 0x01, 0x21, 0x2F, 0x00, 0x00, 0x00, 0x00, 0xEA, 0x60, 0x00, 0x03, 0x00, 0x00,
        0x8A,
    ];
    group.bench_function("fc telegram read 303", |b| {
        b.iter(|| {
            exchange(
                &fc51::protocols::FC,
                black_box(&read_303),
                Some(1),
                &fc_reply,
                &mut out,
            )
        })
    });
    group.bench_function("modbus rtu read 303 (03, 2 registers)", |b| {
        b.iter(|| {
            exchange(
                &fc51::protocols::MODBUS,
                black_box(&read_303),
                Some(1),
                &[0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B],
                &mut out,
            )
        })
    });
    group.finish();
}

/// The same Modbus RTU work for vfd and rmodbus: raw wire registers, no typed conversion.
fn against_rmodbus(c: &mut Criterion) {
    let mut group = c.benchmark_group("modbus rtu: vfd vs rmodbus");
    let protocol = &fc51::protocols::MODBUS;
    let read = Request {
        wire_register: true,
        ..Request::raw(CommandKind::Read, 0x0BD5, 0).with_data_type(DataType::DoubleWord)
    };
    let read_reply = [0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B];
    let write = Request {
        wire_register: true,
        ..Request::raw(CommandKind::WriteRam, 0x03F1, 1)
    };
    let write_reply = [0x01, 0x06, 0x03, 0xF1, 0x00, 0x01, 0x19, 0xBD];
    let mut out = [0u8; 64];
    group.bench_function("vfd: read holding registers (build + parse)", |b| {
        b.iter(|| {
            exchange(
                protocol,
                black_box(&read),
                Some(1),
                black_box(&read_reply),
                &mut out,
            )
        })
    });
    let mut request_buf: Vec<u8> = Vec::with_capacity(256);
    let mut values: Vec<u16> = Vec::with_capacity(8);
    group.bench_function("rmodbus: read holding registers (build + parse)", |b| {
        b.iter(|| {
            let mut mreq = ModbusRequest::new(1, ModbusProto::Rtu);
            request_buf.clear();
            mreq.generate_get_holdings(black_box(0x0BD5), 2, &mut request_buf)
                .expect("builds");
            black_box(&request_buf);
            values.clear();
            mreq.parse_u16(black_box(&read_reply), &mut values)
                .expect("parses");
            (u32::from(values[0]) << 16) | u32::from(values[1])
        })
    });
    group.bench_function("vfd: write single register (build + parse)", |b| {
        b.iter(|| {
            exchange(
                protocol,
                black_box(&write),
                Some(1),
                black_box(&write_reply),
                &mut out,
            )
        })
    });
    group.bench_function("rmodbus: write single register (build + parse)", |b| {
        b.iter(|| {
            let mut mreq = ModbusRequest::new(1, ModbusProto::Rtu);
            request_buf.clear();
            mreq.generate_set_holding(black_box(0x03F1), 1, &mut request_buf)
                .expect("builds");
            black_box(&request_buf);
            mreq.parse_ok(black_box(&write_reply)).expect("parses");
        })
    });
    group.finish();
}

criterion_group!(benches, per_protocol, against_rmodbus);
criterion_main!(benches);
