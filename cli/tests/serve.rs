//! `vfd serve` end to end against virtual drives served over TCP (`vfd sim --listen`, a
//! serial device server's raw frames), with `--jsonl` out and `--stdin-writes` in:
//!
//! - readings and availability appear; a write the plant allows is carried out and read
//!   back; one out of range, one the plant does not allow and one to an unknown drive are
//!   refused with the reason, and the virtual drive received exactly one write frame;
//! - a bus whose device server goes away is reported offline and reopened with back-off,
//!   while another bus keeps its polling rate;
//! - a port that is not there at the start is opened once it appears;
//! - SIGTERM ends the service within a bound, every station reported offline;
//! - a closed standard output ends it quietly; no output chosen is a clear error;
//! - a request of 200 KB gets a short result and log line; result ids differ from one
//!   run to the next;
//! - the bit-field example of docs/mqtt.md is a value a shipped drive takes.
//!
//! The multi-drop bus (several stations on one line) and MQTT are tested in
//! `serve_plant.rs` and `serve_mqtt.rs`.

use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A `vfd sim --listen` child on a given or free port, stopped when dropped.
struct TcpSim {
    child: Child,
    port: String,
    log: PathBuf,
}

impl TcpSim {
    /// A VF-AS1 on Modbus RTU at station 1.
    fn start(dir: &Path, name: &str, listen: &str) -> TcpSim {
        TcpSim::start_drive(dir, name, listen, "vf-as1", "modbus")
    }

    /// A `drive` speaking `protocol` at station 1.
    fn start_drive(dir: &Path, name: &str, listen: &str, drive: &str, protocol: &str) -> TcpSim {
        let log = dir.join(format!("{name}.log"));
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(["sim", "-d", drive, "-p", protocol, "--address", "1", "-v"])
            .args(["--listen", listen])
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).expect("log file"))
            .spawn()
            .expect("vfd sim starts");
        let mut first = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut first)
            .expect("the address");
        TcpSim {
            child,
            port: first.trim().to_owned(),
            log,
        }
    }

    /// The requests it logged (`-v`), as hex.
    fn requests(&self) -> Vec<String> {
        std::fs::read_to_string(&self.log)
            .unwrap_or_default()
            .lines()
            .filter_map(|l| {
                l.split_once(" request ")
                    .map(|(_, r)| r.split("  ").next().unwrap_or(r).trim().to_owned())
            })
            .collect()
    }

    fn stop(&mut self) {
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

impl Drop for TcpSim {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Events with the time each was seen.
type Seen = Arc<Mutex<Vec<(Instant, Value)>>>;

/// A `vfd serve PLANT --jsonl --stdin-writes` child; its events collected as they come.
struct Service {
    child: Child,
    stdin: Option<ChildStdin>,
    events: Seen,
    stderr: Arc<Mutex<String>>,
}

impl Service {
    fn start(plant: &Path) -> Service {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(["serve", "--jsonl", "--stdin-writes"])
            .arg(plant)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("vfd serve starts");
        let events: Seen = Arc::default();
        let stdout = child.stdout.take().expect("piped");
        let sink = events.clone();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                let value: Value = serde_json::from_str(&line)
                    .unwrap_or_else(|e| panic!("not JSON ({e}): {line}"));
                sink.lock().unwrap().push((Instant::now(), value));
            }
        });
        let stderr = Arc::new(Mutex::new(String::new()));
        let mut err = child.stderr.take().expect("piped");
        let sink = stderr.clone();
        std::thread::spawn(move || {
            let mut text = String::new();
            let mut buf = [0u8; 4096];
            while let Ok(n) = err.read(&mut buf) {
                if n == 0 {
                    break;
                }
                text.push_str(&String::from_utf8_lossy(&buf[..n]));
                *sink.lock().unwrap() = text.clone();
            }
        });
        Service {
            stdin: child.stdin.take(),
            child,
            events,
            stderr,
        }
    }

    fn write(&mut self, bus: &str, drive: &str, register: &str, value: &str) {
        let line =
            serde_json::json!({"bus": bus, "drive": drive, "register": register, "value": value});
        let stdin = self.stdin.as_mut().expect("stdin open");
        writeln!(stdin, "{line}").expect("the service reads");
        stdin.flush().expect("flushed");
    }

    fn events(&self) -> Vec<(Instant, Value)> {
        self.events.lock().unwrap().clone()
    }

    /// Waits up to `limit` for an event `matches` accepts; returns it.
    fn wait_for(
        &self,
        limit: Duration,
        what: &str,
        matches: impl Fn(&Value) -> bool,
    ) -> (Instant, Value) {
        let (_, at, event) = self.wait_for_after(0, limit, what, matches);
        (at, event)
    }

    /// Waits up to `limit` for an event `matches` accepts among those from the `from`th
    /// on (in the order the service printed them); returns it with its place.
    fn wait_for_after(
        &self,
        from: usize,
        limit: Duration,
        what: &str,
        matches: impl Fn(&Value) -> bool,
    ) -> (usize, Instant, Value) {
        let end = Instant::now() + limit;
        loop {
            let found = self
                .events()
                .into_iter()
                .enumerate()
                .skip(from)
                .find(|(_, (_, e))| matches(e));
            if let Some((place, (at, event))) = found {
                return (place, at, event);
            }
            assert!(
                Instant::now() < end,
                "no {what} within {limit:?}; events: {:#?}\nstderr: {}",
                self.events()
                    .iter()
                    .map(|(_, e)| e.to_string())
                    .collect::<Vec<_>>(),
                self.stderr.lock().unwrap()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// SIGTERM, then the exit status within `limit`.
    fn terminate(&mut self, limit: Duration) -> std::process::ExitStatus {
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let end = Instant::now() + limit;
        loop {
            if let Some(status) = self.child.try_wait().expect("wait") {
                return status;
            }
            assert!(
                Instant::now() < end,
                "vfd serve still runs {limit:?} after SIGTERM"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn event_is(e: &Value, kind: &str, bus: &str, drive: &str) -> bool {
    e["event"] == kind && e["bus"] == bus && (drive.is_empty() || e["drive"] == drive)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vfd-serve-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// A plant file of one VF-AS1 (Modbus RTU, station 1) per bus, `(bus name, port)`.
fn plant(dir: &Path, buses: &[(&str, &str)], every: &str) -> PathBuf {
    let mut text = String::from("buses:\n");
    for (name, port) in buses {
        text.push_str(&format!(
            "  - name: {name}\n    port: {port}\n    offline_after: 2\n    backoff: {{ first_ms: 200, cap_ms: 1000 }}\n    drives:\n      - name: pump1\n        drive: vf-as1\n        protocol: modbus\n        station: 1\n        poll:\n          - every: {every}\n            registers: [FD00, FD01, FA01]\n        write:\n          - FA01\n"
        ));
    }
    let path = dir.join("plant.yaml");
    std::fs::write(&path, text).expect("plant file");
    path
}

/// The write requests (function 06) among a sim's logged requests.
fn write_frames(sim: &TcpSim) -> Vec<String> {
    sim.requests()
        .into_iter()
        .filter(|r| r.starts_with("01 06"))
        .collect()
}

#[test]
fn writes_are_checked_carried_out_once_and_read_back() {
    let dir = temp_dir("writes");
    let sim = TcpSim::start(&dir, "sim", "127.0.0.1:0");
    let mut service = Service::start(&plant(&dir, &[("line1", &sim.port)], "500ms"));
    service.wait_for(Duration::from_secs(10), "online", |e| {
        event_is(e, "availability", "line1", "pump1") && e["online"] == true
    });
    service.write("line1", "pump1", "FA01", "50 Hz");
    let (_, ok) = service.wait_for(Duration::from_secs(5), "the write's outcome", |e| {
        e["event"] == "written" && e["request"] == "50 Hz"
    });
    assert_eq!(ok["ok"], true, "{ok}");
    assert_eq!(ok["sent"], true);
    assert_eq!(ok["raw"], 5000);
    assert_eq!(ok["code"], "FA01");
    // Read back: the frequency command now reads 50 Hz.
    service.wait_for(Duration::from_secs(5), "FA01 read back as 50 Hz", |e| {
        e["event"] == "reading" && e["code"] == "FA01" && e["value"] == 50.0
    });
    // Out of range, not allowed by the plant, an unknown drive: refused, nothing sent.
    service.write("line1", "pump1", "FA01", "999");
    service.write("line1", "pump1", "FH", "60");
    service.write("line1", "pump9", "FA01", "10");
    service.write("line9", "pump1", "FA01", "10");
    for (drive, request, code, says) in [
        ("pump1", "999", "FA01", "outside the range"),
        ("pump1", "60", "FH", "the plant file does not allow it"),
        ("pump9", "10", "FA01", "no drive `pump9`"),
    ] {
        let (_, refused) = service.wait_for(Duration::from_secs(5), "a refusal", |e| {
            event_is(e, "written", "line1", drive) && e["request"] == request && e["code"] == code
        });
        assert_eq!(refused["ok"], false, "{refused}");
        assert_eq!(refused["sent"], false, "{refused}");
        let error = refused["error"].as_str().unwrap_or_default();
        assert!(error.contains(says), "{error}");
        assert!(error.contains("nothing was sent"), "{error}");
    }
    service.wait_for(Duration::from_secs(5), "the unknown bus refused", |e| {
        e["event"] == "written" && e["bus"] == "line9" && e["ok"] == false
    });
    // A reading printed after line1's refusals was polled after its worker took them (one
    // worker per bus, one line), and the sim logs a request before it answers: a frame a
    // refused write had sent would be in the log by then. Then count: the one write that
    // was allowed.
    let refusals = service
        .events()
        .iter()
        .rposition(|(_, e)| event_is(e, "written", "line1", "") && e["ok"] == false)
        .expect("line1's refusals were printed");
    service.wait_for_after(
        refusals + 1,
        Duration::from_secs(10),
        "a reading of line1 after its refusals",
        |e| event_is(e, "reading", "line1", "pump1"),
    );
    assert_eq!(
        write_frames(&sim),
        ["01 06 FA 01 13 88 E5 84"],
        "one write frame on the line"
    );
}

#[test]
fn a_bus_that_fails_is_reopened_and_the_other_bus_keeps_its_rate() {
    let dir = temp_dir("buses");
    let steady = TcpSim::start(&dir, "steady", "127.0.0.1:0");
    let mut failing = TcpSim::start(&dir, "failing", "127.0.0.1:0");
    let failing_port = failing.port.clone();
    let service = Service::start(&plant(
        &dir,
        &[("line1", &steady.port), ("line2", &failing.port)],
        "200ms",
    ));
    for bus in ["line1", "line2"] {
        service.wait_for(Duration::from_secs(10), "online", |e| {
            event_is(e, "availability", bus, "pump1") && e["online"] == true
        });
    }
    std::thread::sleep(Duration::from_secs(2));
    let killed = Instant::now();
    failing.stop();
    let (offline_at, offline) = service.wait_for(Duration::from_secs(5), "line2 offline", |e| {
        event_is(e, "availability", "line2", "pump1") && e["online"] == false
    });
    assert!(
        offline_at - killed < Duration::from_secs(2),
        "offline after {:?}",
        offline_at - killed
    );
    assert!(
        offline["reason"]
            .as_str()
            .unwrap_or_default()
            .contains(failing_port.trim_start_matches("tcp://")),
        "{offline}"
    );
    let (port_failed, _) = service.wait_for(Duration::from_secs(1), "line2's port failed", |e| {
        event_is(e, "port", "line2", "") && e["open"] == false
    });
    // line1 is still polled after line2's port failed: each bus has its own worker, so
    // line1's readings go on (3 registers every 200 ms), five of them waited for within a
    // bound on a hang. The rate itself is the plant bench's to measure (BENCHMARKS.md), not
    // a test's: a count in a slept window would be one.
    let line1_since = || {
        service
            .events()
            .iter()
            .filter(|(t, e)| *t > port_failed && event_is(e, "reading", "line1", "pump1"))
            .count()
    };
    let end = Instant::now() + Duration::from_secs(20);
    while line1_since() < 5 {
        assert!(
            Instant::now() < end,
            "line1 is still polled after line2 failed: {} readings; events: {:#?}",
            line1_since(),
            service
                .events()
                .iter()
                .map(|(_, e)| e.to_string())
                .collect::<Vec<_>>()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    // The device server comes back on the same port: line2 is reopened and online again.
    let _back = TcpSim::start(&dir, "back", failing_port.trim_start_matches("tcp://"));
    let (_, online) = service.wait_for(Duration::from_secs(8), "line2 online again", |e| {
        event_is(e, "availability", "line2", "pump1")
            && e["online"] == true
            && e["time"].as_str() > offline["time"].as_str()
    });
    assert_eq!(online["reason"], Value::Null);
}

#[test]
fn a_port_that_appears_later_is_opened() {
    let dir = temp_dir("later");
    let free = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
    let address = free.local_addr().expect("address").to_string();
    drop(free);
    let service = Service::start(&plant(
        &dir,
        &[("line1", &format!("tcp://{address}"))],
        "500ms",
    ));
    let (_, offline) = service.wait_for(Duration::from_secs(5), "offline", |e| {
        event_is(e, "availability", "line1", "pump1") && e["online"] == false
    });
    assert!(
        offline["reason"]
            .as_str()
            .unwrap_or_default()
            .contains("refused"),
        "{offline}"
    );
    std::thread::sleep(Duration::from_secs(1));
    let _sim = TcpSim::start(&dir, "sim", &address);
    service.wait_for(
        Duration::from_secs(8),
        "online once the port is there",
        |e| event_is(e, "availability", "line1", "pump1") && e["online"] == true,
    );
    service.wait_for(Duration::from_secs(3), "a reading", |e| {
        event_is(e, "reading", "line1", "pump1")
    });
}

#[test]
fn sigterm_reports_every_station_offline_and_ends() {
    let dir = temp_dir("sigterm");
    let a = TcpSim::start(&dir, "a", "127.0.0.1:0");
    let b = TcpSim::start(&dir, "b", "127.0.0.1:0");
    let mut service = Service::start(&plant(
        &dir,
        &[("line1", &a.port), ("line2", &b.port)],
        "200ms",
    ));
    for bus in ["line1", "line2"] {
        service.wait_for(Duration::from_secs(10), "online", |e| {
            event_is(e, "availability", bus, "pump1") && e["online"] == true
        });
    }
    let status = service.terminate(Duration::from_secs(3));
    assert!(
        status.success(),
        "{status:?}: {}",
        service.stderr.lock().unwrap()
    );
    // The service has ended: its last lines are read from the pipe by our reader thread.
    for bus in ["line1", "line2"] {
        service.wait_for(Duration::from_secs(10), "offline at the end", |e| {
            event_is(e, "availability", bus, "pump1")
                && e["online"] == false
                && e["reason"] == "the service stopped"
        });
    }
    let stderr = service.stderr.lock().unwrap().clone();
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_closed_standard_output_ends_the_service_quietly() {
    let dir = temp_dir("pipe");
    let sim = TcpSim::start(&dir, "sim", "127.0.0.1:0");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["serve", "--jsonl"])
        .arg(plant(&dir, &[("line1", &sim.port)], "100ms"))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("vfd serve starts");
    let mut stdout = child.stdout.take().expect("piped");
    let mut first = [0u8; 1];
    stdout.read_exact(&mut first).expect("some output");
    drop(stdout);
    let end = Instant::now() + Duration::from_secs(5);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        assert!(
            Instant::now() < end,
            "vfd serve still runs with its standard output closed"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .expect("piped")
        .read_to_string(&mut stderr)
        .expect("stderr");
    assert!(status.success(), "{status:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn without_an_output_it_says_which_to_choose() {
    let dir = temp_dir("no-output");
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .arg("serve")
        .arg(plant(&dir, &[("line1", "tcp://127.0.0.1:9")], "1s"))
        .output()
        .expect("vfd runs");
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("--jsonl"), "{stderr}");
}

#[test]
fn demo_plant_polls_every_station_of_both_buses_and_ends() {
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["demo", "--plant", "--seconds", "3"])
        .stdin(Stdio::null())
        .output()
        .expect("vfd demo runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let events: Vec<Value> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect();
    let stations: std::collections::BTreeSet<(String, String, String)> = events
        .iter()
        .filter(|e| e["event"] == "reading")
        .map(|e| {
            (
                e["bus"].as_str().unwrap_or_default().to_owned(),
                e["drive"].as_str().unwrap_or_default().to_owned(),
                e["model"].as_str().unwrap_or_default().to_owned(),
            )
        })
        .collect();
    let buses: std::collections::BTreeSet<&str> = stations.iter().map(|s| s.0.as_str()).collect();
    let models: std::collections::BTreeSet<&str> = stations.iter().map(|s| s.2.as_str()).collect();
    assert!(buses.len() >= 2, "{stations:?}");
    assert!(stations.len() >= 3, "{stations:?}");
    assert!(models.len() >= 2, "{stations:?}");
    for (bus, drive, _) in &stations {
        assert!(
            events
                .iter()
                .any(|e| event_is(e, "availability", bus, drive)
                    && e["online"] == false
                    && e["reason"] == "the service stopped"),
            "{bus}/{drive} reported offline at the end"
        );
    }
}

#[test]
fn a_huge_request_gets_a_short_answer_and_ids_differ_across_restarts() {
    let dir = temp_dir("ids");
    let sim = TcpSim::start(&dir, "sim", "127.0.0.1:0");
    let plant = plant(&dir, &[("line1", &sim.port)], "500ms");
    let mut ids = Vec::new();
    for run in 0..2 {
        let mut service = Service::start(&plant);
        service.wait_for(Duration::from_secs(10), "online", |e| {
            event_is(e, "availability", "line1", "pump1") && e["online"] == true
        });
        // A 200 KB value, then a plain one, on standard input.
        service.write("line1", "pump1", "FA01", &"5".repeat(200 * 1024));
        service.write("line1", "pump1", "FA01", "999");
        let (_, long) = service.wait_for(Duration::from_secs(5), "the long line refused", |e| {
            e["event"] == "written" && e["error"].as_str().unwrap_or_default().contains("bytes")
        });
        let text = long.to_string();
        assert!(text.len() < 1024, "a {} byte result", text.len());
        assert!(
            long["request"]
                .as_str()
                .unwrap_or_default()
                .contains("bytes)"),
            "{long}"
        );
        let (_, plain) = service.wait_for(Duration::from_secs(5), "999 refused", |e| {
            e["event"] == "written" && e["request"] == "999"
        });
        ids.push((long["id"].clone(), plain["id"].clone()));
        service.terminate(Duration::from_secs(3));
        let stderr = service.stderr.lock().unwrap().clone();
        assert!(
            stderr.lines().all(|l| l.len() < 1024),
            "run {run}: a log line of {} bytes",
            stderr.lines().map(str::len).max().unwrap_or(0)
        );
    }
    // `RUN-N`, RUN the start time and process id: never the same in two runs.
    for (long, plain) in &ids {
        for id in [long, plain] {
            let text = id.as_str().unwrap_or_else(|| panic!("a text id: {id}"));
            let parts: Vec<&str> = text.split('-').collect();
            assert_eq!(parts.len(), 3, "{text}");
            assert!(parts.iter().all(|p| p.parse::<u64>().is_ok()), "{text}");
        }
    }
    assert_ne!(ids[0].0, ids[1].0, "{ids:?}");
    assert_ne!(ids[0].1, ids[1].1, "{ids:?}");
}

/// The bit-field value docs/mqtt.md gives as its example: the backquoted text after "bit
/// fields by name (", and the drive and register it names.
fn documented_bit_fields() -> (String, String, String) {
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/mqtt.md"))
        .expect("docs/mqtt.md")
        .replace('\n', " ");
    let after = docs
        .split_once("bit fields by name (`")
        .expect("docs/mqtt.md gives a bit-field example")
        .1;
    let (value, rest) = after.split_once('`').expect("a closing backquote");
    // "`VALUE` on a DRIVE's REGISTER"
    let rest = rest
        .strip_prefix(" on a ")
        .expect("the example names its drive: `VALUE` on a DRIVE's REGISTER");
    let (drive, rest) = rest.split_once("'s ").expect("DRIVE's");
    let register: String = rest
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect();
    (value.to_owned(), drive.to_lowercase(), register)
}

#[test]
fn the_documented_bit_field_example_is_written_by_a_shipped_drive() {
    let (value, drive, register) = documented_bit_fields();
    let dir = temp_dir("bits");
    let sim = TcpSim::start_drive(&dir, "sim", "127.0.0.1:0", &drive, "binary");
    let text = format!(
        "buses:\n  - name: line1\n    port: {}\n    drives:\n      - name: belt1\n        drive: {drive}\n        protocol: binary\n        station: 1\n        poll:\n          - every: 500ms\n            registers: [FA01]\n        write: [{register}]\n",
        sim.port
    );
    let path = dir.join("plant.yaml");
    std::fs::write(&path, text).expect("plant file");
    let mut service = Service::start(&path);
    service.wait_for(Duration::from_secs(10), "online", |e| {
        event_is(e, "availability", "line1", "belt1") && e["online"] == true
    });
    service.write("line1", "belt1", &register, &value);
    let (_, outcome) = service.wait_for(Duration::from_secs(5), "the example's outcome", |e| {
        e["event"] == "written" && e["request"] == value.as_str()
    });
    assert_eq!(
        outcome["ok"], true,
        "{drive} {register} = {value}: {outcome}"
    );
    assert_eq!(outcome["sent"], true, "{outcome}");
}
