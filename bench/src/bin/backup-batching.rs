//! Backup batching: a full backup of every described drive over each of its protocols,
//! from the virtual drive through a recording transport, batched as `vfd backup` reads it
//! (consecutive registers in one block read where the protocol allows it) and one read per
//! register: requests, bytes and wire time at 9600 baud in the drive's factory character
//! format, with the protocol's frame gap before every frame.
//!
//! `cargo run --release -p vfd-bench --bin backup-batching [-- BAUD]`. The counts are
//! deterministic; prints a markdown table ready to paste into BENCHMARKS.md.

use vfd_bench::batching::compare;

fn main() {
    let baud: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(9600);
    println!("| Drive | Protocol | Line (gap) | Registers | Batched: requests | bytes out / in | wire time | One per register: requests | bytes out / in | wire time | Requests saved | Wire time ratio |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols {
            match compare(drive, protocol, baud) {
                Ok(c) => {
                    let s = c.settings;
                    let line = format!(
                        "{} {}{}{} ({:.1} ms)",
                        s.baud,
                        s.data_bits,
                        s.parity
                            .as_str()
                            .chars()
                            .next()
                            .unwrap_or('?')
                            .to_ascii_uppercase(),
                        s.stop_bits,
                        c.gap.as_secs_f64() * 1000.0
                    );
                    let batched = c.batched.wire_time(&c.settings, c.gap);
                    let single = c.single.wire_time(&c.settings, c.gap);
                    println!(
                        "| {} | {}{} | {line} | {} | {} | {} / {} | {:.2} s | {} | {} / {} | {:.2} s | {:.0} % | {:.2}x |",
                        c.drive,
                        c.protocol,
                        if c.blocks { "" } else { " (no block read)" },
                        if c.read == c.registers {
                            c.registers.to_string()
                        } else {
                            format!("{} ({} read)", c.registers, c.read)
                        },
                        c.batched.requests,
                        c.batched.sent,
                        c.batched.received,
                        batched.as_secs_f64(),
                        c.single.requests,
                        c.single.sent,
                        c.single.received,
                        single.as_secs_f64(),
                        100.0 * (1.0 - c.batched.requests as f64 / c.single.requests.max(1) as f64),
                        single.as_secs_f64() / batched.as_secs_f64().max(f64::MIN_POSITIVE),
                    );
                }
                Err(message) => {
                    eprintln!("backup-batching: {message}");
                    failed = true;
                }
            }
        }
    }
    if failed {
        std::process::exit(1);
    }
}
