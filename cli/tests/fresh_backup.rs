//! A backup of a fresh virtual drive restores onto it, for every seed drive and every
//! protocol it can be backed up over: the virtual drive starts each register at a value it
//! accepts (its default, else one within its range), so no entry of the backup is refused
//! (a fresh VF-AS1 once held ACC and DEC at 0 s, outside 0.1-6000 s).

mod common;

use common::{text, Sim};

const DRIVES: [(&str, &[&str]); 4] = [
    ("yd1000", &["ascii", "binary"]),
    ("fc51", &["fc", "modbus"]),
    ("dv1", &["modbus", "modbus_ascii", "eaton"]),
    ("vf-as1", &["ascii", "binary", "modbus"]),
];

#[test]
fn a_backup_of_a_fresh_virtual_drive_restores_onto_it() {
    let dir = std::env::temp_dir().join(format!("vfd-fresh-backup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (drive, protocols) in DRIVES {
        for protocol in protocols {
            let file = dir.join(format!("{drive}-{protocol}.yaml"));
            let file = file.to_str().unwrap();
            let sim = Sim::start(drive, protocol);
            let saved = sim.vfd(drive, protocol, &["backup", "--to", file]);
            assert!(
                saved.status.success(),
                "{drive}/{protocol}: {}",
                text(&saved)
            );
            // Only a text the virtual drive holds none of (FC 51 1546, the ordering number)
            // goes unread.
            for line in text(&saved).lines().filter(|l| l.contains("not read")) {
                assert!(
                    line.contains("not read: 1546:"),
                    "{drive}/{protocol}: {line}"
                );
            }
            let restored = sim.vfd(drive, protocol, &["restore", "--from", file]);
            let message = text(&restored);
            assert!(restored.status.success(), "{drive}/{protocol}: {message}");
            assert!(
                message.contains("restored 0 value(s)"),
                "{drive}/{protocol}: nothing differs: {message}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
