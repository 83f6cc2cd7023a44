//! A watch that outlives the line: dropped replies leave stale values and count errors, an
//! unplugged adapter (the `vfd sim` serving the pseudo-terminal stopped, another started
//! behind the same link) does not end it, Ctrl-C ends it with status 0, and it fails only
//! when no read ever succeeded. Bounds are generous; nothing is timed.

mod common;

use common::Sim;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

fn record(line: &str) -> serde_json::Value {
    serde_json::from_str(line).unwrap_or_else(|e| panic!("not JSON ({e}): {line}"))
}

/// Waits for `child` at most a minute (killed and failed beyond).
fn wait(child: &mut Child) -> ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            return status;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("the watch did not end within a minute");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn watch(port: &str, extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args([
            "watch",
            "--drive",
            "yd1000",
            "--protocol",
            "binary",
            "--port",
            port,
        ])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("vfd watch starts")
}

#[test]
fn a_watch_through_dropped_replies_gives_every_sample() {
    let sim = Sim::start_with(
        "yd1000",
        "binary",
        &["--fault", "drop-reply", "--fault", "drop-reply"],
    );
    let output = sim.vfd(
        "yd1000",
        "binary",
        &[
            "watch",
            "FH",
            "--count",
            "4",
            "--interval",
            "50",
            "--format",
            "jsonl",
        ],
    );
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", common::text(&output));
    let records: Vec<serde_json::Value> = text.lines().map(record).collect();
    assert_eq!(records.len(), 4, "four samples: {text}");
    let stale: Vec<&serde_json::Value> = records.iter().filter(|r| r["stale"] == true).collect();
    assert_eq!(stale.len(), 2, "the two dropped replies: {text}");
    assert_eq!(stale[0]["error_kind"], "timeout");
    assert!(stale[0]["error_meaning"]
        .as_str()
        .is_some_and(|m| !m.is_empty()));
    assert!(stale[0]["tripped"].is_null());
    let good: Vec<&serde_json::Value> = records.iter().filter(|r| r["stale"] == false).collect();
    assert!(!good.is_empty());
    assert_eq!(good[0]["value"], 80.0);
    assert_eq!(records[3]["errors"], 2, "errors are counted: {text}");
    let samples: Vec<u64> = records
        .iter()
        .map(|r| r["sample"].as_u64().unwrap())
        .collect();
    assert_eq!(samples, [1, 2, 3, 4]);

    // Text marks the stale value and counts the errors in its footer.
    let sim = Sim::start_with("yd1000", "binary", &["--fault", "drop-reply"]);
    let output = sim.vfd(
        "yd1000",
        "binary",
        &["watch", "FH", "--count", "3", "--interval", "50"],
    );
    let all = common::text(&output);
    assert!(output.status.success(), "{all}");
    assert!(all.contains("[stale: timeout]"), "{all}");
    assert!(
        all.contains("3 samples, 1 failed read (stale values marked)"),
        "{all}"
    );
}

#[test]
fn a_watch_that_never_reads_fails() {
    let sim = Sim::start_with("yd1000", "binary", &["--fault", "noise"]);
    let output = sim.vfd(
        "yd1000",
        "binary",
        &[
            "watch",
            "FH",
            "--count",
            "2",
            "--interval",
            "50",
            "--format",
            "jsonl",
        ],
    );
    assert!(!output.status.success(), "{}", common::text(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("no read succeeded in 2 sample(s)"),
        "{stderr}"
    );
    assert_eq!(String::from_utf8_lossy(&output.stdout).lines().count(), 2);
}

#[test]
fn an_unplugged_and_replugged_port_does_not_end_the_watch() {
    let dir = std::env::temp_dir().join(format!("vfd-replug-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let link = dir.join("ttyVFD");
    let first = Sim::start("yd1000", "binary");
    std::os::unix::fs::symlink(&first.port, &link).unwrap();
    let mut child = watch(
        link.to_str().unwrap(),
        &[
            "FH",
            "--count",
            "12",
            "--interval",
            "100",
            "--format",
            "jsonl",
        ],
    );
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let one = record(&lines.next().expect("a first sample").unwrap());
    assert_eq!(one["stale"], false, "{one}");
    // Unplug: the drive's pseudo-terminal goes away; plug in another behind the same name.
    drop(first);
    let second = Sim::start("yd1000", "binary");
    let relinked = dir.join("ttyVFD.new");
    std::os::unix::fs::symlink(&second.port, &relinked).unwrap();
    std::fs::rename(&relinked, &link).unwrap();
    let rest: Vec<serde_json::Value> = lines.map(|l| record(&l.unwrap())).collect();
    let status = wait(&mut child);
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    assert!(status.success(), "{status:?} {stderr}");
    assert_eq!(rest.len(), 11, "every sample: {rest:?}");
    let lost = rest.iter().position(|r| r["stale"] == true);
    let lost = lost.unwrap_or_else(|| panic!("the unplugged port shows: {rest:?}"));
    assert!(
        rest[lost..]
            .iter()
            .any(|r| r["stale"] == false && r["value"] == 80.0),
        "reads again after the port came back: {rest:?}"
    );
    assert!(rest[lost]["errors"].as_u64().unwrap() >= 1);
    drop(second);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ctrl_c_ends_a_watch_with_status_zero() {
    let sim = Sim::start("yd1000", "binary");
    let mut child = watch(&sim.port, &["FH", "--interval", "50", "--format", "jsonl"]);
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let one = record(&lines.next().expect("a first sample").unwrap());
    assert_eq!(one["stale"], false);
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    // Drain the pipe so the watch never blocks on it.
    for line in lines {
        record(&line.unwrap());
    }
    let status = wait(&mut child);
    assert!(status.success(), "{status:?}");
}

#[test]
fn a_closed_pipe_ends_a_watch_quietly() {
    let sim = Sim::start("yd1000", "binary");
    for format in ["jsonl", "csv", "text"] {
        // `vfd watch … | head -1`
        let mut child = watch(&sim.port, &["FH", "--interval", "50", "--format", format]);
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut first = String::new();
        stdout.read_line(&mut first).unwrap();
        assert!(!first.is_empty(), "{format}: a first line");
        drop(stdout);
        let status = wait(&mut child);
        let mut stderr = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
        assert!(status.success(), "{format}: {status:?} {stderr}");
        assert!(!stderr.contains("panicked"), "{format}: {stderr}");
    }
}
