//! `vfd serve` end to end through a real MQTT broker: a private mosquitto on a free
//! loopback port, two virtual multi-drop buses (`vfd sim --station ...`, five stations of
//! three models), and mosquitto's own clients as the peer:
//!
//! - a retained state appears for every polled register of every station, and each
//!   station is `online`;
//! - `50 Hz` on a `set` topic reaches the virtual drive and reads back; `999 Hz`, and a
//!   register the plant does not allow, are refused on the result topic with the reason,
//!   and the virtual drive received exactly the one write frame;
//! - a station whose plug is pulled goes `offline` within its bound, the other stations
//!   on its bus are still polled, and the dead one is probed at most once per back-off
//!   period (rates are measured by the plant bench, not asserted here);
//! - the broker killed and started again (without persistence: its retained states are
//!   gone) is reconnected to, and the states come back;
//! - SIGTERM: the broker is told every station and the service are offline;
//! - hostile `set` messages (several MiB, not UTF-8, deeply nested JSON, huge numbers,
//!   empty) each get a short refusal, the service never loses the broker, and a good
//!   `set` afterwards is carried out.
//!
//! Without mosquitto these are `#[ignore]`d with the reason (cli/build.rs); under CI they
//! run (`.ci/run` installs mosquitto).

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

fn mosquitto() -> &'static str {
    [
        "/usr/sbin/mosquitto",
        "/usr/local/sbin/mosquitto",
        "/opt/homebrew/sbin/mosquitto",
    ]
    .into_iter()
    .find(|p| Path::new(p).exists())
    .unwrap_or("mosquitto")
}

/// A private mosquitto (no persistence), restartable on its port.
struct Broker {
    port: u16,
    config: PathBuf,
    child: Option<Child>,
}

impl Broker {
    fn start(dir: &Path) -> Broker {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let config = dir.join("mosquitto.conf");
        std::fs::write(
            &config,
            format!("listener {port} 127.0.0.1\npersistence false\nallow_anonymous true\n"),
        )
        .expect("config");
        let mut broker = Broker {
            port,
            config,
            child: None,
        };
        broker.run();
        broker
    }

    fn run(&mut self) {
        self.child = Some(
            Command::new(mosquitto())
                .arg("-c")
                .arg(&self.config)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("mosquitto starts"),
        );
        let end = Instant::now() + Duration::from_secs(10);
        while std::net::TcpStream::connect(("127.0.0.1", self.port)).is_err() {
            assert!(Instant::now() < end, "mosquitto listens");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn kill(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    fn publish(&self, topic: &str, payload: &str) {
        let status = Command::new("mosquitto_pub")
            .args(["-h", "127.0.0.1", "-p", &self.port.to_string(), "-q", "1"])
            .args(["-t", topic, "-m", payload])
            .status()
            .expect("mosquitto_pub runs");
        assert!(status.success());
    }

    /// Publishes `payload` (any bytes, of any size; empty: a zero-length message) on
    /// `topic` at QoS 1, from a file in `dir`.
    fn publish_bytes(&self, dir: &Path, topic: &str, payload: &[u8]) {
        let mut command = Command::new("mosquitto_pub");
        command.args(["-h", "127.0.0.1", "-p", &self.port.to_string(), "-q", "1"]);
        command.args(["-t", topic]);
        if payload.is_empty() {
            command.arg("-n");
        } else {
            let file = dir.join("payload.bin");
            std::fs::write(&file, payload).expect("payload file");
            command.arg("-f").arg(file);
        }
        assert!(command.status().expect("mosquitto_pub runs").success());
    }

    /// Every message on `filter` (retained ones first) as (time seen, topic, payload),
    /// collected by a `mosquitto_sub` child until it is dropped.
    fn subscribe(&self, filter: &str) -> Subscriber {
        let mut child = Command::new("mosquitto_sub")
            .args([
                "-h",
                "127.0.0.1",
                "-p",
                &self.port.to_string(),
                "-v",
                "-t",
                filter,
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("mosquitto_sub runs");
        let seen: Seen = Arc::default();
        let sink = seen.clone();
        let stdout = child.stdout.take().expect("piped");
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                let (topic, payload) = line.split_once(' ').unwrap_or((&line, ""));
                sink.lock()
                    .unwrap()
                    .push((Instant::now(), topic.to_owned(), payload.to_owned()));
            }
        });
        Subscriber { child, seen }
    }
}

impl Drop for Broker {
    fn drop(&mut self) {
        self.kill();
    }
}

type Seen = Arc<Mutex<Vec<(Instant, String, String)>>>;

struct Subscriber {
    child: Child,
    seen: Seen,
}

impl Subscriber {
    fn messages(&self) -> Vec<(Instant, String, String)> {
        self.seen.lock().unwrap().clone()
    }

    /// Waits up to `limit` for a message `matches` accepts.
    fn wait_for(
        &self,
        limit: Duration,
        what: &str,
        matches: impl Fn(&str, &str) -> bool,
    ) -> (Instant, String, String) {
        let end = Instant::now() + limit;
        loop {
            if let Some(found) = self.messages().into_iter().find(|(_, t, p)| matches(t, p)) {
                return found;
            }
            assert!(
                Instant::now() < end,
                "no {what} within {limit:?}; seen: {:#?}",
                self.messages()
                    .iter()
                    .rev()
                    .take(30)
                    .map(|(_, t, p)| format!("{t} {p}"))
                    .collect::<Vec<_>>()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Subscriber {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A `vfd sim --station ... -v` bus: its device, its standard input (controls) and its
/// log of answered exchanges.
struct SimBus {
    child: Child,
    port: String,
    stdin: ChildStdin,
    log: PathBuf,
}

impl SimBus {
    fn start(dir: &Path, name: &str, stations: &[&str]) -> SimBus {
        let log = dir.join(format!("{name}.log"));
        let mut command = Command::new(env!("CARGO_BIN_EXE_vfd"));
        command.args(["sim", "-v", "--baud", "9600", "--parity", "even"]);
        for station in stations {
            command.args(["--station", station]);
        }
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).expect("log"))
            .spawn()
            .expect("vfd sim starts");
        let mut first = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut first)
            .expect("the device");
        SimBus {
            port: first.trim().to_owned(),
            stdin: child.stdin.take().expect("piped"),
            child,
            log,
        }
    }

    fn control(&mut self, line: &str) {
        writeln!(self.stdin, "{line}").expect("the sim reads its controls");
        self.stdin.flush().expect("flushed");
    }

    /// Requests station `address` has received so far (answered or not), from the sim's
    /// `status` control.
    fn received(&mut self, address: u8) -> u64 {
        let before = std::fs::read_to_string(&self.log).unwrap_or_default().len();
        self.control("status");
        let end = Instant::now() + Duration::from_secs(5);
        loop {
            let log = std::fs::read_to_string(&self.log).unwrap_or_default();
            let fresh = log.get(before..).unwrap_or_default();
            if let Some(line) = fresh.lines().find(|l| l.contains("received, ")) {
                let station = format!("station {address} ");
                let part = line
                    .split("; ")
                    .find_map(|p| p.split_once(&station).map(|(_, rest)| rest))
                    .unwrap_or_else(|| panic!("station {address} in {line}"));
                let count = part
                    .split_once(": ")
                    .and_then(|(_, n)| n.split(' ').next())
                    .and_then(|n| n.parse().ok());
                return count.unwrap_or_else(|| panic!("a count in {line}"));
            }
            assert!(Instant::now() < end, "no status line from the sim");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The requests it answered, as hex.
    fn requests(&self) -> Vec<String> {
        std::fs::read_to_string(&self.log)
            .unwrap_or_default()
            .lines()
            .filter_map(|l| l.split_once(" request ").map(|(_, r)| r.trim().to_owned()))
            // `[N] ` names the station that answered.
            .map(|r| match r.split_once("] ") {
                Some((tag, rest)) if tag.starts_with('[') => rest.to_owned(),
                _ => r,
            })
            .collect()
    }
}

impl Drop for SimBus {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

/// `vfd serve PLANT --mqtt URL`, stopped (SIGTERM) when dropped.
struct Service(Child);

impl Drop for Service {
    fn drop(&mut self) {
        let _ = Command::new("kill").arg(self.0.id().to_string()).status();
        let _ = self.0.wait();
    }
}

/// How many back-off periods start within `window`: the first lasts `first_ms`, each next
/// one twice the last, up to `cap_ms`.
fn backoff_periods_within(first_ms: u64, cap_ms: u64, window: Duration) -> u64 {
    let (mut at, mut period, mut count) = (0, first_ms, 0);
    while at < window.as_millis() as u64 {
        count += 1;
        at += period;
        period = (period * 2).min(cap_ms);
    }
    count
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vfd-serve-mqtt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// A station: `(bus, name, drive, protocol, address, polled registers)`.
type Planned = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    u8,
    &'static [&'static str],
);

/// The stations of the two buses.
const STATIONS: [Planned; 5] = [
    ("line1", "fan1", "vf-as1", "modbus", 1, &["FD00", "FA01"]),
    ("line1", "pump1", "fc51", "modbus", 2, &["MAV", "STW"]),
    ("line1", "fan2", "vf-as1", "modbus", 3, &["FD00", "FA01"]),
    ("line2", "belt1", "yd1000", "binary", 1, &["FD00", "FA01"]),
    ("line2", "fan3", "vf-as1", "binary", 2, &["FD00", "FA01"]),
];

/// Starts the two virtual buses, the plant file and `vfd serve` publishing to `broker`.
fn plant(dir: &Path, broker: &Broker) -> (SimBus, SimBus, Service) {
    let specs = |bus: &str| -> Vec<String> {
        STATIONS
            .iter()
            .filter(|s| s.0 == bus)
            .map(|s| format!("{}:{}@{}", s.2, s.3, s.4))
            .collect()
    };
    let line1 = specs("line1");
    let line2 = specs("line2");
    let bus1 = SimBus::start(
        dir,
        "line1",
        &line1.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    let bus2 = SimBus::start(
        dir,
        "line2",
        &line2.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    let mut text = String::from("buses:\n");
    for (bus, port) in [("line1", &bus1.port), ("line2", &bus2.port)] {
        text.push_str(&format!(
            "  - name: {bus}\n    port: {port}\n    baud: 9600\n    parity: even\n    offline_after: 2\n    backoff: {{ first_ms: 500, cap_ms: 2000 }}\n    drives:\n"
        ));
        for (_, name, drive, protocol, address, registers) in STATIONS.iter().filter(|s| s.0 == bus)
        {
            text.push_str(&format!(
                "      - name: {name}\n        drive: {drive}\n        protocol: {protocol}\n        station: {address}\n        poll:\n          - every: 250ms\n            registers: [{}]\n",
                registers.join(", ")
            ));
            if *drive != "fc51" {
                text.push_str("        write: [FA01]\n");
            }
        }
    }
    let path = dir.join("plant.yaml");
    std::fs::write(&path, text).expect("plant file");
    let service = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .arg("serve")
        .arg(&path)
        .args(["--mqtt", &format!("mqtt://127.0.0.1:{}", broker.port)])
        .args([
            "--mqtt-client-id",
            &format!("vfd-test-{}", std::process::id()),
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(dir.join("serve.log")).expect("log"))
        .spawn()
        .expect("vfd serve starts");
    (bus1, bus2, Service(service))
}

/// Every polled register of every station has a retained state, and every station is online.
fn all_states(subscriber: &Subscriber, limit: Duration) {
    for (bus, name, _, _, _, registers) in STATIONS {
        for code in registers {
            let topic = format!("vfd/{bus}/{name}/{code}");
            let (_, _, payload) = subscriber.wait_for(limit, &topic, |t, _| t == topic);
            let state: serde_json::Value = serde_json::from_str(&payload).expect("JSON state");
            assert_eq!(state["code"], *code, "{payload}");
            assert!(state["raw"].is_u64(), "{payload}");
            assert!(state["time"].is_string(), "{payload}");
        }
        let topic = format!("vfd/{bus}/{name}/available");
        subscriber.wait_for(limit, &format!("{topic} online"), |t, p| {
            t == topic && p == "online"
        });
    }
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients); .ci/run installs it"
)]
fn states_writes_refusals_and_a_pulled_plug_through_the_broker() {
    let dir = temp_dir("plant");
    let broker = Broker::start(&dir);
    let everything = broker.subscribe("vfd/#");
    let (mut bus1, _bus2, _service) = plant(&dir, &broker);
    all_states(&everything, Duration::from_secs(15));

    // 50 Hz through MQTT reaches the drive and reads back.
    broker.publish("vfd/line1/fan1/FA01/set", "50 Hz");
    let (_, _, result) =
        everything.wait_for(Duration::from_secs(5), "the result of 50 Hz", |t, p| {
            t == "vfd/line1/fan1/FA01/set/result" && p.contains("\"request\":\"50 Hz\"")
        });
    let result: serde_json::Value = serde_json::from_str(&result).expect("JSON");
    assert_eq!(result["ok"], true, "{result}");
    everything.wait_for(Duration::from_secs(5), "FA01 read back as 50 Hz", |t, p| {
        t == "vfd/line1/fan1/FA01" && p.contains("\"value\":50.0")
    });
    // 999 Hz, and a register the plant does not allow: refused, nothing sent.
    broker.publish("vfd/line1/fan1/FA01/set", "999 Hz");
    broker.publish("vfd/line1/fan1/FH/set", "60");
    for (topic, request, says) in [
        (
            "vfd/line1/fan1/FA01/set/result",
            "999 Hz",
            "outside the range",
        ),
        ("vfd/line1/fan1/FH/set/result", "60", "does not allow"),
    ] {
        let (_, _, refused) = everything.wait_for(Duration::from_secs(5), "a refusal", |t, p| {
            t == topic && p.contains(&format!("\"request\":\"{request}\""))
        });
        let refused: serde_json::Value = serde_json::from_str(&refused).expect("JSON");
        assert_eq!(refused["ok"], false, "{refused}");
        assert_eq!(refused["sent"], false, "{refused}");
        assert!(
            refused["error"].as_str().unwrap_or_default().contains(says),
            "{refused}"
        );
    }
    // A state of fan1 received after both refusals was polled after its bus's worker took
    // them (one worker per bus, one line), and the sim logs a request before it answers: a
    // frame a refused write had sent would be in the log by then.
    let refusals = everything
        .messages()
        .iter()
        .rposition(|(_, t, _)| t.starts_with("vfd/line1/fan1/") && t.ends_with("/set/result"))
        .expect("the refusals were received");
    let end = Instant::now() + Duration::from_secs(10);
    while !everything.messages()[refusals + 1..]
        .iter()
        .any(|(_, t, _)| t == "vfd/line1/fan1/FD00" || t == "vfd/line1/fan1/FA01")
    {
        assert!(
            Instant::now() < end,
            "no state of fan1 after the refusals within 10 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let writes: Vec<String> = bus1
        .requests()
        .into_iter()
        .filter(|r| r.starts_with("01 06") || r.starts_with("01 10"))
        .collect();
    assert_eq!(
        writes.len(),
        1,
        "exactly the allowed write reached station 1: {writes:?}"
    );
    assert!(writes[0].starts_with("01 06 FA 01 13 88"), "{writes:?}");

    // Pull station 3's plug: offline within its bound; the other stations on its bus are
    // still polled; the dead station is probed at most once per back-off period (500 ms
    // doubling to 2 s). Rates are the plant bench's (BENCHMARKS.md), not a test's: whether
    // a probe lands inside a window depends on the machine's load.
    std::thread::sleep(Duration::from_secs(1));
    let pulled = Instant::now();
    bus1.control("unplug 3");
    // Two failed rounds of one reply timeout each (under 1 s at 9600 baud) after at most
    // one poll interval.
    let (offline_at, _, _) = everything.wait_for(Duration::from_secs(6), "fan2 offline", |t, p| {
        t == "vfd/line1/fan2/available" && p == "offline"
    });
    assert!(
        offline_at - pulled < Duration::from_secs(4),
        "offline after {:?}",
        offline_at - pulled
    );
    // The dead station's probes are counted by the sim between two of its status lines;
    // the window is what passed around both (at least 4 s, more on a loaded machine: a
    // late timer only ever probes less often).
    let watch_started = Instant::now();
    let probes_then = bus1.received(3);
    std::thread::sleep(Duration::from_secs(4));
    let probes = bus1.received(3) - probes_then;
    let watched = watch_started.elapsed();
    let states_since = |name: &str| {
        let prefix = format!("vfd/line1/{name}/");
        everything
            .messages()
            .iter()
            .filter(|(at, t, _)| {
                *at > offline_at
                    && t.starts_with(&prefix)
                    && !t.ends_with("available")
                    && !t.contains("/set")
            })
            .count()
    };
    for name in ["fan1", "pump1"] {
        // Two registers every 250 ms, a dead neighbour costing at most a reply timeout per
        // back-off period: four states after it went offline are waited for, within a
        // bound on a hang (a count in a slept window would be a rate).
        let end = Instant::now() + Duration::from_secs(20);
        while states_since(name) < 4 {
            assert!(
                Instant::now() < end,
                "{name} is still polled beside a dead station: {} states since it went offline",
                states_since(name)
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    // Back-off periods of 0.5, 1, 2, 2, ... s: no window holds more period starts than one
    // of the same length from going offline, and one probe may have been under way when
    // the count was taken.
    let periods = backoff_periods_within(500, 2000, watched);
    assert!(
        probes <= periods + 1,
        "the dead station was probed {probes} times in {watched:?}: more than once per back-off period ({periods} periods)"
    );
    bus1.control("plug 3");
    everything.wait_for(Duration::from_secs(6), "fan2 online again", |t, p| {
        t == "vfd/line1/fan2/available"
            && p == "online"
            && everything
                .messages()
                .iter()
                .any(|(at, tt, pp)| *at > offline_at && tt == t && pp == p)
    });
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients); .ci/run installs it"
)]
fn a_restarted_broker_is_reconnected_to_and_the_states_come_back() {
    let dir = temp_dir("restart");
    let mut broker = Broker::start(&dir);
    let (_bus1, _bus2, service) = plant(&dir, &broker);
    {
        let first = broker.subscribe("vfd/#");
        all_states(&first, Duration::from_secs(15));
    }
    broker.kill();
    std::thread::sleep(Duration::from_secs(1));
    broker.run();
    // A new broker without persistence: whatever it holds now was published again.
    let again = broker.subscribe("vfd/#");
    all_states(&again, Duration::from_secs(20));
    again.wait_for(Duration::from_secs(5), "the service's status", |t, p| {
        t == "vfd/status" && p == "online"
    });
    // SIGTERM: the broker is told every station and the service are offline. (A new
    // subscriber: its retained messages are the latest, `online`; `offline` comes live.)
    let last = broker.subscribe("vfd/#");
    last.wait_for(Duration::from_secs(5), "the retained status", |t, p| {
        t == "vfd/status" && p == "online"
    });
    let again = last;
    let stopped = Instant::now();
    drop(service);
    for (bus, name, ..) in STATIONS {
        let topic = format!("vfd/{bus}/{name}/available");
        again.wait_for(
            Duration::from_secs(5),
            &format!("{topic} offline"),
            |t, p| t == topic && p == "offline",
        );
    }
    let (at, _, _) = again.wait_for(Duration::from_secs(5), "the service offline", |t, p| {
        t == "vfd/status" && p == "offline"
    });
    assert!(at >= stopped, "offline only once stopped");
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients); .ci/run installs it"
)]
fn demo_plant_publishes_every_station_and_takes_50_hz_but_not_999() {
    let dir = temp_dir("demo");
    let broker = Broker::start(&dir);
    let everything = broker.subscribe("vfd/#");
    let _demo = Service(
        Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(["demo", "--plant", "--seconds", "30"])
            .args(["--mqtt", &format!("mqtt://127.0.0.1:{}", broker.port)])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("vfd demo starts"),
    );
    // The built-in plant: line1 fc51 pump1, pump2, vf-as1 fan1; line2 yd1000 conveyor1, vf-as1 fan2.
    for (bus, drive) in [
        ("line1", "pump1"),
        ("line1", "pump2"),
        ("line1", "fan1"),
        ("line2", "conveyor1"),
        ("line2", "fan2"),
    ] {
        let available = format!("vfd/{bus}/{drive}/available");
        everything.wait_for(Duration::from_secs(15), &available, |t, p| {
            t == available && p == "online"
        });
        let state = format!("vfd/{bus}/{drive}/");
        everything.wait_for(Duration::from_secs(5), "a state", |t, p| {
            t.starts_with(&state) && p.starts_with('{')
        });
    }
    broker.publish("vfd/line1/fan1/FA01/set", "50 Hz");
    broker.publish("vfd/line1/fan1/FA01/set", "999 Hz");
    everything.wait_for(Duration::from_secs(5), "50 Hz carried out", |t, p| {
        t == "vfd/line1/fan1/FA01/set/result"
            && p.contains("\"request\":\"50 Hz\"")
            && p.contains("\"ok\":true")
    });
    everything.wait_for(
        Duration::from_secs(5),
        "999 Hz refused, nothing sent",
        |t, p| {
            t == "vfd/line1/fan1/FA01/set/result"
                && p.contains("\"request\":\"999 Hz\"")
                && p.contains("\"ok\":false")
                && p.contains("\"sent\":false")
        },
    );
    everything.wait_for(Duration::from_secs(5), "50 Hz read back", |t, p| {
        t == "vfd/line1/fan1/FA01" && p.contains("\"value\":50.0")
    });
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients); .ci/run installs it"
)]
fn hostile_set_messages_are_refused_and_never_cost_the_connection() {
    let dir = temp_dir("hostile");
    let broker = Broker::start(&dir);
    let topic = "vfd/line1/fan1/FA01/set";
    let states = broker.subscribe("vfd/+/+/+");
    // Only the results: the `set` messages themselves are not text.
    let results = broker.subscribe(&format!("{topic}/result"));
    let (_bus1, _bus2, _service) = plant(&dir, &broker);
    all_states(&states, Duration::from_secs(15));
    let deep_json = format!("{{\"value\": {}{}}}", "[".repeat(400), "]".repeat(400));
    let binary: Vec<u8> = (0u32..5 * 1024 * 1024)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let hostile: Vec<(&str, Vec<u8>)> = vec![
        // Larger than rumqttc's default limit (256 KiB), which used to end the connection.
        ("300 KiB of digits", vec![b'5'; 300 * 1024]),
        ("5 MiB of binary", binary),
        (
            "1 MiB in JSON",
            format!("{{\"value\": \"{}\"}}", "A".repeat(1024 * 1024)).into_bytes(),
        ),
        ("not UTF-8", vec![0xff, 0xfe, 0x00, 0x80, 0xc3]),
        ("deeply nested JSON", deep_json.into_bytes()),
        ("100 KB of brackets", "[".repeat(100_000).into_bytes()),
        ("a huge number", b"1e999999".to_vec()),
        ("a huge JSON number", b"{\"value\": 1e999999}".to_vec()),
        ("a thousand digits", vec![b'9'; 1000]),
        ("null", b"{\"value\": null}".to_vec()),
        ("empty", Vec::new()),
    ];
    for (count, (what, payload)) in hostile.iter().enumerate() {
        broker.publish_bytes(&dir, topic, payload);
        results.wait_for(
            Duration::from_secs(10),
            &format!("the refusal of {what}"),
            |_, _| results.messages().len() > count,
        );
        let (_, _, result) = results.messages()[count].clone();
        assert!(
            result.len() < 1024,
            "{what}: a {} byte result",
            result.len()
        );
        let result: serde_json::Value = serde_json::from_str(&result).expect("JSON");
        assert_eq!(result["ok"], false, "{what}: {result}");
        assert_eq!(result["sent"], false, "{what}: {result}");
        assert!(result["error"].is_string(), "{what}: {result}");
    }
    // The 300 KiB message's result repeats its start and its size only.
    let first: serde_json::Value = serde_json::from_str(&results.messages()[0].2).expect("JSON");
    assert_eq!(
        first["request"],
        format!("{}… (307200 bytes)", "5".repeat(64)),
        "{first}"
    );
    // A good set is still carried out and read back.
    broker.publish(topic, "50 Hz");
    let (_, _, result) = results.wait_for(Duration::from_secs(5), "the result of 50 Hz", |_, p| {
        p.contains("\"request\":\"50 Hz\"")
    });
    assert!(result.contains("\"ok\":true"), "{result}");
    states.wait_for(Duration::from_secs(5), "FA01 read back as 50 Hz", |t, p| {
        t == "vfd/line1/fan1/FA01" && p.contains("\"value\":50.0")
    });
    // The connection was never lost, and no line of the log repeats a request whole.
    let log = std::fs::read_to_string(dir.join("serve.log")).expect("the service's log");
    assert!(
        !log.contains("lost the broker") && !log.contains("reconnected"),
        "{log}"
    );
    assert!(
        log.lines().all(|line| line.len() < 1024),
        "a log line of {} bytes",
        log.lines().map(str::len).max().unwrap_or(0)
    );
    assert_eq!(
        results.messages().len(),
        hostile.len() + 1,
        "one result each"
    );
}
