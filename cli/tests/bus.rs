//! `vfd read`, `write`, `backup` and `restore` against `vfd sim` started as a child
//! process: its first line of output is the pseudo-terminal to open.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Output, Stdio};

/// A `vfd sim` child, stopped (SIGTERM through `kill`) when dropped.
struct Sim {
    child: Child,
    port: String,
}

impl Sim {
    fn start(drive: &str, protocol: &str) -> Sim {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .args(["sim", "--drive", drive, "--protocol", protocol])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("vfd sim starts");
        let mut first = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut first)
            .expect("the device path");
        let port = first.trim().to_owned();
        assert!(
            port.starts_with("/dev/"),
            "first line is the device: {port:?}"
        );
        Sim { child, port }
    }

    fn vfd(&self, drive: &str, protocol: &str, args: &[&str]) -> Output {
        let (command, rest) = args.split_first().expect("a command");
        Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg(command)
            .args([
                "--drive",
                drive,
                "--protocol",
                protocol,
                "--port",
                &self.port,
            ])
            .args(rest)
            .output()
            .expect("vfd runs")
    }
}

impl Drop for Sim {
    fn drop(&mut self) {
        // SIGTERM, as a service manager would: the sim ends cleanly.
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

#[test]
fn yd1000_read_write_and_refusals() {
    let sim = Sim::start("yd1000", "binary");
    let read = sim.vfd("yd1000", "binary", &["read", "FH", "F801"]);
    assert!(read.status.success(), "{}", text(&read));
    assert!(text(&read).contains("80.00 Hz"), "{}", text(&read));
    assert!(text(&read).contains("Even parity"), "{}", text(&read));

    let write = sim.vfd("yd1000", "binary", &["write", "FA01", "60Hz"]);
    assert!(write.status.success(), "{}", text(&write));
    let back = sim.vfd("yd1000", "binary", &["read", "FA01"]);
    assert!(text(&back).contains("60.00 Hz"), "{}", text(&back));

    // Bit fields by name, shown field by field.
    let run = sim.vfd(
        "yd1000",
        "binary",
        &["write", "FA00", "command_enabled,frequency_enabled"],
    );
    assert!(run.status.success(), "{}", text(&run));
    let word = sim.vfd("yd1000", "binary", &["read", "FA00"]);
    assert!(
        text(&word).contains("C000h: command_enabled, frequency_enabled"),
        "{}",
        text(&word)
    );

    // Out of range: refused before anything is sent, so the value stays.
    let refused = sim.vfd("yd1000", "binary", &["write", "FA01", "400Hz"]);
    assert!(!refused.status.success());
    assert!(
        text(&refused).contains("outside the range 0 to 320 Hz"),
        "{}",
        text(&refused)
    );
    assert!(
        text(&refused).contains("nothing was sent"),
        "{}",
        text(&refused)
    );
    let beyond_fh = sim.vfd("yd1000", "binary", &["write", "FA01", "90"]);
    assert!(!beyond_fh.status.success());
    assert!(
        text(&beyond_fh).contains("above FH"),
        "{}",
        text(&beyond_fh)
    );
    let still = sim.vfd("yd1000", "binary", &["read", "FA01"]);
    assert!(text(&still).contains("60.00 Hz"), "{}", text(&still));

    // Read-only and RAM-only registers.
    let read_only = sim.vfd("yd1000", "binary", &["write", "FD00", "1"]);
    assert!(
        text(&read_only).contains("read-only"),
        "{}",
        text(&read_only)
    );
    let ram_only = sim.vfd("yd1000", "binary", &["write", "--persist", "FA01", "10"]);
    assert!(text(&ram_only).contains("RAM-only"), "{}", text(&ram_only));
}

#[test]
fn fc51_over_modbus_reads_and_writes_parameters() {
    let sim = Sim::start("fc51", "modbus");
    let write = sim.vfd("fc51", "modbus", &["write", "3-03", "60"]);
    assert!(write.status.success(), "{}", text(&write));
    let read = sim.vfd("fc51", "modbus", &["read", "303"]);
    assert!(read.status.success(), "{}", text(&read));
    assert!(text(&read).contains("60.000"), "{}", text(&read));
}

#[test]
fn backup_and_restore_round_trip() {
    let dir = std::env::temp_dir().join(format!("vfd-backup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("yd1000.yaml");
    let file_arg = file.to_str().unwrap();
    let sim = Sim::start("yd1000", "ascii");
    let saved = sim.vfd("yd1000", "ascii", &["backup", "--to", file_arg]);
    assert!(saved.status.success(), "{}", text(&saved));
    let yaml = std::fs::read_to_string(&file).unwrap();
    assert!(
        yaml.contains("code: FH") && yaml.contains("80.00 Hz"),
        "{yaml}"
    );
    assert!(
        !yaml.contains("code: FA00"),
        "command words are not backed up"
    );

    // Nothing changed: nothing to write.
    let same = sim.vfd(
        "yd1000",
        "ascii",
        &["restore", "--from", file_arg, "--dry-run"],
    );
    assert!(same.status.success(), "{}", text(&same));
    assert!(
        text(&same).contains("dry run: 0 to write"),
        "{}",
        text(&same)
    );

    // Change FH on the drive, restore puts the saved value back.
    let changed = sim.vfd("yd1000", "ascii", &["write", "FH", "70"]);
    assert!(changed.status.success(), "{}", text(&changed));
    let restored = sim.vfd("yd1000", "ascii", &["restore", "--from", file_arg]);
    assert!(restored.status.success(), "{}", text(&restored));
    assert!(text(&restored).contains("FH"), "{}", text(&restored));
    let back = sim.vfd("yd1000", "ascii", &["read", "FH"]);
    assert!(text(&back).contains("80.00 Hz"), "{}", text(&back));

    // An out-of-range entry is refused, and nothing is written.
    std::fs::write(&file, yaml.replacen("80.00 Hz", "999 Hz", 1)).unwrap();
    let refused = sim.vfd("yd1000", "ascii", &["restore", "--from", file_arg]);
    assert!(!refused.status.success());
    assert!(
        text(&refused).contains("outside the range"),
        "{}",
        text(&refused)
    );
    assert!(
        text(&refused).contains("nothing written"),
        "{}",
        text(&refused)
    );

    // Another model's file is refused.
    let other = sim.vfd("fc51", "modbus", &["restore", "--from", file_arg]);
    assert!(!other.status.success());
    assert!(text(&other).contains("not of a fc51"), "{}", text(&other));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_port_is_one_clear_error() {
    let output = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args([
            "read",
            "--drive",
            "yd1000",
            "--port",
            "/dev/nonexistent-vfd",
            "FH",
        ])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let message = text(&output);
    assert!(
        message.contains("cannot open serial port /dev/nonexistent-vfd"),
        "{message}"
    );
    assert!(message.contains("hint:"), "{message}");
    assert!(!message.contains("panicked"));
}

/// `saved N parameters of DRIVE to FILE (M read request(s))`: N and M.
fn saved_counts(output: &str) -> (usize, usize) {
    let line = output
        .lines()
        .find(|l| l.starts_with("saved "))
        .unwrap_or_else(|| panic!("a summary line: {output}"));
    let number = |after: &str| -> usize {
        line[line.find(after).unwrap() + after.len()..]
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    (number("saved "), number("("))
}

#[test]
fn backup_reads_consecutive_registers_in_blocks_where_the_protocol_allows() {
    let dir = std::env::temp_dir().join(format!("vfd-blocks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // DV1 over Modbus reads up to 12 registers per request; VF-AS1 one.
    for (drive, blocks) in [("dv1", true), ("vf-as1", false)] {
        let sim = Sim::start(drive, "modbus");
        let file = dir.join(format!("{drive}.yaml"));
        let saved = sim.vfd(drive, "modbus", &["backup", "--to", file.to_str().unwrap()]);
        assert!(saved.status.success(), "{}", text(&saved));
        let (parameters, requests) = saved_counts(&text(&saved));
        if blocks {
            assert!(
                requests < parameters,
                "{drive}: {requests} requests for {parameters} parameters"
            );
        } else {
            assert_eq!(requests, parameters, "{drive}: one register per read");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
