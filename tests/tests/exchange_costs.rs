//! What an exchange costs the master: one command lookup and one frame encoding for every
//! frame it sends, on every protocol of every drive (`vfd_runtime::tally` counts them on
//! the master's thread; the virtual drive answers from another thread, over a
//! pseudo-terminal). Before the exchanges became values, a typed write looked its command
//! up four times and encoded its frame twice, and a write a persistence selector governs
//! (the DV1's 07-11) encoded its frames once to check them and again to send them.

use vfd_runtime::kinds::{Access, CommandKind, DataType, Space};
use vfd_runtime::register::Request;
use vfd_runtime::tally::Tally;
use vfd_runtime::transaction::Master;
use vfd_tests::fault_cases::{subjects, Served};
use vfd_tests::watched::Watched;

#[test]
fn every_frame_sent_costs_one_lookup_and_one_encoding() {
    let (subjects, _) = subjects();
    assert!(subjects.len() >= 8, "{} subjects", subjects.len());
    let mut checked = 0;
    let mut governed_checked = 0;
    for subject in &subjects {
        let sim = subject.simulator();
        let (line, served) = Served::start(&sim, subject.protocol).expect("pseudo-terminal");
        let address = sim.lock().address();
        let mut master = Master::for_protocol(
            Watched::new(line),
            subject.protocol,
            subject.drive.serial.default,
            subject.drive.serial.timing,
        )
        .with_address(Some(address));
        // Whether the command carrying `kind` in `space` for `data_type` has a follow-up.
        let follow_up = |kind: CommandKind, space: Space, data_type: DataType| {
            let command = subject.protocol.command_for(kind, space, data_type);
            u64::from(command.is_some_and(|c| c.follow_up.is_some()))
        };
        let read = Request::for_register(CommandKind::Read, subject.read, 0);
        let before = Tally::now();
        let sends = master.transport().sends();
        let outcome = master.transact(&read);
        let cost = Tally::since(before);
        let frames = (master.transport().sends() - sends) as u64;
        assert!(outcome.is_ok(), "{}: {outcome:?}", subject.name());
        let with_follow_up = follow_up(
            CommandKind::Read,
            subject.read.space,
            subject.read.data_type,
        );
        assert_eq!(
            (cost.lookups, cost.encodings),
            expected(frames, with_follow_up),
            "{}: a read of {} sent {frames} frame(s)",
            subject.name(),
            subject.read.code
        );
        // A write a persistence selector governs prepares every frame it may send before
        // the first goes out, each once: here each of them is sent (the selector set to
        // RAM first; for a persistent write the selector read when not known, set to
        // persistent, the write, and the old value back).
        let selector = subject.protocol.persistence.as_ref();
        // (what, kind, forget the selector first, selector reads and writes sent)
        // The subject's own write: a RAM write, or a persistent one where the protocol has
        // no RAM write for it.
        let mut writes = vec![("a write", subject.write_kind, false, (0, 1))];
        // The register written: the subject's own, or on a protocol with a persistence
        // selector a plain parameter it governs, written with its default.
        let governed = selector.and_then(|selector| {
            subject.drive.registers.iter().find(|r| {
                r.space == Space::Parameter
                    && r.access == Access::ReadWrite
                    && selector.governs(r.space, r.address, r.ram_only)
                    && r.address != selector.register
                    && r.min_bound.is_none()
                    && r.max_bound.is_none()
                    && r.array_len <= 1
                    && r.bits.is_none()
                    && r.codes.is_none()
            })
        });
        let (register, value) = match governed {
            Some(register) => {
                writes.push((
                    "a persistent write",
                    CommandKind::WritePersistent,
                    false,
                    (0, 2),
                ));
                writes.push((
                    "a persistent write with the selector forgotten",
                    CommandKind::WritePersistent,
                    true,
                    (1, 2),
                ));
                governed_checked += 1;
                let value = register.default_raw.unwrap_or(register.raw_min as u32);
                (*register, value)
            }
            None => (subject.write, subject.value(0)),
        };
        for (what, kind, forget, (selector_reads, selector_writes)) in writes {
            if forget {
                master.forget_persistence_selector();
            }
            let write = Request::for_register(kind, register, value);
            let before = Tally::now();
            let sends = master.transport().sends();
            let outcome = master.transact(&write);
            let cost = Tally::since(before);
            let frames = (master.transport().sends() - sends) as u64;
            assert!(outcome.is_ok(), "{}: {what}: {outcome:?}", subject.name());
            let mut with_follow_up = follow_up(kind, register.space, register.data_type);
            if let (Some(selector), Some(_)) = (selector, governed) {
                with_follow_up += selector_reads
                    * follow_up(CommandKind::Read, selector.space, selector.data_type)
                    + selector_writes
                        * follow_up(CommandKind::WriteRam, selector.space, selector.data_type);
            }
            assert_eq!(
                (cost.lookups, cost.encodings),
                expected(frames, with_follow_up),
                "{}: {what} of {} sent {frames} frame(s)",
                subject.name(),
                register.code
            );
            if governed.is_some() {
                assert!(
                    frames >= 2,
                    "{}: {what} sent {frames} frame(s)",
                    subject.name()
                );
            }
        }
        served.stop().expect("serve loop");
        drop(master);
        checked += 1;
    }
    eprintln!("{checked} protocols checked, {governed_checked} with a persistence selector");
    assert!(
        governed_checked >= 1,
        "no protocol with a persistence selector was checked"
    );
}

/// The lookups and encodings `frames` sent cost when `with_follow_up` of their exchanges
/// had a follow-up: each sends an acknowledgement after a sound reply, a frame of its own
/// prepared with its request (no lookup), and prepares the request for the reply again it
/// may send (an encoding, not sent).
fn expected(frames: u64, with_follow_up: u64) -> (u64, u64) {
    (frames - with_follow_up, frames + with_follow_up)
}
