//! Codec speed: encode a request and decode its reply, per protocol family, and the same
//! Modbus RTU work done by rmodbus, in one run (`cargo bench -p vfd-bench --bench codec`).
//!
//! Every vfd row calls what a user of the generated API calls (`Protocol::encode_request`,
//! `Protocol::command_for`, `Protocol::find_reply`) on the generated protocol statics, whose
//! layouts hold plans the generator compiled. Each `[interpreter]` row does the same work on
//! the same protocol with its plans taken out (`Protocol::without_plans`): what every frame
//! cost before plans, and what a layout no plan covers costs. At the end the run prints a
//! summary of every row and the ratios, all from this run's measurements.

use criterion::{black_box, criterion_group, Criterion};
use rmodbus::client::ModbusRequest;
use rmodbus::ModbusProto;
use vfd_drives::{dv1, fc51, vf_as1, yd1000};
use vfd_runtime::codec;
use vfd_runtime::protocol::Found;
use vfd_runtime::{
    CommandKind, DataType, FrameValues, Protocol, Register, RegisterValue, Request, Roles,
};

/// Encodes `request`, decodes `reply`, converts the data: one transaction's codec work.
fn exchange(
    protocol: &Protocol,
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

/// The same protocol without plans, for the `[interpreter]` rows (kept for the whole run).
fn interpreter(protocol: &Protocol) -> &'static Protocol {
    Box::leak(Box::new(protocol.without_plans()))
}

/// The reply `protocol` gives to `request` from station `address` carrying `data`, as the
/// interpreter writes it (for families whose replies are not written out below).
fn reply_to(protocol: &Protocol, request: &Request, address: Option<u8>, data: u32) -> Vec<u8> {
    let command = protocol.command_for_request(request).expect("a command");
    let layout = &command.reply;
    let mut values = FrameValues {
        data_size: request.data_type.size(),
        ..FrameValues::default()
    };
    for name in protocol.default_optional_parts.iter() {
        values.include(layout, &[name]);
    }
    values.fill(
        layout,
        &Roles {
            address: address.map(u32::from),
            command: Some(command.reply_codes.first().copied().unwrap_or(command.code)),
            register: Some(u32::from(request.register)),
            index: Some(0),
            data: Some(data),
            error_code: None,
            process_1: Some(0),
            process_2: Some(0),
            decimals: Some(2),
        },
    );
    let mut out = [0u8; 64];
    let len = codec::encode(layout, &values, &mut out).expect("a reply");
    out[..len].to_vec()
}

/// A read of `register` as it goes on the wire.
fn raw_read(register: u16, data_type: DataType) -> Request {
    Request {
        wire_register: true,
        ..Request::raw(CommandKind::Read, register, 0).with_data_type(data_type)
    }
}

/// One row per protocol family (and per described drive's use of it), through the
/// generated protocol and through the interpreter.
fn per_protocol(c: &mut Criterion) {
    let mut group = c.benchmark_group("codec: encode request + decode reply");
    let mut out = [0u8; 64];
    fn row(
        group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
        name: &str,
        protocol: &'static Protocol,
        request: Request,
        address: Option<u8>,
        reply: Vec<u8>,
    ) {
        let mut out = [0u8; 64];
        let slow = interpreter(protocol);
        assert_eq!(
            exchange(protocol, &request, address, &reply, &mut out),
            exchange(slow, &request, address, &reply, &mut out),
            "{name}: both paths decode the same data"
        );
        group.bench_function(name, |b| {
            b.iter(|| {
                exchange(
                    protocol,
                    black_box(&request),
                    address,
                    black_box(&reply),
                    &mut out,
                )
            })
        });
        group.bench_function(format!("{name} [interpreter]"), |b| {
            b.iter(|| {
                exchange(
                    slow,
                    black_box(&request),
                    address,
                    black_box(&reply),
                    &mut out,
                )
            })
        });
    }
    // Typed, with the value converted: what the generated API's users do.
    let read_fd00 = Request::read::<yd1000::registers::OutputFrequencyNow>();
    for (name, protocol) in [
        (
            "toshiba ascii (yd1000) read FD00, typed",
            yd1000::protocols::ASCII.protocol(),
        ),
        (
            "toshiba ascii (yd1000) read FD00, typed [interpreter]",
            interpreter(yd1000::protocols::ASCII.protocol()),
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let raw = exchange(
                    protocol,
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
    }
    row(
        &mut group,
        "toshiba binary (yd1000) read FD00",
        yd1000::protocols::BINARY.protocol(),
        read_fd00,
        None,
        vec![0x2F, 0x52, 0xFD, 0x00, 0x17, 0x70, 0x05],
    );
    let read_303 = Request::read::<fc51::registers::MaximumReference>();
    row(
        &mut group,
        "fc telegram (fc51) read 303",
        fc51::protocols::FC.protocol(),
        read_303,
        Some(1),
        vec![
            0x02, 0x0E, 0x01, 0x21, 0x2F, 0x00, 0x00, 0x00, 0x00, 0xEA, 0x60, 0x00, 0x03, 0x00,
            0x00, 0x8A,
        ],
    );
    row(
        &mut group,
        "modbus rtu (fc51) read 303 (03, 2 registers)",
        fc51::protocols::MODBUS.protocol(),
        read_303,
        Some(1),
        vec![0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B],
    );
    // The manual's frames (vf-as1.yaml examples).
    row(
        &mut group,
        "toshiba ascii (vf-as1) read 0000",
        vf_as1::protocols::ASCII.protocol(),
        raw_read(0x0000, DataType::Word),
        Some(2),
        b"(02R00000000)\r".to_vec(),
    );
    let protocol = vf_as1::protocols::BINARY.protocol();
    let request = raw_read(0xFA01, DataType::Word);
    row(
        &mut group,
        "toshiba binary (vf-as1) read FA01",
        protocol,
        request,
        None,
        reply_to(protocol, &request, None, 0x1770),
    );
    row(
        &mut group,
        "modbus rtu (vf-as1) read FD00",
        vf_as1::protocols::MODBUS.protocol(),
        raw_read(0xFD00, DataType::Word),
        Some(1),
        vec![0x01, 0x03, 0x02, 0x17, 0x70, 0xB6, 0x50],
    );
    // DV1 (dv1.yaml examples): Modbus ASCII has no plan (hex pairs), both rows interpret.
    row(
        &mut group,
        "modbus ascii (dv1) read 00C3",
        dv1::protocols::MODBUS_ASCII.protocol(),
        raw_read(0x00C3, DataType::Word),
        Some(1),
        b":010302177073\r\n".to_vec(),
    );
    row(
        &mut group,
        "eaton ascii (dv1) read 5F (02-15 on its page)",
        dv1::protocols::EATON.protocol(),
        raw_read(0x5F, DataType::Word),
        Some(0),
        b"\x020017702\x0361\r".to_vec(),
    );
    group.finish();
}

/// The same Modbus RTU work for vfd and rmodbus: raw wire registers, no typed conversion.
fn against_rmodbus(c: &mut Criterion) {
    let mut group = c.benchmark_group("modbus rtu: vfd vs rmodbus");
    let protocol = fc51::protocols::MODBUS.protocol();
    let slow = interpreter(protocol);
    let read = raw_read(0x0BD5, DataType::DoubleWord);
    let read_reply = [0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B];
    let write = Request {
        wire_register: true,
        ..Request::raw(CommandKind::WriteRam, 0x03F1, 1)
    };
    let write_reply = [0x01, 0x06, 0x03, 0xF1, 0x00, 0x01, 0x19, 0xBD];
    let mut out = [0u8; 64];
    for (name, protocol) in [("vfd", protocol), ("vfd interpreter", slow)] {
        group.bench_function(
            format!("{name}: read holding registers (build + parse)"),
            |b| {
                b.iter(|| {
                    exchange(
                        protocol,
                        black_box(&read),
                        Some(1),
                        black_box(&read_reply),
                        &mut out,
                    )
                })
            },
        );
    }
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
    for (name, protocol) in [("vfd", protocol), ("vfd interpreter", slow)] {
        group.bench_function(
            format!("{name}: write single register (build + parse)"),
            |b| {
                b.iter(|| {
                    exchange(
                        protocol,
                        black_box(&write),
                        Some(1),
                        black_box(&write_reply),
                        &mut out,
                    )
                })
            },
        );
    }
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

/// Criterion's mean estimate of one benchmark of this run, in nanoseconds, from the files
/// it writes (`target/criterion/<group>/<benchmark>/new/estimates.json`).
fn mean_ns(group: &str, bench: &str) -> Option<f64> {
    // As criterion names its folders: some characters replaced, at most 64 bytes.
    let clean = |s: &str| {
        let mut name: String = s
            .chars()
            .map(|c| if "?\"/\\*<>:|^".contains(c) { '_' } else { c })
            .collect();
        if name.len() > 64 {
            let mut end = 64;
            while !name.is_char_boundary(end) {
                end -= 1;
            }
            name.truncate(end);
        }
        name.trim().to_owned()
    };
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"));
    let path = target
        .join("criterion")
        .join(clean(group))
        .join(clean(bench))
        .join("new/estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let mean = &text[text.find("\"mean\"")?..];
    let value = &mean[mean.find("\"point_estimate\":")? + "\"point_estimate\":".len()..];
    let end = value.find([',', '}'])?;
    value[..end].trim().parse().ok()
}

/// Prints every row of this run and the ratios the benchmarks are for.
fn summary() {
    println!("\nSummary of this run (criterion mean estimates):");
    let group = "codec: encode request + decode reply";
    let rows = [
        "toshiba ascii (yd1000) read FD00, typed",
        "toshiba binary (yd1000) read FD00",
        "fc telegram (fc51) read 303",
        "modbus rtu (fc51) read 303 (03, 2 registers)",
        "toshiba ascii (vf-as1) read 0000",
        "toshiba binary (vf-as1) read FA01",
        "modbus rtu (vf-as1) read FD00",
        "modbus ascii (dv1) read 00C3",
        "eaton ascii (dv1) read 5F (02-15 on its page)",
    ];
    println!("| Protocol family (drive) | Work | vfd | vfd interpreter | interpreter / vfd |");
    println!("|---|---|---|---|---|");
    for name in rows {
        let (fast, slow) = (
            mean_ns(group, name),
            mean_ns(group, &format!("{name} [interpreter]")),
        );
        let (family, work) = name.split_once(") ").unwrap_or((name, ""));
        match (fast, slow) {
            (Some(fast), Some(slow)) => println!(
                "| {family}) | {work} | {fast:.0} ns | {slow:.0} ns | {:.2}x |",
                slow / fast
            ),
            _ => println!("| {family}) | {work} | not measured in this run | | |"),
        }
    }
    let group = "modbus rtu: vfd vs rmodbus";
    println!("\n| Work | vfd | vfd interpreter | rmodbus | rmodbus / vfd |");
    println!("|---|---|---|---|---|");
    for work in [
        "read holding registers (build + parse)",
        "write single register (build + parse)",
    ] {
        let fast = mean_ns(group, &format!("vfd: {work}"));
        let slow = mean_ns(group, &format!("vfd interpreter: {work}"));
        let peer = mean_ns(group, &format!("rmodbus: {work}"));
        match (fast, slow, peer) {
            (Some(fast), Some(slow), Some(peer)) => {
                let ratio = peer / fast;
                let verdict = if ratio >= 1.0 { "faster" } else { "slower" };
                println!(
                    "| {work} | {fast:.0} ns | {slow:.0} ns | {peer:.0} ns | vfd {:.2}x {verdict} |",
                    if ratio >= 1.0 { ratio } else { 1.0 / ratio }
                );
            }
            _ => println!("| {work} | not measured in this run | | | |"),
        }
    }
}

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    summary();
}
