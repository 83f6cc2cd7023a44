//! `vfd` with serial device servers ("RTU over TCP": the serial line's frames over TCP):
//! `vfd sim --listen` serves a virtual drive, `--port tcp://HOST:PORT` reaches it.
//!
//! - the Toshiba protocol of the VF-AS1 (not Modbus): read, write and read back across
//!   several connections, one client at a time, the drive keeping its state;
//! - a fault (`--fault corrupt-checksum`) applies over TCP as on the pseudo-terminal;
//! - a connection the device server drops mid-request is a typed error naming the address,
//!   and the next command works; a refused connection and a bad address are clear errors;
//! - pymodbus (an implementation we did not write) with its TCP client and the RTU framer
//!   reads and writes our virtual DV1, and `vfd read/write` reads and writes pymodbus's TCP
//!   server with the RTU framer. These two are `#[ignore]`d with the reason and run with
//!   `-- --include-ignored` (`.ci/run` runs them; without pymodbus they then fail).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A `vfd sim --listen 127.0.0.1:0` child, stopped when dropped.
struct ListeningSim {
    child: Child,
    /// `tcp://127.0.0.1:PORT`, the first line it printed.
    port: String,
}

impl ListeningSim {
    fn start(args: &[&str]) -> ListeningSim {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg("sim")
            .args(args)
            .args(["--listen", "127.0.0.1:0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("vfd sim starts");
        let mut first = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut first)
            .expect("the address");
        let port = first.trim().to_owned();
        assert!(
            port.starts_with("tcp://127.0.0.1:") && !port.ends_with(":0"),
            "first line is the bound address: {port:?}"
        );
        ListeningSim { child, port }
    }
}

impl Drop for ListeningSim {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

/// `vfd ARGS...`.
fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs")
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn succeeded(output: &Output) -> String {
    assert!(output.status.success(), "{}", text(output));
    text(output)
}

#[test]
fn a_toshiba_drive_is_read_and_written_over_tcp_one_client_at_a_time() {
    let sim = ListeningSim::start(&["--drive", "vf-as1", "--protocol", "ascii"]);
    let line = [
        "--drive",
        "vf-as1",
        "--protocol",
        "ascii",
        "--port",
        &sim.port,
    ];
    let read = |code: &str| succeeded(&vfd(&[&["read"][..], &line, &[code]].concat()));
    // FA01 is 0 Hz at power-on; written 42.5 Hz by one command, read back by the next
    // (a new connection: the drive keeps its state across clients).
    assert!(read("FA01").contains("= 0.00 Hz"), "{}", read("FA01"));
    let written = succeeded(&vfd(&[&["write"][..], &line, &["FA01", "42.5Hz"]].concat()));
    assert!(written.contains("42.50 Hz"), "{written}");
    let back = read("FA01");
    assert!(back.contains("= 42.50 Hz"), "{back}");
}

#[test]
fn a_fault_applies_over_tcp() {
    let sim = ListeningSim::start(&[
        "--drive",
        "vf-as1",
        "--protocol",
        "ascii",
        "--fault",
        "corrupt-checksum",
    ]);
    let damaged = vfd(&[
        "read",
        "--drive",
        "vf-as1",
        "--protocol",
        "ascii",
        "--port",
        &sim.port,
        "FA01",
    ]);
    assert!(!damaged.status.success(), "{}", text(&damaged));
    assert!(text(&damaged).contains("checksum"), "{}", text(&damaged));
}

/// A device server that takes the first request and hangs up, and forwards every later
/// connection to `target`.
fn flaky_device_server(target: &str) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = format!("tcp://{}", listener.local_addr().unwrap());
    let target = target.trim_start_matches("tcp://").to_owned();
    std::thread::spawn(move || {
        let mut first = true;
        for client in listener.incoming() {
            let Ok(mut client) = client else { return };
            if first {
                first = false;
                let mut request = [0u8; 64];
                let _ = client.read(&mut request);
                drop(client);
                continue;
            }
            let Ok(server) = TcpStream::connect(&target) else {
                return;
            };
            let (mut client_in, mut server_out) =
                (client.try_clone().unwrap(), server.try_clone().unwrap());
            std::thread::spawn(move || std::io::copy(&mut client_in, &mut server_out));
            let (mut server_in, mut client_out) = (server, client);
            std::thread::spawn(move || {
                let _ = std::io::copy(&mut server_in, &mut client_out);
                let _ = client_out.shutdown(std::net::Shutdown::Both);
            });
        }
    });
    address
}

#[test]
fn a_dropped_connection_is_a_typed_error_and_the_next_command_works() {
    let sim = ListeningSim::start(&["--drive", "vf-as1", "--protocol", "ascii"]);
    let flaky = flaky_device_server(&sim.port);
    let read = || {
        vfd(&[
            "read",
            "--drive",
            "vf-as1",
            "--protocol",
            "ascii",
            "--port",
            &flaky,
            "FA01",
        ])
    };
    let dropped = read();
    assert!(!dropped.status.success(), "{}", text(&dropped));
    let message = text(&dropped);
    assert!(
        message.contains(&format!(
            "{flaky}: the connection was closed by the device server"
        )) && message.contains("the next request connects again"),
        "{message}"
    );
    let again = read();
    assert!(succeeded(&again).contains("= 0.00 Hz"), "{}", text(&again));
}

#[test]
fn a_refused_connection_and_a_bad_address_are_clear_errors() {
    let closed = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = format!("tcp://{}", closed.local_addr().unwrap());
    drop(closed);
    let refused = vfd(&["read", "--drive", "yd1000", "--port", &address, "FA01"]);
    assert!(!refused.status.success());
    let message = text(&refused);
    assert!(
        message.contains(&format!(
            "{address}: cannot connect: the connection was refused"
        )) && message.contains("vfd sim --listen"),
        "{message}"
    );
    let bad = vfd(&[
        "read",
        "--drive",
        "yd1000",
        "--port",
        "tcp://nowhere",
        "FA01",
    ]);
    assert!(!bad.status.success());
    let message = text(&bad);
    assert!(
        message.contains("tcp://nowhere: not a reachable HOST:PORT address")
            && message.contains("tcp://HOST:PORT"),
        "{message}"
    );
}

/// Fails when pymodbus is missing: the peer tests are `#[ignore]`d (the `vfd` binary's
/// crate has no build script to find the package at build time), so they run only when
/// asked for (`-- --include-ignored`, as `.ci/run` does), and then they must run.
fn require_pymodbus() {
    let installed = Command::new("python3")
        .args(["-c", "import pymodbus"])
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        installed,
        "pymodbus is missing: pip install -r tests/python/requirements.txt"
    );
}

/// The workspace's Python peers.
fn python(script: &str) -> String {
    format!("{}/../tests/python/{script}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
#[ignore = "needs python3 with pymodbus: cargo test -p vfd-cli --test tcp -- --include-ignored (.ci/run does)"]
fn pymodbus_over_tcp_with_the_rtu_framer_reads_and_writes_our_virtual_dv1() {
    require_pymodbus();
    let sim = ListeningSim::start(&["--drive", "dv1", "--protocol", "modbus"]);
    // 02-15 is at 00C3h: 60.00 Hz; write 50.00 Hz, read it back; no register at 2000h
    // (exception 02); thirteen registers from 07-03 (0030h) are more than function 10
    // takes (exception 03).
    let plan = r#"[
        {"op": "read", "address": 195, "count": 1},
        {"op": "write", "address": 195, "value": 5000},
        {"op": "read", "address": 195, "count": 1},
        {"op": "write", "address": 8192, "value": 1},
        {"op": "write_many", "address": 48, "values": [0,0,0,0,0,0,0,0,0,0,0,0,0]}
    ]"#;
    let mut child = Command::new("python3")
        .args([
            &python("modbus_peer_client.py"),
            "pymodbus",
            &sim.port,
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
        .unwrap()
        .write_all(plan.as_bytes())
        .unwrap();
    let output = child.wait_with_output().expect("the client ends");
    assert!(output.status.success());
    let answers: Vec<String> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| l.replace(' ', ""))
        .collect();
    assert_eq!(
        answers,
        [
            r#"{"ok":true,"values":[6000]}"#,
            r#"{"ok":true,"values":[5000]}"#,
            r#"{"ok":true,"values":[5000]}"#,
            r#"{"ok":false,"exception":2}"#,
            r#"{"ok":false,"exception":3}"#,
        ]
    );
}

#[test]
#[ignore = "needs python3 with pymodbus: cargo test -p vfd-cli --test tcp -- --include-ignored (.ci/run does)"]
fn vfd_reads_and_writes_pymodbus_over_tcp_with_the_rtu_framer() {
    require_pymodbus();
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .unwrap()
        .port();
    let address = format!("tcp://127.0.0.1:{port}");
    let mut server = Command::new("python3")
        .args([&python("modbus_peer_server.py"), &address, "rtu"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("python3 runs");
    let mut ready = String::new();
    BufReader::new(server.stdout.take().unwrap())
        .read_line(&mut ready)
        .unwrap();
    let started = Instant::now();
    while TcpStream::connect(address.trim_start_matches("tcp://")).is_err() {
        assert!(started.elapsed() < Duration::from_secs(30), "no server");
        std::thread::sleep(Duration::from_millis(50));
    }
    let line = [
        "--drive",
        "fc51",
        "--protocol",
        "modbus",
        "--address",
        "1",
        "--timeout",
        "300",
        "--port",
        &address,
    ];
    let read = |code: &str| vfd(&[&["read"][..], &line, &[code]].concat());
    let first = read("303");
    let write = vfd(&[&["write"][..], &line, &["101", "7"]].concat());
    let back = read("101");
    let _ = server.kill();
    let _ = server.wait();
    assert!(succeeded(&first).contains("60.000"), "{}", text(&first));
    succeeded(&write);
    assert!(succeeded(&back).contains("= 7"), "{}", text(&back));
}
