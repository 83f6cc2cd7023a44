//! Modbus RTU against an independent implementation: the FC drive's typed API drives a
//! pymodbus server over a pseudo-terminal. Reads, writes (with the coil-65 step), indexed
//! access, coils and exception replies must all be understood by both sides. The DV1's
//! Modbus RTU and Modbus ASCII masters read and write the same server in each framing.
//!
//! Needs `pip install -r tests/python/requirements.txt` (.ci/run does it). Without the
//! packages the test reports that it skipped, except under CI, where it fails.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use vfd_drives::fc51::{bits, protocols, registers};
use vfd_runtime::serial::{DriveTiming, Parity, SerialSettings};
use vfd_runtime::transaction::Master;
use vfd_runtime::transport::{PseudoTerminal, PtyTransport};
use vfd_runtime::TransactionErrorKind;

struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn peers_installed() -> bool {
    Command::new("python3")
        .args(["-c", "import pymodbus, serial"])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Starts the pymodbus server in `framing` (`rtu` or `ascii`) on a pseudo-terminal; the
/// master's end of it.
fn start_server(framing: &str) -> Option<(Server, PtyTransport)> {
    if !peers_installed() {
        panic!(
            "pymodbus is missing: pip install -r tests/python/requirements.txt (under CI a missing peer fails; elsewhere tests/build.rs marks its tests ignored when it finds the package missing: touch tests/build.rs to look again)"
        );
    }
    let pty = PseudoTerminal::open().expect("a pseudo-terminal");
    let path = pty.slave_path().display().to_string();
    let ours = pty.master().expect("the master side");
    let mut child = Command::new("python3")
        .args(["python/modbus_peer_server.py", &path, framing])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("python3 runs");
    let mut line = String::new();
    BufReader::new(child.stdout.take().expect("piped"))
        .read_line(&mut line)
        .expect("the server starts");
    Some((Server(child), ours))
}

const SETTINGS: SerialSettings = SerialSettings {
    baud: 115_200,
    data_bits: 8,
    parity: Parity::None,
    stop_bits: 1,
};

fn start() -> Option<(Server, Master<PtyTransport, vfd_drives::fc51::Drive>)> {
    let (server, ours) = start_server("rtu")?;
    let settings = SerialSettings {
        baud: 115_200,
        data_bits: 8,
        parity: Parity::None,
        stop_bits: 1,
    };
    let timing = DriveTiming {
        startup_delay: Duration::ZERO,
        processing_allowance: Duration::from_millis(300),
        frame_abandon: Duration::from_secs(1),
    };
    let mut master = Master::new(ours, &protocols::MODBUS, settings, timing).with_address(Some(1));
    // The server opens its port after printing "ready": retry the first read.
    let started = Instant::now();
    while master.read::<registers::MaximumReference>().is_err() {
        assert!(
            started.elapsed() < Duration::from_secs(30),
            "the pymodbus server does not answer"
        );
    }
    Some((server, master))
}

#[test]
#[cfg_attr(
    missing_pymodbus,
    ignore = "needs python3 with pymodbus and pyserial: pip install -r tests/python/requirements.txt, then cargo test again"
)]
fn the_fc_modbus_api_works_against_pymodbus() {
    let Some((_server, mut master)) = start() else {
        return;
    };

    // 03 with two registers at 303 x 10 - 1.
    assert_eq!(master.read::<registers::MaximumReference>().unwrap(), 60.0);

    // RAM write: coil 65 = 0000h (05), then 06; read back with 03.
    assert_eq!(
        master.write_ram::<registers::Parameter101>(7).unwrap(),
        Some(7),
        "06 echoes the value written"
    );
    assert_eq!(master.read::<registers::Parameter101>().unwrap(), 7);

    // Persistent double-word write: coil 65 = FF00h, then 10 with two registers.
    master
        .write_persistent::<registers::MaximumReference>(55.5)
        .unwrap();
    assert_eq!(master.read::<registers::MaximumReference>().unwrap(), 55.5);

    // Indexed read: register 0008h = 2 (06), then 03 at 310 x 10 - 1.
    assert_eq!(master.read_at::<registers::PresetReference>(2).unwrap(), 42);

    // Coils: the control word as 16 coils from coil 1 (0F), read back with 01.
    let run = bits::ControlWord(0x047C);
    master.write_ram::<registers::ControlWord>(run).unwrap();
    assert_eq!(master.read::<registers::ControlWord>().unwrap(), run);

    // An address the server does not have: exception 83h, error number 2.
    let error = master.read_text::<registers::OrderingNumber>().unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Encode(_)),
        "Modbus carries no text: {error:?}"
    );
    let error = master.read::<registers::SetupSelect>().unwrap_err();
    assert!(
        matches!(error.kind, TransactionErrorKind::Rejected { code: 2, .. }),
        "{error:?}"
    );
}

/// The DV1's Modbus masters (typed API) against pymodbus's server, in `framing`.
fn dv1_against_pymodbus(framing: &str) {
    use vfd_drives::dv1;
    let Some((_server, ours)) = start_server(framing) else {
        return;
    };
    let protocol = match framing {
        "ascii" => &dv1::protocols::MODBUS_ASCII,
        _ => &dv1::protocols::MODBUS,
    };
    let timing = DriveTiming {
        startup_delay: Duration::ZERO,
        processing_allowance: Duration::from_millis(300),
        frame_abandon: Duration::from_secs(1),
    };
    let mut master = Master::new(ours, protocol, SETTINGS, timing).with_address(Some(1));
    let started = Instant::now();
    // 02-15 at 00C3h: the server's register holds 0 until written.
    while master.read::<dv1::registers::Parameter0215>().is_err() {
        assert!(
            started.elapsed() < Duration::from_secs(30),
            "the pymodbus server does not answer ({framing})"
        );
    }
    master
        .write_ram::<dv1::registers::Parameter0215>(vfd_runtime::units::Hertz(50.0))
        .unwrap();
    assert_eq!(
        master.read::<dv1::registers::Parameter0215>().unwrap(),
        vfd_runtime::units::Hertz(50.0),
        "{framing}"
    );
    // Twelve registers in one 03 request (the DV1's limit).
    let mut words = [0u16; 12];
    master.read_words(0x00C0, &mut words).unwrap();
    assert_eq!(words[3], 5000, "{framing}: 00C3h in the block");
    // An address the server does not have: exception 02.
    let nowhere = vfd_runtime::Request::raw(vfd_runtime::CommandKind::Read, 0x3000, 0);
    match master.transact(&nowhere) {
        Err(error) => assert!(
            matches!(error.kind, TransactionErrorKind::Rejected { code: 2, .. }),
            "{framing}: {error}"
        ),
        Ok(answer) => panic!("{framing}: answered {answer:?}"),
    }
}

#[test]
#[cfg_attr(
    missing_pymodbus,
    ignore = "needs python3 with pymodbus and pyserial: pip install -r tests/python/requirements.txt, then cargo test again"
)]
fn the_dv1_modbus_rtu_master_works_against_pymodbus() {
    dv1_against_pymodbus("rtu");
}

#[test]
#[cfg_attr(
    missing_pymodbus,
    ignore = "needs python3 with pymodbus and pyserial: pip install -r tests/python/requirements.txt, then cargo test again"
)]
fn the_dv1_modbus_ascii_master_works_against_pymodbus() {
    dv1_against_pymodbus("ascii");
}
