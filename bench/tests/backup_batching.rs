//! The backup batching count (`vfd_bench::batching`, `--bin backup-batching`): deterministic
//! request counts, no timing. Batching never costs a request, reads the same values as one
//! read per register, changes nothing where the protocol has no block read, and saves
//! requests where consecutive registers can share one.

use vfd_bench::batching::compare;

#[test]
fn batched_backups_read_the_same_values_in_no_more_requests() {
    let mut saved_somewhere = false;
    for drive in vfd_drives::ALL_DRIVES {
        for protocol in drive.protocols {
            let c = compare(drive, protocol, 9600).unwrap_or_else(|e| panic!("{e}"));
            let label = format!("{} over {}", drive.id, protocol.id);
            assert!(c.registers > 0, "{label}: nothing to back up");
            assert!(c.read > 0, "{label}: nothing read");
            assert!(
                c.batched.requests <= c.single.requests,
                "{label}: batched {} requests, singly {}",
                c.batched.requests,
                c.single.requests
            );
            if !c.blocks {
                assert_eq!(c.batched, c.single, "{label}: no block read, same traffic");
            }
            if c.batched.requests < c.single.requests {
                assert!(c.blocks, "{label}: fewer requests without a block read");
                assert!(
                    c.batched.wire_time(&c.settings, c.gap)
                        < c.single.wire_time(&c.settings, c.gap),
                    "{label}: fewer requests but no less wire time"
                );
                saved_somewhere = true;
            }
        }
    }
    assert!(saved_somewhere, "no backup was batched");
}

/// The DV1's parameters sit at consecutive Modbus addresses within each group: its backup
/// over Modbus RTU and Modbus ASCII (up to 12 words per 03) takes fewer requests than it
/// has registers, and one read per register takes one request each (no page switches).
#[test]
fn dv1_modbus_backups_take_fewer_requests_than_registers() {
    let drive = &vfd_drives::dv1::DRIVE;
    for id in ["modbus", "modbus_ascii"] {
        let protocol = drive
            .protocols
            .iter()
            .copied()
            .find(|p| p.id == id)
            .expect(id);
        let c = compare(drive, protocol, 9600).unwrap_or_else(|e| panic!("{e}"));
        assert!(c.blocks, "{id}: a block read");
        assert_eq!(c.read, c.registers, "{id}: every register read");
        assert_eq!(
            c.single.requests, c.registers,
            "{id}: one request a register"
        );
        assert!(
            c.batched.requests < c.registers,
            "{id}: {} requests for {} registers",
            c.batched.requests,
            c.registers
        );
    }
}
