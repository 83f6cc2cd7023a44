//! `vfd ports` runs on this machine and exits 0: either the one "no serial ports" line, or
//! one line per port naming it and its kind; `--format json` gives the same ports.

use std::process::Command;

fn vfd(args: &[&str]) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .output()
        .expect("vfd runs");
    let text = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    (output.status.success(), text)
}

#[test]
fn ports_lists_the_system_s_ports_or_says_there_are_none() {
    let (ok, text) = vfd(&["ports"]);
    assert!(ok, "{text}");
    let lines: Vec<&str> = text.lines().collect();
    let (ok, json) = vfd(&["ports", "--format", "json"]);
    assert!(ok, "{json}");
    let ports: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    let ports = ports.as_array().expect("an array");
    if lines == ["no serial ports found (a USB adapter shows up here once plugged in)"] {
        assert!(ports.is_empty(), "{json}");
        return;
    }
    assert_eq!(lines.len(), ports.len(), "{text}\n{json}");
    for (line, port) in lines.iter().zip(ports) {
        let mut words = line.split_whitespace();
        assert_eq!(words.next(), port["name"].as_str(), "{line}");
        let kind = words.next().unwrap_or_default();
        assert!(
            ["usb", "pci", "bluetooth", "other"].contains(&kind),
            "{line}"
        );
        assert_eq!(port["kind"], kind, "{line}");
    }
}
