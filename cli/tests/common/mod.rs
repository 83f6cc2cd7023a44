//! The `vfd sim` harness the command-line tests share: a virtual drive served on a
//! pseudo-terminal by the `vfd` binary, and `vfd` commands run against it.

#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Output, Stdio};

/// A `vfd sim` child, stopped (SIGTERM through `kill`, as a service manager would) when
/// dropped.
pub struct Sim {
    child: Child,
    /// The pseudo-terminal it serves.
    pub port: String,
}

impl Sim {
    /// `vfd sim --drive DRIVE --protocol PROTOCOL`.
    pub fn start(drive: &str, protocol: &str) -> Sim {
        Sim::start_with(drive, protocol, &[])
    }

    /// `vfd sim --drive DRIVE --protocol PROTOCOL EXTRA...`.
    pub fn start_with(drive: &str, protocol: &str, extra: &[&str]) -> Sim {
        let mut args = vec!["--drive", drive, "--protocol", protocol];
        args.extend_from_slice(extra);
        Sim::spawn(&args)
    }

    /// `vfd sim ARGS...`; its first line names the device.
    pub fn spawn(args: &[&str]) -> Sim {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg("sim")
            .args(args)
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

    /// `vfd COMMAND --drive DRIVE --protocol PROTOCOL --port DEVICE ARGS...`.
    pub fn vfd(&self, drive: &str, protocol: &str, args: &[&str]) -> Output {
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
        let _ = Command::new("kill")
            .arg(self.child.id().to_string())
            .status();
        let _ = self.child.wait();
    }
}

/// A command's stdout and stderr, as text.
pub fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}
