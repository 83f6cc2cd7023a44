//! `vfd sim` with several stations on one pseudo-terminal (a multi-drop bus): each answers
//! `vfd read` at its own address, a request for a station that is not there gets no answer,
//! `unplug N` / `plug N` / `status` on standard input pull a station off the line and put it
//! back, the end of standard input does not stop the sim, lines that cannot be shared are
//! refused; and pymodbus (an implementation we did not write) reads two stations of one
//! line (`#[ignore]`d with the reason, run by `.ci/run` with `--ignored`).

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, Command, Output, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::Duration;

/// A `vfd sim` child serving several stations, its standard input and error at hand;
/// stopped (SIGTERM) when dropped.
struct Bus {
    child: Child,
    port: String,
    stdin: Option<ChildStdin>,
    stderr: Receiver<String>,
}

impl Bus {
    fn start(args: &[&str], stdin: Stdio) -> Bus {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg("sim")
            .args(args)
            .stdin(stdin)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("vfd sim starts");
        let mut first = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut first)
            .expect("the device path");
        let port = first.trim().to_owned();
        assert!(port.starts_with("/dev/"), "first line: {port:?}");
        let (send, stderr) = channel();
        let lines = BufReader::new(child.stderr.take().expect("piped"));
        std::thread::spawn(move || {
            for line in lines.lines().map_while(Result::ok) {
                if send.send(line).is_err() {
                    break;
                }
            }
        });
        let stdin = child.stdin.take();
        Bus {
            child,
            port,
            stdin,
            stderr,
        }
    }

    /// Sends `command` on standard input and returns the line that answers it.
    fn control(&mut self, command: &str) -> String {
        let stdin = self.stdin.as_mut().expect("standard input piped");
        writeln!(stdin, "{command}").unwrap();
        stdin.flush().unwrap();
        loop {
            let line = self
                .stderr
                .recv_timeout(Duration::from_secs(10))
                .unwrap_or_else(|_| panic!("no answer to `{command}`"));
            // The banner's lines come first.
            if line.starts_with("vfd sim: ") && !line.contains("virtual stations on") {
                return line;
            }
        }
    }

    /// `vfd read --drive DRIVE --protocol PROTOCOL --port PTY --address N CODE`.
    fn read(&self, drive: &str, protocol: &str, address: u8, code: &str) -> Output {
        Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(["read", "--drive", drive, "--protocol", protocol])
            .args([
                "--port",
                &self.port,
                "--address",
                &address.to_string(),
                code,
            ])
            .output()
            .expect("vfd read runs")
    }
}

impl Drop for Bus {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn answers(output: &Output, code: &str) {
    assert!(output.status.success(), "{}", text(output));
    assert!(text(output).starts_with(code), "{}", text(output));
}

fn silent(output: &Output) {
    assert!(!output.status.success(), "{}", text(output));
    assert!(text(output).contains("no reply"), "{}", text(output));
}

const THREE: [&str; 6] = [
    "--station",
    "fc51:modbus@1",
    "--station",
    "fc51:modbus@2",
    "--station",
    "vf-as1:modbus@3",
];

#[test]
fn three_stations_answer_at_their_addresses_and_unplug_and_plug_on_standard_input() {
    let mut bus = Bus::start(&THREE, Stdio::piped());
    answers(&bus.read("fc51", "modbus", 1, "303"), "303");
    answers(&bus.read("fc51", "modbus", 2, "303"), "303");
    answers(&bus.read("vf-as1", "modbus", 3, "FA01"), "FA01");
    // No station 4 on the line: nobody answers.
    silent(&bus.read("fc51", "modbus", 4, "303"));
    assert_eq!(
        bus.control("unplug 2"),
        "vfd sim: station 2 (fc51) unplugged"
    );
    silent(&bus.read("fc51", "modbus", 2, "303"));
    answers(&bus.read("fc51", "modbus", 1, "303"), "303");
    answers(&bus.read("vf-as1", "modbus", 3, "FA01"), "FA01");
    let status = bus.control("status");
    assert!(
        status.contains("station 1 fc51: 2 received, 2 answered, 0 writes")
            && status.contains("station 2 fc51 (unplugged): 2 received, 1 answered, 0 writes")
            && status.contains("station 3 vf-as1: 2 received, 2 answered, 0 writes"),
        "{status}"
    );
    assert_eq!(
        bus.control("plug 2"),
        "vfd sim: station 2 (fc51) plugged in"
    );
    answers(&bus.read("fc51", "modbus", 2, "303"), "303");
    let unknown = bus.control("reboot 2");
    assert!(unknown.contains("unknown command `reboot 2`"), "{unknown}");
    assert!(unknown.contains("unplug N, plug N"), "{unknown}");
}

#[test]
fn the_end_of_standard_input_does_not_stop_the_sim() {
    let bus = Bus::start(&THREE, Stdio::null());
    std::thread::sleep(Duration::from_millis(300));
    answers(&bus.read("vf-as1", "modbus", 3, "FA01"), "FA01");
    answers(&bus.read("fc51", "modbus", 1, "303"), "303");
}

#[test]
fn a_line_that_cannot_be_shared_is_refused() {
    let refused = |args: &[&str], says: &str| {
        let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg("sim")
            .args(args)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert!(!output.status.success());
        assert!(text(&output).contains(says), "{}", text(&output));
    };
    refused(
        &["--station", "fc51:modbus@1", "--station", "vf-as1:modbus@1"],
        "two stations at address 1",
    );
    refused(
        &["--station", "fc51:modbus@1", "--station", "vf-as1:binary@2"],
        "a line carries one framing",
    );
    refused(
        &[
            "--station",
            "vf-as1:modbus@1",
            "--station",
            "fc51:modbus@2",
            "--baud",
            "19200",
        ],
        "cannot be set to 19200 baud",
    );
    refused(&["--station", "fc51@300"], "no station address");
}

/// Fails when pymodbus is missing: the peer test is `#[ignore]`d (the `vfd` binary's
/// crate has no build script to find the package at build time), so it runs only when
/// asked for (`-- --ignored`, as `.ci/run` does), and then it must run.
fn require_pymodbus() {
    let installed = Command::new("python3")
        .args(["-c", "import pymodbus, serial"])
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        installed,
        "pymodbus is missing: pip install -r tests/python/requirements.txt"
    );
}

/// pymodbus reads (and writes) `plan` at `station` on `port`; its answers, one a line.
fn pymodbus(port: &str, station: u8, plan: &str) -> Vec<String> {
    let script = format!(
        "{}/../tests/python/modbus_peer_client.py",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut child = Command::new("python3")
        .args([&script, "pymodbus", port, &station.to_string(), "rtu"])
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
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| l.replace(' ', ""))
        .collect()
}

#[test]
#[ignore = "needs python3 with pymodbus: cargo test -p vfd-cli --test sim_bus -- --ignored (.ci/run does)"]
fn pymodbus_reads_two_stations_of_one_line() {
    require_pymodbus();
    let bus = Bus::start(
        &["--station", "dv1:modbus@1", "--station", "dv1:modbus@2"],
        Stdio::null(),
    );
    // 02-15 is at 00C3h: 60.00 Hz. Station 1 is set to 50.00 Hz; station 2 keeps 60.00 Hz.
    let one = pymodbus(
        &bus.port,
        1,
        r#"[{"op": "write", "address": 195, "value": 5000},
            {"op": "read", "address": 195, "count": 1}]"#,
    );
    assert_eq!(
        one,
        [
            r#"{"ok":true,"values":[5000]}"#,
            r#"{"ok":true,"values":[5000]}"#
        ]
    );
    let two = pymodbus(
        &bus.port,
        2,
        r#"[{"op": "read", "address": 195, "count": 1}]"#,
    );
    assert_eq!(two, [r#"{"ok":true,"values":[6000]}"#]);
}
