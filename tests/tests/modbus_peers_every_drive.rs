//! Every described drive that speaks Modbus RTU, read and written by two masters we did not
//! write: minimalmodbus (PyPI) and mbpoll (libmodbus, Debian's `mbpoll`), each over a
//! pseudo-terminal against the drive's virtual drive. For each such protocol of each drive
//! the test picks, from the description alone, a register the protocol reads with function
//! 03 and one it writes with function 06 (a value inside the register's range that the
//! virtual drive accepts), then has each peer read the first, write the second and read it
//! back; the value must be the one the virtual drive holds. A drive added as YAML is covered
//! without a line of Rust.
//!
//! Needs minimalmodbus (`pip install -r tests/python/requirements.txt`) and mbpoll
//! (`apt-get install mbpoll`); `.ci/run` installs both. Without them the tests are reported
//! ignored with the reason, except under CI, where they fail.

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use vfd_runtime::serial::{Parity, SerialSettings};
use vfd_runtime::virtual_drive::{Outcome, VirtualDrive};
use vfd_runtime::{CommandKind, DriveInfo, Protocol, RegisterInfo, Request};
use vfd_tests::virtual_port::VirtualPort;

/// Linux pseudo-terminals carry no parity: 8N1 at 115200, as the peers open it.
const LINE: SerialSettings = SerialSettings {
    baud: 115_200,
    data_bits: 8,
    parity: Parity::None,
    stop_bits: 1,
};

/// What a peer is asked to do on one drive's protocol.
struct Subject {
    drive: &'static DriveInfo,
    protocol: &'static Protocol,
    /// Read with function 03: (register, its wire address).
    read: (&'static RegisterInfo, u16),
    /// Written with function 06: (register, its wire address, the raw value).
    write: (&'static RegisterInfo, u16, u16),
}

/// The Modbus RTU request `request` encodes to, when it is one: (function, address, value).
fn modbus_frame(protocol: &Protocol, request: &Request) -> Option<(u8, u16, u16)> {
    let mut frame = [0u8; 64];
    let len = protocol.encode_request(request, Some(1), &mut frame).ok()?;
    let frame = &frame[..len];
    if len != 8 || frame[0] != 1 {
        return None;
    }
    let crc =
        vfd_runtime::checksum::compute(vfd_runtime::ChecksumAlgorithm::Crc16Modbus, &frame[..6]);
    if u16::from_le_bytes([frame[6], frame[7]]) != crc as u16 {
        return None;
    }
    let word = |at: usize| u16::from_be_bytes([frame[at], frame[at + 1]]);
    Some((frame[1], word(2), word(4)))
}

/// A value inside `info`'s range other than what a fresh drive holds.
fn candidate(info: &RegisterInfo, now: u32) -> Option<u16> {
    let (min, max) = (info.raw_min.max(0), info.raw_max.min(0xFFFF));
    if min >= max {
        return None;
    }
    let value = if i64::from(now) == max {
        min
    } else {
        (i64::from(now) + 1).clamp(min, max)
    };
    u16::try_from(value).ok().filter(|v| u32::from(*v) != now)
}

/// The read and the write the peers make on `protocol` of `drive`, when it is Modbus RTU.
fn subject(drive: &'static DriveInfo, protocol: &'static Protocol) -> Option<Subject> {
    let fresh = || {
        let mut d = VirtualDrive::new(drive);
        d.set_address(1);
        d
    };
    let readable = drive.registers.iter().copied().find_map(|info| {
        let request = Request::for_register(CommandKind::Read, info, 0);
        match modbus_frame(protocol, &request)? {
            (0x03, address, 1) => {
                let mut frame = [0u8; 64];
                let len = protocol.encode_request(&request, Some(1), &mut frame).ok()?;
                matches!(fresh().respond(protocol, &frame[..len]), Outcome::Reply(r) if r[1] == 0x03)
                    .then_some((info, address))
            }
            _ => None,
        }
    })?;
    // A setting that acts at once (not the station or the line, which act after a reset),
    // one with a unit first (a ramp, a frequency), a code table's only if none.
    let settings = || {
        drive
            .registers
            .iter()
            .copied()
            .filter(|info| info.takes_effect == vfd_runtime::kinds::TakesEffect::Immediately)
    };
    let by_preference = settings()
        .filter(|info| info.codes.is_none())
        .chain(settings().filter(|info| info.codes.is_some()));
    let writable = by_preference.into_iter().find_map(|info| {
        let now = fresh().raw(info.id).unwrap_or(0);
        let value = candidate(info, now)?;
        let request = Request::for_register(CommandKind::WriteRam, info, u32::from(value));
        let (function, address, _) = modbus_frame(protocol, &request)?;
        if function != 0x06 {
            return None;
        }
        let mut frame = [0u8; 64];
        let len = protocol.encode_request(&request, Some(1), &mut frame).ok()?;
        let mut drive_now = fresh();
        let echoed = matches!(drive_now.respond(protocol, &frame[..len]), Outcome::Reply(r) if r == frame[..len]);
        (echoed && drive_now.raw(info.id) == Some(u32::from(value))).then_some((info, address, value))
    })?;
    Some(Subject {
        drive,
        protocol,
        read: readable,
        write: writable,
    })
}

/// Every Modbus RTU protocol of every described drive, with what the peers do on it.
fn subjects() -> Vec<Subject> {
    let subjects: Vec<Subject> = vfd_drives::ALL_DRIVES
        .iter()
        .flat_map(|drive| drive.protocols.iter().filter_map(|p| subject(drive, p)))
        .collect();
    assert!(
        subjects.len() >= 3,
        "fewer Modbus RTU drives than described: {}",
        subjects.len()
    );
    subjects
}

/// `(value read, value written back)` through minimalmodbus.
fn through_minimalmodbus(subject: &Subject, port: &VirtualPort) -> (u16, u16) {
    let plan = serde_json::json!([
        { "op": "read", "address": subject.read.1, "count": 1 },
        { "op": "write", "address": subject.write.1, "value": subject.write.2 },
        { "op": "read", "address": subject.write.1, "count": 1 },
    ]);
    let mut child = Command::new("python3")
        .args([
            "python/modbus_peer_client.py",
            "minimalmodbus",
            &port.path,
            "1",
            "rtu",
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("python3 runs");
    child
        .stdin
        .take()
        .expect("piped")
        .write_all(plan.to_string().as_bytes())
        .expect("the plan is sent");
    let answers: Vec<serde_json::Value> = BufReader::new(child.stdout.take().expect("piped"))
        .lines()
        .map(|line| serde_json::from_str(&line.expect("a line")).expect("JSON"))
        .collect();
    assert!(
        child.wait().expect("ends").success(),
        "minimalmodbus failed"
    );
    let value = |i: usize| -> u16 {
        assert_eq!(
            answers[i]["ok"], true,
            "{}: step {i}: {}",
            subject.drive.id, answers[i]
        );
        answers[i]["values"][0].as_u64().expect("a value") as u16
    };
    assert_eq!(
        answers[1]["ok"], true,
        "{}: the write: {}",
        subject.drive.id, answers[1]
    );
    (value(0), value(2))
}

/// mbpoll on the pseudo-terminal with `args`; its standard output.
fn mbpoll(port: &VirtualPort, args: &[String]) -> String {
    let output = Command::new("mbpoll")
        .args([
            "-m", "rtu", "-b", "115200", "-P", "none", "-d", "8", "-s", "1", "-a", "1",
        ])
        .args(["-t", "4", "-0", "-1", "-o", "1"])
        .args(args)
        .output()
        .expect("mbpoll runs");
    let text = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "mbpoll {args:?} on {} failed: {text}{}",
        port.path,
        String::from_utf8_lossy(&output.stderr)
    );
    text
}

/// The value mbpoll prints for `address` (`[1234]:  567`).
fn mbpoll_value(text: &str, address: u16) -> u16 {
    let tag = format!("[{address}]:");
    text.lines()
        .find_map(|line| line.trim().strip_prefix(&tag))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|v| v.parse::<i32>().ok())
        .map(|v| v as u16)
        .unwrap_or_else(|| panic!("no value for [{address}] in mbpoll's output:\n{text}"))
}

/// `(value read, value written back)` through mbpoll.
fn through_mbpoll(subject: &Subject, port: &VirtualPort) -> (u16, u16) {
    let read = mbpoll(
        port,
        &["-r".into(), subject.read.1.to_string(), port.path.clone()],
    );
    let address = subject.write.1.to_string();
    mbpoll(
        port,
        &[
            "-r".into(),
            address.clone(),
            port.path.clone(),
            subject.write.2.to_string(),
        ],
    );
    let back = mbpoll(port, &["-r".into(), address, port.path.clone()]);
    (
        mbpoll_value(&read, subject.read.1),
        mbpoll_value(&back, subject.write.1),
    )
}

fn check(peer: &str, through: fn(&Subject, &VirtualPort) -> (u16, u16)) {
    for subject in subjects() {
        let port = VirtualPort::serve(subject.drive, &subject.protocol.id, 1, LINE);
        let held = port.simulator.lock().raw(subject.read.0.id).expect("held") as u16;
        let (read, back) = through(&subject, &port);
        let what = format!(
            "{peer} on {} over {}: {} at {}",
            subject.drive.id, subject.protocol.id, subject.read.0.code, subject.read.1
        );
        assert_eq!(read, held, "{what}: read");
        let (info, address, value) = subject.write;
        assert_eq!(
            back, value,
            "{peer} on {}: {} at {address} read back",
            subject.drive.id, info.code
        );
        assert_eq!(
            port.simulator.lock().raw(info.id),
            Some(u32::from(value)),
            "{peer} on {}: the virtual drive holds what {peer} wrote to {}",
            subject.drive.id,
            info.code
        );
    }
}

#[test]
#[cfg_attr(
    missing_minimalmodbus,
    ignore = "needs python3 with minimalmodbus and pyserial: pip install -r tests/python/requirements.txt, then cargo test again"
)]
fn minimalmodbus_reads_and_writes_every_modbus_drive() {
    check("minimalmodbus", through_minimalmodbus);
}

#[test]
#[cfg_attr(
    missing_mbpoll,
    ignore = "needs mbpoll (libmodbus): apt-get install mbpoll, then cargo test again; .ci/run installs it"
)]
fn mbpoll_reads_and_writes_every_modbus_drive() {
    check("mbpoll", through_mbpoll);
}
