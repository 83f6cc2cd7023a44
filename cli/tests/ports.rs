//! `vfd --port-kind` against `vfd sim --port-kind` for the VF-AS1's two serial ports,
//! registers whose scale another register chooses (ACC by FA09) and values taken besides
//! the range (the DV1's 99999 as FFFFh), read and written through the command line.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A `vfd sim` child, stopped (SIGTERM through `kill`) when dropped.
struct Sim {
    child: Child,
    device: String,
}

impl Sim {
    fn start(args: &[&str]) -> Sim {
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
        let device = first.trim().to_owned();
        assert!(
            device.starts_with("/dev/"),
            "first line is the device: {device:?}"
        );
        Sim { child, device }
    }

    /// `vfd COMMAND --drive vf-as1 --protocol binary --port DEVICE ARGS...`.
    fn vfd(&self, args: &[&str]) -> Output {
        self.vfd_on("vf-as1", "binary", args)
    }

    /// `vfd COMMAND --drive DRIVE --protocol PROTOCOL --port DEVICE ARGS...`.
    fn vfd_on(&self, drive: &str, protocol: &str, args: &[&str]) -> Output {
        let (command, rest) = args.split_first().expect("a command");
        Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg(command)
            .args([
                "--drive",
                drive,
                "--protocol",
                protocol,
                "--port",
                &self.device,
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

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

#[test]
fn a_port_named_once_points_the_2_wire_registers_at_the_4_wire_copies() {
    let sim = Sim::start(&[
        "--drive",
        "vf-as1",
        "--protocol",
        "binary",
        "--port-kind",
        "four_wire",
    ]);
    let write = sim.vfd(&["write", "--port-kind", "four_wire", "FA01", "30Hz"]);
    assert!(write.status.success(), "{}", text(&write));
    assert!(text(&write).contains("wrote FA05"), "{}", text(&write));
    let copy = sim.vfd(&["read", "FA05", "FA01"]);
    assert!(
        text(&copy).contains("FA05") && text(&copy).contains("30.00 Hz"),
        "{}",
        text(&copy)
    );
    assert!(
        text(&copy).contains("0.00 Hz"),
        "FA01 is untouched: {}",
        text(&copy)
    );
    let run = sim.vfd(&[
        "write",
        "--port-kind",
        "four_wire",
        "FA00",
        "command_priority,frequency_priority,run",
    ]);
    assert!(run.status.success(), "{}", text(&run));
    assert!(text(&run).contains("wrote FA04"), "{}", text(&run));
    // The virtual drive serves the 4-wire port: FA04 runs it (ACC has no factory value,
    // so the output steps to the command at once, on the simulator's wall clock).
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let output = sim.vfd(&["read", "FD00"]);
        if text(&output).contains("30.00 Hz") {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the drive does not run: {}",
            text(&output)
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let read = sim.vfd(&["read", "--port-kind", "four_wire", "FA00"]);
    assert!(
        text(&read).contains("FA04") && text(&read).contains("C400h"),
        "{}",
        text(&read)
    );
}

#[test]
fn a_port_the_drive_does_not_have_is_refused_with_the_ports_it_has() {
    let sim = Sim::start(&["--drive", "vf-as1", "--protocol", "binary"]);
    let wrong = sim.vfd(&["read", "--port-kind", "usb", "FA01"]);
    assert!(!wrong.status.success());
    assert!(
        text(&wrong).contains("drive vf-as1 has no port `usb`"),
        "{}",
        text(&wrong)
    );
    assert!(
        text(&wrong).contains("two_wire, four_wire"),
        "{}",
        text(&wrong)
    );
    let one = Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["sim", "--drive", "yd1000", "--port-kind", "two_wire"])
        .output()
        .expect("vfd runs");
    assert!(!one.status.success());
    assert!(
        text(&one).contains("drive yd1000 has one serial port"),
        "{}",
        text(&one)
    );
}

#[test]
fn acc_is_shown_and_written_in_the_step_fa09_chooses() {
    let sim = Sim::start(&["--drive", "vf-as1", "--protocol", "binary"]);
    // FA09 = 1 (0.1 s steps): 10 s is 0064h.
    let write = sim.vfd(&["write", "ACC", "10"]);
    assert!(write.status.success(), "{}", text(&write));
    assert!(text(&write).contains("10.0 s"), "{}", text(&write));
    // FA09 = 0 (0.01 s steps): the same word reads 1.00 s, and 10 s is written as 03E8h.
    let unit = sim.vfd(&["write", "FA09", "centiseconds"]);
    assert!(unit.status.success(), "{}", text(&unit));
    let read = sim.vfd(&["read", "ACC"]);
    assert!(text(&read).contains("1.00 s"), "{}", text(&read));
    let write = sim.vfd(&["write", "ACC", "10"]);
    assert!(text(&write).contains("10.00 s"), "{}", text(&write));
    let read = sim.vfd(&["read", "ACC"]);
    assert!(text(&read).contains("10.00 s"), "{}", text(&read));
    let watch = sim.vfd(&["watch", "--count", "1", "ACC"]);
    assert!(watch.status.success(), "{}", text(&watch));
    assert!(text(&watch).contains("10.00 s"), "{}", text(&watch));
    // 700 s is beyond 600 s in 0.01 s steps: refused, nothing written.
    let beyond = sim.vfd(&["write", "ACC", "700"]);
    assert!(!beyond.status.success());
    assert!(text(&beyond).contains("0.01 to 600 s"), "{}", text(&beyond));
}

#[test]
fn dv1_shows_and_takes_99999_by_number_or_name() {
    let sim = Sim::start(&["--drive", "dv1", "--protocol", "modbus"]);
    let read = sim.vfd_on("dv1", "modbus", &["read", "07-09"]);
    assert!(read.status.success(), "{}", text(&read));
    assert!(
        text(&read).contains("99999 (no_check: No time-out check)"),
        "{}",
        text(&read)
    );
    let write = sim.vfd_on("dv1", "modbus", &["write", "07-09", "2.5"]);
    assert!(write.status.success(), "{}", text(&write));
    let back = sim.vfd_on("dv1", "modbus", &["read", "07-09"]);
    assert!(text(&back).contains("2.5 s"), "{}", text(&back));
    for value in ["no_check", "99999"] {
        let write = sim.vfd_on("dv1", "modbus", &["write", "07-09", value]);
        assert!(write.status.success(), "{value}: {}", text(&write));
        let back = sim.vfd_on("dv1", "modbus", &["read", "07-09"]);
        assert!(
            text(&back).contains("99999 (no_check"),
            "{value}: {}",
            text(&back)
        );
    }
    let beyond = sim.vfd_on("dv1", "modbus", &["write", "07-09", "1000"]);
    assert!(!beyond.status.success(), "{}", text(&beyond));
}
