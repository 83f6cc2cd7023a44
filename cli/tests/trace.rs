//! `--trace`, `--retries`, `--gap-ms` and `--host-latency-ms` against `vfd sim --fault`:
//! the trace shows each frame (hex and decoded, with times) and the retry after a dropped
//! reply, on standard error; a dropped reply fails a read without retries and not with
//! them; a longer gap shows in the trace times (a generous lower bound only).

mod common;

use common::{text, Sim};

/// The times (ms) of the trace's request lines (`[   12.3 ms] -> ...`).
fn request_times(stderr: &str) -> Vec<f64> {
    stderr
        .lines()
        .filter(|line| line.contains("] -> "))
        .filter_map(|line| {
            let inner = line.strip_prefix('[')?.split(" ms]").next()?;
            inner.trim().parse().ok()
        })
        .collect()
}

#[test]
fn trace_shows_the_frames_and_the_retry_after_a_dropped_reply() {
    let sim = Sim::start_with("yd1000", "binary", &["--fault", "drop-reply"]);
    let read = sim.vfd(
        "yd1000",
        "binary",
        &["read", "FH", "--trace", "--retries", "2"],
    );
    assert!(read.status.success(), "{}", text(&read));
    let stdout = String::from_utf8_lossy(&read.stdout);
    let stderr = String::from_utf8_lossy(&read.stderr);
    assert!(
        stdout.contains("FH") && stdout.contains("80.00 Hz"),
        "{stdout}"
    );
    assert!(
        !stdout.contains("->"),
        "the trace is on standard error: {stdout}"
    );
    let sent = stderr
        .lines()
        .filter(|l| l.contains("-> 2F 52 00 11 92  [R, FH Maximum frequency]"))
        .count();
    assert_eq!(sent, 2, "the request and its retry: {stderr}");
    assert!(stderr.contains("retrying"), "{stderr}");
    assert!(
        stderr.contains("<- 2F 52 00 11 1F 40 F1  [R, FH Maximum frequency, data 1F40h]"),
        "{stderr}"
    );
    assert_eq!(
        request_times(&stderr).len(),
        2,
        "each line has its time: {stderr}"
    );
}

#[test]
fn a_dropped_reply_fails_without_retries_and_not_with_them() {
    let sim = Sim::start_with("yd1000", "binary", &["--fault", "drop-reply"]);
    let without = sim.vfd("yd1000", "binary", &["read", "FH", "--retries", "0"]);
    assert!(!without.status.success(), "{}", text(&without));
    assert!(text(&without).contains("no reply"), "{}", text(&without));
    let sim = Sim::start_with("yd1000", "binary", &["--fault", "drop-reply"]);
    let with = sim.vfd("yd1000", "binary", &["read", "FH", "--retries", "2"]);
    assert!(with.status.success(), "{}", text(&with));
}

#[test]
fn a_longer_gap_shows_in_the_trace_times() {
    let sim = Sim::start("yd1000", "binary");
    let read = sim.vfd(
        "yd1000",
        "binary",
        &[
            "read",
            "FH",
            "FA01",
            "--trace",
            "--gap-ms",
            "50",
            "--host-latency-ms",
            "200",
        ],
    );
    assert!(read.status.success(), "{}", text(&read));
    let stderr = String::from_utf8_lossy(&read.stderr);
    let times = request_times(&stderr);
    assert_eq!(times.len(), 2, "{stderr}");
    // At least the 50 ms gap after the first reply (which came after the first request);
    // no upper bound: the machine may be slow.
    assert!(times[1] - times[0] >= 50.0, "{stderr}");
}

#[test]
fn the_tuning_options_are_documented() {
    let help = std::process::Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["read", "--help"])
        .output()
        .expect("vfd runs");
    let help = text(&help);
    for option in ["--trace", "--retries", "--gap-ms", "--host-latency-ms"] {
        assert!(help.contains(option), "{option}: {help}");
    }
}
