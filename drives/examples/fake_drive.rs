//! A `Master` talking to a scripted fake YD1000 over the in-memory transport: no hardware.
//! The fake drive answers with the manual's own example frames (section 9, binary).
//!
//! Run it with `cargo run -p vfd-drives --example fake_drive`.

use std::time::{Duration, Instant};
use vfd_drives::yd1000::{self, bits, registers};
use vfd_runtime::prelude::*;
use vfd_runtime::transport::{memory_pair, MemoryTransport};
use vfd_runtime::TransactionErrorKind;

/// Answers each request it recognises with the reply the manual prints for it, and a data
/// error (`N`, code 1) to anything else.
fn fake_drive(mut line: MemoryTransport) -> std::thread::JoinHandle<()> {
    let script: [(&[u8], &[u8]); 4] = [
        // FA01 = 60.00 Hz, in RAM (P): the drive echoes the request.
        (
            &[0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01],
            &[0x2F, 0x50, 0xFA, 0x01, 0x17, 0x70, 0x01],
        ),
        // FA00 = C400h (commands from the link, run forward).
        (
            &[0x2F, 0x50, 0xFA, 0x00, 0xC4, 0x00, 0x3D],
            &[0x2F, 0x50, 0xFA, 0x00, 0xC4, 0x00, 0x3D],
        ),
        // Read FD00, the output frequency: 1770h = 60.00 Hz.
        (
            &[0x2F, 0x52, 0xFD, 0x00, 0x7E],
            &[0x2F, 0x52, 0xFD, 0x00, 0x17, 0x70, 0x05],
        ),
        // Read FE01, status word 1: 9000h.
        (
            &[0x2F, 0x52, 0xFE, 0x01, 0x80],
            &[0x2F, 0x52, 0xFE, 0x01, 0x90, 0x00, 0x10],
        ),
    ];
    let data_error: &[u8] = &[0x2F, 0x4E, 0x00, 0x01, 0x7E];
    std::thread::spawn(move || {
        let protocol = &yd1000::protocols::BINARY;
        let mut received = Vec::new();
        let mut chunk = [0u8; 32];
        loop {
            let deadline = Instant::now() + Duration::from_secs(2);
            match line.receive(&mut chunk, deadline) {
                Ok(0) | Err(_) => return, // The master is gone.
                Ok(n) => received.extend_from_slice(&chunk[..n]),
            }
            let Ok(vfd_runtime::protocol::Found::Frame { frame, skipped }) =
                protocol.decode_request(&received)
            else {
                continue; // Not a whole request yet.
            };
            let request: Vec<u8> = received
                .drain(..skipped + frame.len)
                .skip(skipped)
                .collect();
            let reply = script
                .iter()
                .find(|(asked, _)| *asked == request.as_slice())
                .map_or(data_error, |(_, reply)| *reply);
            if line.send(reply).is_err() {
                return;
            }
        }
    })
}

fn main() -> Result<(), TransactionError> {
    let (master_end, drive_end) = memory_pair();
    let drive = fake_drive(drive_end);
    let mut master = Master::new(
        master_end,
        &yd1000::protocols::BINARY,
        yd1000::SERIAL.default,
        yd1000::SERIAL.timing,
    );

    // Writes are range-checked before a byte is sent, and go to RAM unless asked otherwise.
    master.write_ram::<registers::FrequencyCommand>(Hertz(60.0))?;
    let run = bits::CommandWord::new()
        .with_command_enabled(true)
        .with_frequency_enabled(true)
        .with_run(true);
    master.write_ram::<registers::CommandWord>(run)?;

    // Reads come back typed: a quantity, a bit-field word.
    let frequency = master.read::<registers::OutputFrequencyNow>()?;
    let status = master.read::<registers::Status>()?;
    println!("output frequency: {} Hz", frequency.0);
    // Bit-field words have an accessor per field; `Display` lists the fields that are set.
    // The manual's example reply, 9000h, sets only bits its own table marks reserved.
    println!(
        "status word 1: {:04X}h, fields set: {status}, running: {}, reserved bits set: {}",
        status.bits(),
        status.running(),
        status.has_reserved_bits()
    );
    assert_eq!(frequency, Hertz(60.0));

    // The drive answers this one with error 1 (data error): a typed error that names the
    // register, the code and the manual's meaning.
    let error = master
        .read::<registers::MaximumFrequency>()
        .expect_err("the fake drive rejects it");
    assert!(matches!(
        error.kind,
        TransactionErrorKind::Rejected { code: 1, .. }
    ));
    println!("error: {error}");

    drop(master); // Closes the line: the fake drive's thread ends.
    drive.join().expect("the fake drive ran to the end");
    Ok(())
}
