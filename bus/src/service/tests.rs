//! The service embedded in a program: a plant in, events and write results out, run
//! in-process against a virtual drive served over TCP (no binary, no broker).

use super::event::{Event, NotSent, Unroutable, WriteRequest};
use super::ServiceCore;
use crate::Catalogue;
use std::net::TcpListener;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;
use std::time::{Duration, Instant};
use vfd_runtime::transport::TcpTransport;
use vfd_runtime::virtual_drive::{serve_bus, BusStation};

/// Serves a vf-as1 (Modbus, station 1) on a TCP port of this host to one client, until
/// `stop`; the port's `tcp://` address.
fn virtual_drive(catalogue: &Catalogue, stop: Arc<AtomicBool>) -> String {
    let drive = catalogue.drive("vf-as1").expect("vf-as1 is built in");
    let protocol = crate::lookup::protocol(drive, Some("modbus")).expect("modbus");
    let simulator = vfd_runtime::virtual_drive::Simulator::new(drive);
    simulator.lock().set_address(1);
    let station = BusStation {
        simulator,
        protocol,
    };
    let settings = drive.serial.default;
    let listener = TcpListener::bind("127.0.0.1:0").expect("a port");
    let port = listener.local_addr().expect("its address").port();
    std::thread::spawn(move || {
        let (stream, _) = listener.accept().expect("the service connects");
        let mut transport = TcpTransport::from_stream(stream).expect("a transport");
        let _ = serve_bus(&[station], &mut transport, settings, &stop);
    });
    format!("tcp://127.0.0.1:{port}")
}

/// The first event `wanted` takes within `limit` (a generous upper bound on a hang).
fn wait_for(events: &Receiver<Event>, what: &str, wanted: impl Fn(&Event) -> bool) -> Event {
    let until = Instant::now() + Duration::from_secs(20);
    while let Some(left) = until.checked_duration_since(Instant::now()) {
        match events.recv_timeout(left) {
            Ok(event) if wanted(&event) => return event,
            Ok(_) => {}
            Err(_) => break,
        }
    }
    panic!("no event: {what}");
}

#[test]
fn a_plant_runs_in_process_and_answers_writes_with_their_outcomes() {
    let catalogue = Catalogue::new();
    let stop = Arc::new(AtomicBool::new(false));
    let port = virtual_drive(&catalogue, stop.clone());
    let text = format!(
        "buses:\n  - name: line1\n    port: {port}\n    drives:\n      - name: pump1\n        drive: vf-as1\n        protocol: modbus\n        station: 1\n        poll:\n          - every: 200ms\n            registers: [FA01]\n        write: [FA01]\n"
    );
    let plant = crate::plant::load_str(&text, Path::new("embedded.yaml"), &catalogue)
        .unwrap_or_else(|problems| panic!("{problems}"));
    let (core, events) = ServiceCore::new(&plant);
    let writes = core.writes();
    let running = core.start(stop.clone()).expect("the workers start");

    let online = wait_for(
        &events,
        "pump1 online",
        |e| matches!(e, Event::Availability(a) if a.drive == "pump1" && a.online),
    );
    let Event::Availability(online) = online else {
        unreachable!()
    };
    assert_eq!(online.bus, "line1");

    writes
        .send(WriteRequest::new("line1", "pump1", "FA01", "50 Hz", 7))
        .expect("routed");
    let written = wait_for(
        &events,
        "the write's outcome",
        |e| matches!(e, Event::Written(w) if w.id == 7),
    );
    let Event::Written(written) = written else {
        unreachable!()
    };
    assert!(written.ok, "{written:?}");
    assert!(written.sent);
    assert_eq!(
        (written.code.as_str(), written.raw, written.value),
        ("FA01", Some(5000), Some(50.0))
    );
    wait_for(
        &events,
        "FA01 read back as 50 Hz",
        |e| matches!(e, Event::Reading(r) if r.code == "FA01" && r.value == Some(50.0)),
    );

    // Refused before anything is sent: a register the plant does not allow, a station the
    // bus does not have; a bus the plant does not have is not routed at all.
    writes
        .send(WriteRequest::new("line1", "pump1", "FH", "60", 8))
        .expect("routed");
    writes
        .send(WriteRequest::new("line1", "pump9", "FA01", "10", 9))
        .expect("routed");
    for (id, says) in [
        (8, "the plant file does not allow it"),
        (9, "no drive `pump9`"),
    ] {
        let refused = wait_for(
            &events,
            "a refusal",
            |e| matches!(e, Event::Written(w) if w.id == id),
        );
        let Event::Written(refused) = refused else {
            unreachable!()
        };
        assert!(!refused.ok && !refused.sent, "{refused:?}");
        let error = refused.error.unwrap_or_default();
        assert!(error.contains(says), "{error}");
    }
    match writes.send(WriteRequest::new("line9", "pump1", "FA01", "10", 10)) {
        Err(NotSent {
            why: Unroutable::NoBus(known),
            ..
        }) => assert_eq!(known, ["line1"]),
        other => panic!("routed to no bus: {other:?}"),
    }

    stop.store(true, Ordering::SeqCst);
    running.join();
    wait_for(
        &events,
        "pump1 offline as the service stops",
        |e| matches!(e, Event::Availability(a) if a.drive == "pump1" && !a.online),
    );
}

#[test]
fn an_allowed_register_is_routed_resolved_and_another_name_is_left_to_the_worker() {
    let catalogue = Catalogue::new();
    let text = "buses:\n  - name: line1\n    port: /dev/null\n    drives:\n      - name: pump1\n        drive: vf-as1\n        protocol: modbus\n        write: [FA01]\n";
    let plant = crate::plant::load_str(text, Path::new("embedded.yaml"), &catalogue)
        .unwrap_or_else(|problems| panic!("{problems}"));
    let (router, queues) = super::event::WriteRouter::new(&plant);
    router
        .send(WriteRequest::new("line1", "pump1", "FA01", "1", 1))
        .expect("routed");
    router
        .send(WriteRequest::new("line1", "pump1", "FH", "1", 2))
        .expect("routed");
    router
        .send(WriteRequest::new("line1", "pump2", "FA01", "1", 3))
        .expect("routed");
    let targets: Vec<_> = queues[0]
        .try_iter()
        .map(|r| r.target.map(|t| (t.bus, t.station, t.allowed)))
        .collect();
    assert_eq!(
        targets,
        [
            Some((0, Some(0), Some(0))),
            Some((0, Some(0), None)),
            Some((0, None, None))
        ]
    );
}
