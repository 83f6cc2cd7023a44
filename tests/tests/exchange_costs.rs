//! What an exchange costs the master: one command lookup and one frame encoding for every
//! frame it sends, on every protocol of every drive (`vfd_runtime::tally` counts them on
//! the master's thread; the virtual drive answers from another thread, over a
//! pseudo-terminal). Before the exchanges became values, a typed write looked its command
//! up four times and encoded its frame twice.

use vfd_runtime::kinds::CommandKind;
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
        // A command with a follow-up prepares its two follow-up frames with the request
        // (the acknowledgement it sends, and the request for the reply again it may send).
        let follow_ups = |kind: CommandKind| {
            let command =
                subject
                    .protocol
                    .command_for(kind, subject.read.space, subject.read.data_type);
            if command.is_some_and(|c| c.follow_up.is_some()) {
                2
            } else {
                0
            }
        };
        let read = Request::for_register(CommandKind::Read, subject.read, 0);
        let before = Tally::now();
        let sends = master.transport().sends();
        let outcome = master.transact(&read);
        let cost = Tally::since(before);
        let frames = (master.transport().sends() - sends) as u64;
        assert!(outcome.is_ok(), "{}: {outcome:?}", subject.name());
        // A follow-up acknowledging a sound reply is a frame of its own, prepared with the
        // request: its encoding is counted, and it needs no lookup.
        let extra = follow_ups(CommandKind::Read);
        assert_eq!(
            (cost.lookups, cost.encodings),
            (frames - extra.min(1), frames - extra.min(1) + extra),
            "{}: a read of {} sent {frames} frame(s)",
            subject.name(),
            subject.read.code
        );
        // A RAM write of a register no persistence selector governs (a governed write
        // prepares the selector's frames as the drive's replies decide them).
        let governed = subject
            .protocol
            .persistence
            .as_ref()
            .is_some_and(|selector| {
                selector.governs(subject.write.space, subject.write.address, true)
            });
        if !governed {
            let write =
                Request::for_register(CommandKind::WriteRam, subject.write, subject.value(0));
            let before = Tally::now();
            let sends = master.transport().sends();
            let outcome = master.transact(&write);
            let cost = Tally::since(before);
            let frames = (master.transport().sends() - sends) as u64;
            assert!(outcome.is_ok(), "{}: {outcome:?}", subject.name());
            let extra = follow_ups(CommandKind::WriteRam);
            assert_eq!(
                (cost.lookups, cost.encodings),
                (frames - extra.min(1), frames - extra.min(1) + extra),
                "{}: a RAM write of {} sent {frames} frame(s)",
                subject.name(),
                subject.write.code
            );
        }
        served.stop().expect("serve loop");
        drop(master);
        checked += 1;
    }
    eprintln!("{checked} protocols checked");
}
