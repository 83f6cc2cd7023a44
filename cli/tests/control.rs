//! `vfd run`, `stop`, `reset` and `state` against `vfd sim`, as a user runs them: the same
//! commands on drives of different families, a speed refused before anything is sent, a
//! run refused while tripped, and one line naming the roles a drive without them lacks.

mod common;

use common::{text, Sim};
use std::process::Command;

/// `vfd state --format json` parsed: the first state.
fn state(sim: &Sim, drive: &str, protocol: &str) -> serde_json::Value {
    let output = sim.vfd(drive, protocol, &["state", "--format", "json"]);
    assert!(output.status.success(), "state: {}", text(&output));
    let states: serde_json::Value =
        serde_json::from_slice(&output.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(&output)));
    states[0].clone()
}

#[test]
fn run_shows_running_at_its_set_point_and_stop_is_taken_on_three_families() {
    for (drive, protocol, speed, set_point) in [
        ("yd1000", "binary", "30Hz", 30.0),
        ("dv1", "modbus", "30", 30.0),
        ("pi500", "modbus", "20 Hz", 20.0),
    ] {
        let sim = Sim::start(drive, protocol);
        let run = sim.vfd(drive, protocol, &["run", speed]);
        assert!(run.status.success(), "{drive} run: {}", text(&run));
        assert!(text(&run).contains("running forward"), "{}", text(&run));
        let now = state(&sim, drive, protocol);
        assert_eq!(now["running"], true, "{drive}: {now}");
        assert_eq!(now["tripped"], false, "{drive}: {now}");
        let set = now["set_point"].as_f64().unwrap_or(f64::NAN);
        assert!((set - set_point).abs() < 0.01, "{drive}: {now}");
        let stop = sim.vfd(drive, protocol, &["stop"]);
        assert!(stop.status.success(), "{drive} stop: {}", text(&stop));
    }
}

#[test]
fn a_speed_out_of_range_is_refused_before_anything_is_sent() {
    let sim = Sim::start("yd1000", "binary");
    let before = sim.vfd("yd1000", "binary", &["read", "FA01"]);
    let refused = sim.vfd("yd1000", "binary", &["run", "400Hz"]);
    assert!(!refused.status.success(), "{}", text(&refused));
    assert!(text(&refused).contains("FA01"), "{}", text(&refused));
    let after = sim.vfd("yd1000", "binary", &["read", "FA01"]);
    assert_eq!(before.stdout, after.stdout, "nothing was written");
    let now = state(&sim, "yd1000", "binary");
    assert_eq!(now["running"], false, "{now}");
}

#[test]
fn a_watch_interval_that_is_not_a_duration_is_refused() {
    for bad in ["inf", "0", "-1", "NaN"] {
        let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args([
                "state",
                "--drive",
                "yd1000",
                "--port",
                "/dev/null-does-not-exist",
            ])
            .arg(format!("--watch={bad}"))
            .output()
            .unwrap();
        let said = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(!output.status.success(), "--watch {bad}");
        assert!(
            said.contains("--watch") && !said.contains("panicked"),
            "{bad}: {said}"
        );
    }
}

#[test]
fn a_drive_without_roles_gets_one_line_naming_them() {
    let source = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/integrator/ts15_like.yaml"
    ))
    .unwrap();
    // The file without its behaviour model (the section up to the next top-level key).
    let mut kept = Vec::new();
    let mut skipping = false;
    for line in source.lines() {
        if line.starts_with("behaviour:") {
            skipping = true;
            continue;
        }
        if skipping && !line.is_empty() && !line.starts_with([' ', '#']) {
            skipping = false;
        }
        if !skipping {
            kept.push(line);
        }
    }
    let dir = std::env::temp_dir().join(format!("vfd-control-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("no_roles.yaml");
    std::fs::write(&file, kept.join("\n")).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["state", "--drive"])
        .arg(&file)
        .args(["--port", "/dev/null-does-not-exist"])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success());
    assert!(
        said.contains("cannot be controlled") && said.contains("command, speed, state"),
        "{said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
