//! Lists the drives this build of `vfd_drives` holds (one per feature turned on), with
//! their protocols and registers: what a program that embeds the catalogue carries.
//!
//! Run it with `cargo run -p vfd-drives --example catalogue`, or with one drive:
//! `cargo run -p vfd-drives --example catalogue --no-default-features --features yd1000`.

fn main() {
    for drive in vfd_drives::ALL_DRIVES {
        let protocols: Vec<String> = drive.protocols.iter().map(|p| p.id.to_string()).collect();
        println!(
            "{:<8} {} {} ({}): {} registers; protocols {}",
            drive.id,
            drive.vendor,
            drive.model,
            drive.name,
            drive.registers.len(),
            protocols.join(", ")
        );
        for register in drive.registers {
            println!(
                "    {:<6} {:<40} {}",
                register.code, register.id, register.name
            );
        }
    }
}
