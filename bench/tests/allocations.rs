//! The hot path makes no heap allocation: encoding a typed request, decoding its reply,
//! converting the value, and a whole `Master` transaction (pre-steps included). Counted by
//! a global allocator wrapper, per thread, after a warm-up.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::time::Instant;
use vfd_drives::{fc51, yd1000};
use vfd_runtime::protocol::Found;
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::Transport;
use vfd_runtime::{CommandKind, DataType, Protocol, Register, RegisterValue, Request};

struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|count| count.set(count.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|count| count.set(count.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Allocations made by `work` run `times` times, after one warm-up run.
fn allocations(times: usize, mut work: impl FnMut()) -> usize {
    work();
    let before = ALLOCATIONS.with(Cell::get);
    for _ in 0..times {
        work();
    }
    ALLOCATIONS.with(Cell::get) - before
}

fn codec_round<R: Register>(
    protocol: &'static Protocol,
    address: Option<u8>,
    reply: &[u8],
) -> R::Value {
    let request = Request::read::<R>();
    let mut out = [0u8; 64];
    let len = protocol
        .encode_request(&request, address, &mut out)
        .expect("encodes");
    assert!(len > 0);
    let command = protocol.command_for(request.kind, request.space, request.data_type);
    match protocol.find_reply(command, reply).expect("decodes") {
        Found::Frame {
            frame: vfd_runtime::Reply::Data { data, .. },
            ..
        } => R::Value::from_raw(data, R::INFO).expect("converts"),
        _ => panic!("unexpected reply"),
    }
}

#[test]
fn encoding_and_decoding_allocate_nothing() {
    let count = allocations(1000, || {
        codec_round::<yd1000::registers::OutputFrequencyNow>(
            &yd1000::protocols::ASCII,
            None,
            b"(RFD001770)\r",
        );
        codec_round::<yd1000::registers::OutputFrequencyNow>(
            &yd1000::protocols::BINARY,
            Some(3),
            &[0x2F, 0x52, 0xFD, 0x00, 0x17, 0x70, 0x05],
        );
        codec_round::<fc51::registers::MaximumReference>(
            &fc51::protocols::FC,
            Some(1),
            &[
                0x02, 0x0E, 0x01, 0x21, 0x2F, 0x00, 0x00, 0x00, 0x00, 0xEA, 0x60, 0x00, 0x03, 0x00,
                0x00, 0x8A,
            ],
        );
        codec_round::<fc51::registers::MaximumReference>(
            &fc51::protocols::MODBUS,
            Some(1),
            &[0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B],
        );
    });
    assert_eq!(count, 0, "allocations in 1000 rounds of 4 protocols");
}

/// Answers every request with the next of a fixed set of replies, without allocating.
struct ReplayTransport {
    replies: &'static [&'static [u8]],
    next: usize,
    pending: Option<&'static [u8]>,
}

impl Transport for ReplayTransport {
    fn send(&mut self, _bytes: &[u8]) -> std::io::Result<()> {
        self.pending = Some(self.replies[self.next % self.replies.len()]);
        self.next += 1;
        Ok(())
    }
    fn receive(&mut self, buf: &mut [u8], _deadline: Instant) -> std::io::Result<usize> {
        match self.pending.take() {
            Some(reply) => {
                buf[..reply.len()].copy_from_slice(reply);
                Ok(reply.len())
            }
            None => Ok(0),
        }
    }
}

#[test]
fn whole_transactions_allocate_nothing() {
    let transport = ReplayTransport {
        replies: &[&[0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01]],
        next: 0,
        pending: None,
    };
    let mut binary = Master::new(
        transport,
        &yd1000::protocols::BINARY,
        yd1000::SERIAL.default,
        yd1000::SERIAL.timing,
    );
    let count = allocations(1000, || {
        binary
            .write_ram::<yd1000::registers::FrequencyCommand>(vfd_runtime::units::Hertz(60.0))
            .expect("exchange");
    });
    assert_eq!(count, 0, "Toshiba binary RAM writes");

    // Modbus RTU with the index pre-step: two exchanges per read. A high baud rate keeps
    // the 3.5-character gap short; the gap is a sleep, not an allocation.
    let settings = vfd_runtime::serial::SerialSettings {
        baud: 1_000_000,
        ..fc51::SERIAL.default
    };
    let transport = ReplayTransport {
        replies: &[
            &[0x01, 0x06, 0x00, 0x08, 0x00, 0x02, 0x89, 0xC9],
            &[0x01, 0x03, 0x02, 0x00, 0x00, 0xB8, 0x44],
        ],
        next: 0,
        pending: None,
    };
    let mut modbus = Master::new(
        transport,
        &fc51::protocols::MODBUS,
        settings,
        fc51::SERIAL.timing,
    )
    .with_address(Some(1));
    let count = allocations(200, || {
        modbus
            .read_at::<fc51::registers::PresetReference>(2)
            .expect("exchange");
    });
    assert_eq!(count, 0, "Modbus indexed reads");
}

/// Encodes `request` by wire number and decodes `reply`: the raw data.
fn raw_round(protocol: &Protocol, request: &Request, address: Option<u8>, reply: &[u8]) -> u32 {
    let mut out = [0u8; 64];
    let len = protocol
        .encode_request(request, address, &mut out)
        .expect("encodes");
    assert!(len > 0);
    let command = protocol.command_for(request.kind, request.space, request.data_type);
    match protocol.find_reply(command, reply).expect("decodes") {
        Found::Frame {
            frame: vfd_runtime::Reply::Data { data, .. },
            ..
        } => data,
        _ => panic!("unexpected reply"),
    }
}

/// A request by wire number.
fn raw(kind: CommandKind, register: u16, data: u32, data_type: DataType) -> Request {
    Request {
        wire_register: true,
        ..Request::raw(kind, register, data).with_data_type(data_type)
    }
}

#[test]
fn the_fast_path_allocates_nothing() {
    use vfd_drives::{dv1, vf_as1};
    let modbus = fc51::protocols::MODBUS.protocol();
    let read = raw(CommandKind::Read, 0x0BD5, 0, DataType::DoubleWord);
    let write = raw(CommandKind::WriteRam, 0x03F1, 1, DataType::Word);
    let eaton = dv1::protocols::EATON.protocol();
    let eaton_read = raw(CommandKind::Read, 0x5F, 0, DataType::Word);
    let eaton_write = raw(CommandKind::WriteRam, 0xDF, 0x1388, DataType::Word);
    let register = raw(CommandKind::Read, 0x0000, 0, DataType::Word);
    let fd00 = raw(CommandKind::Read, 0xFD00, 0, DataType::Word);
    let c3 = raw(CommandKind::Read, 0x00C3, 0, DataType::Word);
    let ascii = dv1::protocols::MODBUS_ASCII.protocol();
    // Every exchange below goes through compiled plans, both ways (so this counts the fast
    // path, not the interpreter).
    let exchanges = [
        (modbus, &read),
        (modbus, &write),
        (eaton, &eaton_read),
        (eaton, &eaton_write),
        (vf_as1::protocols::ASCII.protocol(), &register),
        (vf_as1::protocols::MODBUS.protocol(), &fd00),
        (ascii, &c3),
    ];
    for (protocol, request) in exchanges {
        let command = protocol.command_for_request(request).expect("a command");
        for layout in [&command.request, &command.reply] {
            assert!(
                layout.plan.as_ref().is_some_and(|p| p.compiled.is_some()),
                "{}: {} has a compiled plan",
                protocol.id,
                layout.name
            );
        }
    }
    let count = allocations(1000, || {
        let read_reply = [0x01, 0x03, 0x04, 0x00, 0x00, 0xEA, 0x60, 0xB5, 0x7B];
        assert_eq!(raw_round(modbus, &read, Some(1), &read_reply), 0xEA60);
        let write_reply = [0x01, 0x06, 0x03, 0xF1, 0x00, 0x01, 0x19, 0xBD];
        assert_eq!(raw_round(modbus, &write, Some(1), &write_reply), 1);
        assert_eq!(
            raw_round(eaton, &eaton_read, Some(0), b"\x020017702\x0361\r"),
            0x1770
        );
        raw_round(eaton, &eaton_write, Some(0), b"\x0600\r");
        assert_eq!(
            raw_round(
                vf_as1::protocols::ASCII.protocol(),
                &register,
                Some(2),
                b"(02R00000000)\r",
            ),
            0
        );
        let reply = [0x01, 0x03, 0x02, 0x17, 0x70, 0xB6, 0x50];
        assert_eq!(
            raw_round(vf_as1::protocols::MODBUS.protocol(), &fd00, Some(1), &reply),
            0x1770
        );
        assert_eq!(raw_round(ascii, &c3, Some(1), b":010302177073\r\n"), 0x1770);
    });
    assert_eq!(count, 0, "allocations in 1000 rounds of the fast path");
}

#[test]
fn the_counter_sees_allocations() {
    let count = allocations(10, || {
        std::hint::black_box(vec![1u8; 16]);
    });
    assert_eq!(count, 10);
}
