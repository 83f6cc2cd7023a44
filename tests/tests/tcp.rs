//! Drives behind a serial device server ("RTU over TCP": the serial line's frames over TCP,
//! no Modbus TCP header), against pymodbus, an implementation we did not write:
//!
//! - our library `Master` over a `TcpTransport` reads and writes pymodbus's TCP server with
//!   the RTU framer (`StartTcpServer(..., framer=FramerType.RTU)`);
//! - pymodbus's TCP client with the RTU framer (`ModbusTcpClient(..., framer=RTU)`) reads,
//!   writes and reads back our virtual DV1 served over an accepted TCP connection, and gets
//!   the exception codes of refused requests.
//!
//! Needs `pip install -r tests/python/requirements.txt` (.ci/run does it). Without the
//! packages the test is built ignored, with the reason (see tests/build.rs), except under
//! CI, where it fails.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use vfd_drives::{dv1, fc51};
use vfd_runtime::serial::{DriveTiming, Parity, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{TcpTransport, Transport, NETWORK_ALLOWANCE};
use vfd_runtime::virtual_drive::{serve, Simulator};

fn pymodbus_installed() -> bool {
    let installed = Command::new("python3")
        .args(["-c", "import pymodbus"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !installed {
        panic!(
            "pymodbus is missing: pip install -r tests/python/requirements.txt (under CI a missing peer fails; elsewhere tests/build.rs marks its tests ignored when it finds the package missing: touch tests/build.rs to look again)"
        );
    }
    installed
}

/// A free local port (bound and released: the server binds it again).
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port()
}

struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

const SETTINGS: SerialSettings = SerialSettings {
    baud: 115_200,
    data_bits: 8,
    parity: Parity::None,
    stop_bits: 1,
};

#[test]
#[cfg_attr(
    missing_pymodbus,
    ignore = "needs python3 with pymodbus and pyserial: pip install -r tests/python/requirements.txt, then cargo test again"
)]
fn our_master_reads_and_writes_pymodbus_over_tcp_with_the_rtu_framer() {
    if !pymodbus_installed() {
        return;
    }
    let address = format!("tcp://127.0.0.1:{}", free_port());
    let mut child = Command::new("python3")
        .args(["python/modbus_peer_server.py", &address, "rtu"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("python3 runs");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("piped"))
        .read_line(&mut line)
        .expect("the server starts");
    let _server = Server(child);
    // The server listens a moment after printing "ready": retry the connection.
    let started = Instant::now();
    let transport = loop {
        match TcpTransport::connect(&address) {
            Ok(transport) => break transport,
            Err(err) => {
                assert!(
                    started.elapsed() < Duration::from_secs(30),
                    "the pymodbus server does not listen: {err}"
                );
                std::thread::sleep(Duration::from_millis(50));
            }
        }
    };
    assert_eq!(transport.allowance(), NETWORK_ALLOWANCE);
    let timing = DriveTiming {
        startup_delay: Duration::ZERO,
        processing_allowance: Duration::from_millis(300),
        frame_abandon: Duration::from_secs(1),
    };
    let mut master =
        Master::new(transport, &fc51::protocols::MODBUS, SETTINGS, timing).with_address(Some(1));
    // The network allowance is part of every reply timeout.
    let bare = Master::new(
        vfd_runtime::transport::memory_pair().0,
        &fc51::protocols::MODBUS,
        SETTINGS,
        timing,
    );
    assert_eq!(
        master.reply_timeout(8),
        bare.reply_timeout(8) + NETWORK_ALLOWANCE
    );

    // 03 with two registers at 303 x 10 - 1: 60000, three decimals.
    assert_eq!(
        master
            .read::<fc51::registers::MaximumReference>()
            .expect("03 over TCP"),
        60.0
    );
    // RAM write (coil 65 with 05, then 06), read back with 03.
    assert_eq!(
        master
            .write_ram::<fc51::registers::Parameter101>(7)
            .expect("05 and 06 over TCP"),
        Some(7)
    );
    assert_eq!(master.read::<fc51::registers::Parameter101>().unwrap(), 7);
    // Persistent double-word write (10), read back.
    master
        .write_persistent::<fc51::registers::MaximumReference>(55.5)
        .expect("10 over TCP");
    assert_eq!(
        master.read::<fc51::registers::MaximumReference>().unwrap(),
        55.5
    );
}

/// Runs `plan` with pymodbus's TCP client (RTU framer) against a virtual DV1 served over an
/// accepted TCP connection; one JSON answer per step.
fn pymodbus_against_our_dv1(sim: &Simulator, plan: &serde_json::Value) -> Vec<serde_json::Value> {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a port");
    let address = format!("tcp://{}", listener.local_addr().unwrap());
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let (sim, stop) = (sim.clone(), Arc::clone(&stop));
        std::thread::spawn(move || {
            let (stream, _) = listener.accept().expect("the client connects");
            let mut transport = TcpTransport::from_stream(stream).expect("served");
            serve(
                &sim,
                dv1::protocols::MODBUS.protocol(),
                &mut transport,
                SETTINGS,
                &stop,
            )
        })
    };
    let mut child = Command::new("python3")
        .args([
            "python/modbus_peer_client.py",
            "pymodbus",
            &address,
            "1",
            "rtu",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("python3 runs");
    child
        .stdin
        .take()
        .expect("piped")
        .write_all(plan.to_string().as_bytes())
        .expect("the plan is sent");
    let steps = plan.as_array().map_or(0, Vec::len);
    let answers: Vec<serde_json::Value> = BufReader::new(child.stdout.take().expect("piped"))
        .lines()
        .take(steps)
        .map(|line| serde_json::from_str(&line.expect("a line")).expect("JSON"))
        .collect();
    assert!(child.wait().expect("the client ends").success());
    // The client closed the connection: the serve loop ends with that error.
    let ended = server.join().expect("the server thread");
    stop.store(true, Ordering::Relaxed);
    let err = ended.expect_err("the client left");
    assert_eq!(err.kind(), std::io::ErrorKind::ConnectionAborted, "{err}");
    assert_eq!(answers.len(), steps, "{answers:?}");
    answers
}

#[test]
#[cfg_attr(
    missing_pymodbus,
    ignore = "needs python3 with pymodbus and pyserial: pip install -r tests/python/requirements.txt, then cargo test again"
)]
fn pymodbus_reads_and_writes_our_virtual_dv1_over_tcp_with_the_rtu_framer() {
    if !pymodbus_installed() {
        return;
    }
    let sim = Simulator::new(&dv1::DRIVE);
    sim.lock().set_address(1);
    let register = |id: &str| dv1::DRIVE.register(id).expect(id).address;
    let plan = serde_json::json!([
        // 02-15: 60.00 Hz, write 50.00 Hz, read it back.
        { "op": "read", "address": register("parameter_02_15"), "count": 1 },
        { "op": "write", "address": register("parameter_02_15"), "value": 5000 },
        { "op": "read", "address": register("parameter_02_15"), "count": 1 },
        // No register at 2000h: exception 02, illegal data address.
        { "op": "write", "address": 0x2000, "value": 1 },
        // Thirteen registers, more than function 10 takes: exception 03.
        { "op": "write_many", "address": register("data_length"), "values": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0] },
    ]);
    let answers = pymodbus_against_our_dv1(&sim, &plan);
    assert_eq!(
        answers[0]["values"],
        serde_json::json!([6000]),
        "{answers:?}"
    );
    assert_eq!(answers[1]["ok"], true, "{answers:?}");
    assert_eq!(
        answers[2]["values"],
        serde_json::json!([5000]),
        "{answers:?}"
    );
    assert_eq!(answers[3]["exception"], 2, "{answers:?}");
    assert_eq!(answers[4]["exception"], 3, "{answers:?}");
}

/// A connection the device server drops mid-exchange is a typed error naming the address,
/// and the master's next exchange reconnects (our virtual FC 51 behind a TCP listener; no
/// Python needed).
#[test]
fn a_dropped_connection_is_a_typed_error_and_the_next_exchange_reconnects() {
    use std::io::Read;
    let listener = TcpListener::bind("127.0.0.1:0").expect("a port");
    let address = format!("tcp://{}", listener.local_addr().unwrap());
    let sim = Simulator::new(&fc51::DRIVE);
    sim.lock().set_address(1);
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let (sim, stop) = (sim.clone(), Arc::clone(&stop));
        std::thread::spawn(move || {
            // The first connection: the request arrives, the device server hangs up.
            let (mut first, _) = listener.accept().expect("the master connects");
            let mut request = [0u8; 8];
            first.read_exact(&mut request).expect("a request");
            drop(first);
            // The next one is served.
            let (stream, _) = listener.accept().expect("the master reconnects");
            let mut transport = TcpTransport::from_stream(stream).expect("served");
            serve(
                &sim,
                fc51::protocols::MODBUS.protocol(),
                &mut transport,
                SETTINGS,
                &stop,
            )
        })
    };
    let transport = TcpTransport::connect(&address).expect("connects");
    let timing = DriveTiming {
        startup_delay: Duration::ZERO,
        processing_allowance: Duration::from_millis(300),
        frame_abandon: Duration::from_secs(1),
    };
    let mut master = Master::new(transport, &fc51::protocols::MODBUS, SETTINGS, timing)
        .with_address(Some(1))
        .with_retries(0);
    let err = master
        .read::<fc51::registers::Parameter101>()
        .expect_err("the connection was dropped");
    match &err.kind {
        vfd_runtime::TransactionErrorKind::Io(io) => {
            assert_eq!(io.kind(), std::io::ErrorKind::ConnectionAborted, "{err}");
            assert!(
                io.to_string().contains(&format!(
                    "{address}: the connection was closed by the device server"
                )),
                "{err}"
            );
        }
        other => panic!("expected an I/O error, got {other:?}"),
    }
    // The next exchange connects again and is answered.
    master
        .read::<fc51::registers::Parameter101>()
        .expect("the next exchange reconnects");
    drop(master);
    let ended = server.join().expect("the server thread");
    stop.store(true, Ordering::Relaxed);
    assert!(ended.is_err(), "the served client left");
}
