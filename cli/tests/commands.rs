//! The `vfd` binary as people use it: help, list, info, decode, completions and the demo,
//! without a drive or a line.

use std::process::{Command, Output};

fn vfd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("vfd runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn every_subcommand_has_help_that_runs_nothing() {
    let before: Vec<_> =
        std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../generated-docs"))
            .unwrap()
            .map(|e| e.unwrap().metadata().unwrap().modified().unwrap())
            .collect();
    for command in [
        "list",
        "info",
        "read",
        "write",
        "run",
        "stop",
        "reset",
        "state",
        "watch",
        "backup",
        "restore",
        "sim",
        "demo",
        "decode",
        "encode",
        "registers",
        "generate",
        "check",
        "completions",
    ] {
        let output = vfd(&[command, "--help"]);
        assert!(
            output.status.success(),
            "{command} --help: {}",
            stderr(&output)
        );
        let text = stdout(&output);
        assert!(text.contains("Usage: vfd"), "{command}: {text}");
    }
    let after: Vec<_> =
        std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../generated-docs"))
            .unwrap()
            .map(|e| e.unwrap().metadata().unwrap().modified().unwrap())
            .collect();
    assert_eq!(before, after, "`generate --help` wrote nothing");
    let version = vfd(&["--version"]);
    assert!(stdout(&version).starts_with("vfd "));
    let read_help = stdout(&vfd(&["read", "--help"]));
    for option in [
        "--port",
        "--baud",
        "--parity",
        "--address",
        "--timeout",
        "--protocol",
    ] {
        assert!(read_help.contains(option), "read --help names {option}");
    }
}

#[test]
fn list_names_every_drive_and_protocol() {
    let output = vfd(&["list"]);
    assert!(output.status.success());
    let text = stdout(&output);
    for drive in vfd_drives::ALL_DRIVES {
        assert!(text.contains(drive.id), "{text}");
        for protocol in drive.protocols {
            assert!(text.contains(protocol.id.as_ref()), "{text}");
        }
    }
}

#[test]
fn info_finds_registers_by_code_id_address_and_chinese_name() {
    for name in [
        "FH",
        "fh",
        "maximum_frequency",
        "0x0011",
        "最高频率",
        "Maximum frequency",
    ] {
        let output = vfd(&["info", "yd1000", name]);
        assert!(output.status.success(), "{name}: {}", stderr(&output));
        let text = stdout(&output);
        assert!(
            text.contains("register 0011 FH (Maximum frequency / 最高频率)"),
            "{name}: {text}"
        );
        assert!(text.contains("30.00 Hz to 320.00 Hz"), "{text}");
        assert!(text.contains("default     80.00 Hz"), "{text}");
    }
    let fa01 = stdout(&vfd(&["info", "yd1000", "FA01"]));
    assert!(
        fa01.contains("at run time not above FH (Maximum frequency)"),
        "{fa01}"
    );
    assert!(fa01.contains("RAM only"), "{fa01}");
    let fa00 = stdout(&vfd(&["info", "yd1000", "fa00"]));
    assert!(
        fa00.contains("command_enabled") && fa00.contains("Run/stop"),
        "{fa00}"
    );
    let parity = stdout(&vfd(&["info", "yd1000", "F801"]));
    assert!(parity.contains("Even parity / 偶校验"), "{parity}");
    let p303 = vfd(&["info", "fc51", "3-03"]);
    assert!(stdout(&p303).contains("parameter 303"), "{}", stderr(&p303));
    let missing = vfd(&["info", "yd1000", "NOPE"]);
    assert!(!missing.status.success());
    assert!(stderr(&missing).contains("has no register `NOPE`"));
    assert!(stderr(&missing).contains("hint:"));
    let unknown = vfd(&["info", "nodrive"]);
    assert!(!unknown.status.success());
    assert!(stderr(&unknown).contains("unknown drive `nodrive`"));
    assert!(!stderr(&unknown).contains("panicked"));
}

#[test]
fn decode_explains_manual_frames() {
    // Binary read of FD00 (manual 4.2): the protocol is found; two described drives speak
    // it, and the note says so.
    let output = vfd(&["decode", "2F 52 FD 00 7E"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("all speak this protocol"), "{text}");
    let output = vfd(&["decode", "--drive", "yd1000", "2F 52 FD 00 7E"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("binary request of yd1000"), "{text}");
    assert!(text.contains("register FD00 (Output frequency"), "{text}");
    assert!(text.contains("checksum ok"), "{text}");
    // The same without spaces.
    assert!(vfd(&["decode", "2F52FD007E"]).status.success());
    // ASCII with escapes, and without its final CR (decoded with a note).
    let ascii = stdout(&vfd(&["decode", "(PFA011770&55)\\r"]));
    assert!(ascii.contains("value:    60.00 Hz"), "{ascii}");
    let no_cr = stdout(&vfd(&["decode", "(RFD00)"]));
    assert!(no_cr.contains("lacks its final CR"), "{no_cr}");
    // A reply decodes as a reply, with units.
    let reply = stdout(&vfd(&["decode", "--drive", "yd1000", "(R00111F40&3D)\\r"]));
    assert!(
        reply.contains("ascii reply") && reply.contains("80.00 Hz"),
        "{reply}"
    );
    // An error reply names the manual's code; the old positional form still works.
    let error = stdout(&vfd(&["decode", "yd1000", "ascii", "(N0001&5D)\\r"]));
    assert!(error.contains("Data error"), "{error}");
}

#[test]
fn decode_explains_commands_without_a_reply() {
    // 4.2: S carries 0.01 % of FH and is never answered; s says the sender tripped.
    let s = stdout(&vfd(&[
        "decode",
        "--drive",
        "vf-as1",
        "2F 53 FA 01 13 88 18",
    ]));
    assert!(s.contains("50.00 % of FH (1388h)"), "{s}");
    assert!(s.contains("never answers"), "{s}");
    assert!(!s.contains("also a valid reply"), "{s}");
    let tripped = stdout(&vfd(&[
        "decode",
        "--drive",
        "vf-as1",
        "2F 73 FA 01 13 88 38",
    ]));
    assert!(
        tripped.contains("the sender (master) reports a trip"),
        "{tripped}"
    );
    // The YD1000, on the same protocol file, has no S.
    assert!(
        !vfd(&["decode", "--drive", "yd1000", "2F 53 FA 01 13 88 18"])
            .status
            .success()
    );
    // G's dummy data is no value; the DV1's reset is never answered.
    let g = stdout(&vfd(&[
        "decode",
        "--drive",
        "vf-as1",
        "2F 47 FE 03 00 00 77",
    ]));
    assert!(g.contains("dummy"), "{g}");
    let reset = stdout(&vfd(&[
        "decode",
        "--drive",
        "dv1",
        "01 06 11 01 96 96 32 F8",
    ]));
    assert!(reset.contains("never answers"), "{reset}");
}

#[test]
fn encode_builds_g_and_s_frames_by_name() {
    let g = stdout(&vfd(&[
        "encode",
        "vf-as1",
        "binary",
        "read",
        "FE03",
        "--command",
        "G",
    ]));
    assert!(g.contains("2F 47 FE 03 00 00 77"), "{g}");
    let s = stdout(&vfd(&[
        "encode",
        "vf-as1",
        "binary",
        "write-ram",
        "FA01",
        "50%",
        "--command",
        "S",
    ]));
    assert!(s.contains("2F 53 FA 01 13 88 18"), "{s}");
    let tripped = stdout(&vfd(&[
        "encode",
        "vf-as1",
        "binary",
        "write-ram",
        "FA01",
        "50%",
        "--command",
        "s",
    ]));
    assert!(tripped.contains("2F 73 FA 01 13 88 38"), "{tripped}");
    let none = vfd(&[
        "encode",
        "yd1000",
        "binary",
        "read",
        "FD00",
        "--command",
        "G",
    ]);
    assert!(!none.status.success());
    assert!(
        stderr(&none).contains("has no command G"),
        "{}",
        stderr(&none)
    );
}

#[test]
fn decode_refuses_bad_frames_with_the_reason() {
    let bad_sum = vfd(&["decode", "2F 52 FD 00 7F"]);
    assert!(!bad_sum.status.success());
    assert!(
        stderr(&bad_sum).contains("checksum mismatch: computed 7Eh, frame has 7Fh"),
        "{}",
        stderr(&bad_sum)
    );
    let not_hex = vfd(&["decode", "2F 52 FG 00 7E"]);
    assert!(!not_hex.status.success());
    assert!(
        stderr(&not_hex).contains("`G` is not a hex digit"),
        "{}",
        stderr(&not_hex)
    );
    let garbage = vfd(&["decode", "(hello)\\r"]);
    assert!(!garbage.status.success());
    assert!(!stderr(&garbage).contains("panicked"));
}

#[test]
fn decode_json_is_one_object() {
    let output = vfd(&["decode", "--json", "2F 52 FD 00 7E"]);
    assert!(output.status.success());
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(json["valid"], true);
    assert_eq!(json["protocol"], "binary");
    assert_eq!(json["direction"], "request");
    assert_eq!(json["register"], "FD00");
    let bad = vfd(&["decode", "--json", "2F 52 FD 00 7F"]);
    assert!(!bad.status.success());
    let json: serde_json::Value = serde_json::from_slice(&bad.stdout).expect("JSON");
    assert_eq!(json["valid"], false);
}

#[test]
fn encode_still_builds_frames_by_register_name() {
    let output = vfd(&["encode", "yd1000", "binary", "write-ram", "FA01", "60Hz"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stdout(&output).contains("hex:   2F 50 FA 01 17 70 01"));
    let refused = vfd(&["encode", "yd1000", "binary", "write-ram", "FA01", "400Hz"]);
    assert!(!refused.status.success());
    assert!(stderr(&refused).contains("outside the range"));
}

#[test]
fn encode_shows_the_frames_a_master_sends_first() {
    // A persistent parameter write over the FC 51's Modbus sets coil 65 first (its
    // `persistence` step); a DV1 Eaton read of a paged parameter switches the page first.
    let output = vfd(&[
        "encode",
        "fc51",
        "modbus",
        "write-persistent",
        "202",
        "5",
        "--address",
        "1",
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    let step = text
        .find("first: RAM write of FF00h to coil 65")
        .expect(&text);
    let step_frame = text.find("hex:   01 05 00 40 FF 00 8D EE").expect(&text);
    let main_frame = text.find("hex:   01 06 07 E3 00 05 B9 4B").expect(&text);
    assert!(step < step_frame && step_frame < main_frame, "{text}");
    let output = vfd(&["encode", "dv1", "eaton", "read", "02-15", "--address", "1"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(
        text.contains("first: RAM write of 0001h to register 00FF"),
        "{text}"
    );
    assert_eq!(text.matches("hex:").count(), 2, "{text}");
}

#[test]
fn completions_are_printed_for_bash() {
    let output = vfd(&["completions", "bash"]);
    assert!(output.status.success());
    let text = stdout(&output);
    assert!(text.contains("_vfd()") && text.contains("decode"), "{text}");
}

#[test]
fn demo_runs_to_completion_piped() {
    let started = std::time::Instant::now();
    // fc51's tour, step by step; every other drive's is run below.
    let output = vfd(&["demo", "--drive", "fc51", "--seconds", "2"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    for step in [
        "$ vfd list",
        "$ vfd info",
        "$ vfd write",
        "$ vfd watch",
        "TRIPPED",
        "Done.",
    ] {
        assert!(text.contains(step), "demo shows `{step}`:\n{text}");
    }
    assert!(!text.contains('\x1b'), "no terminal codes when piped");
    // On a pseudo-terminal, every frame shown both ways, in hex and decoded.
    assert!(text.contains("on the pseudo-terminal /dev/"), "{text}");
    assert!(
        text.contains("    -> ") && text.contains("    <- "),
        "{text}"
    );
    // A bound on a hang: the tour takes about 5 s.
    assert!(started.elapsed() < std::time::Duration::from_secs(60));
    // `--drive` chooses; every described drive has a behaviour model now.
    for drive in ["yd1000", "vf-as1", "dv1"] {
        let demo = vfd(&["demo", "--drive", drive, "--seconds", "1"]);
        assert!(demo.status.success(), "{drive}: {}", stderr(&demo));
        assert!(stdout(&demo).contains("Done."), "{}", stdout(&demo));
    }
    // The DV1's tour: its status word at 1001h shows the trip; the reset is a write of
    // its own register (1101h = 9696h), never answered.
    let dv1 = vfd(&["demo", "--drive", "dv1", "--seconds", "1"]);
    assert!(dv1.status.success(), "{}", stderr(&dv1));
    let shown = stdout(&dv1);
    assert!(
        shown.contains("TRIPPED: H7A says so") && shown.contains("HFD reset   # reset"),
        "{shown}"
    );
    let default = vfd(&["demo", "--seconds", "1"]);
    assert!(default.status.success(), "{}", stderr(&default));
}

#[test]
fn decode_finds_the_protocol_variant_a_frame_is_in() {
    // 例一 with CR LF (the DV1 set to 07-06 = 2): the Eaton protocol's variant cr_lf.
    let text = stdout(&vfd(&["decode", "\\x0500FA00002D9\\r\\n"]));
    assert!(
        text.contains("eaton request of dv1 (Eaton computer-link protocol (ASCII), variant cr_lf), checksum ok"),
        "{text}"
    );
    let json = stdout(&vfd(&["decode", "--json", "\\x0600\\r\\n"]));
    assert!(json.contains("\"variant\": \"cr_lf\""), "{json}");
    // As printed, with CR only: the protocol as written, no variant named.
    let text = stdout(&vfd(&["decode", "\\x0500FA00002D9\\r"]));
    assert!(
        text.contains("(Eaton computer-link protocol (ASCII)), checksum ok"),
        "{text}"
    );
}

/// A register the manual gives no number (known by its instruction code only) is shown and
/// found by its code, with its wire numbers, and not by the number no frame carries; one
/// known by its page and number shows its place (fixtures/link-vocabulary).
#[test]
fn info_shows_registers_known_by_wire_numbers_or_pages() {
    let file = "tests/fixtures/link-vocabulary/kestrel_k7.yaml";
    let status = vfd(&["info", file, "H7A"]);
    assert!(status.status.success(), "{}", stderr(&status));
    let text = stdout(&status);
    assert!(text.starts_with("register H7A (Inverter status)"), "{text}");
    assert!(
        text.contains("number      none of its own: reached by its wire numbers"),
        "{text}"
    );
    assert!(text.contains("on link     read 7Ah, write -"), "{text}");
    let by_number = vfd(&["info", file, "0xFFFF"]);
    assert!(!by_number.status.success());
    assert!(stderr(&by_number).contains("has no register `0xFFFF`"));
    let paged = stdout(&vfd(&["info", file, "Pr.42"]));
    assert!(paged.contains("on link     page 0, offset 2Ah"), "{paged}");
    let list = stdout(&vfd(&["info", file]));
    assert!(
        list.lines().any(|l| l.starts_with("-        H7A")),
        "{list}"
    );
}
