//! A drive that is not built into `vfd`, used by its file: named by path wherever a drive
//! is asked for, found by id through `--drives DIR` and `VFD_DRIVES`, its protocol file
//! taken from the ones `vfd` ships when the drive's folder has none, and refused with
//! `vfd check`'s diagnostics (nothing opened) when it has problems. Every run is from a
//! folder outside the workspace, as from an installed `vfd`.

mod common;

use common::{text, Sim};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder outside the workspace holding `pump.yaml`, a copy of the out-of-tree
/// example crate's drive (id `demo_pump`, the shipped Toshiba-style binary protocol, no
/// `protocols/` folder beside it).
fn outside_folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vfd-drive-files-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/external-crate/demo_pump.yaml");
    std::fs::copy(source, dir.join("pump.yaml")).expect("the example drive file");
    dir
}

/// `vfd ARGS...` run in `dir`, with `VFD_DRIVES` as given (unset when `None`).
fn vfd_in(dir: &Path, drives_variable: Option<&Path>, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_vfd"));
    command.current_dir(dir).args(args).env_remove("VFD_DRIVES");
    if let Some(folder) = drives_variable {
        command.env("VFD_DRIVES", folder);
    }
    command.output().expect("vfd runs")
}

#[test]
fn a_drive_file_is_used_by_its_path() {
    let dir = outside_folder("path");
    let check = vfd_in(&dir, None, &["check", "pump.yaml"]);
    assert!(check.status.success(), "{}", text(&check));
    assert!(
        text(&check).contains("pump.yaml: ok (4 registers"),
        "{}",
        text(&check)
    );

    let info = vfd_in(&dir, None, &["info", "./pump.yaml", "ACC"]);
    assert!(info.status.success(), "{}", text(&info));
    assert!(text(&info).contains("Acceleration time"), "{}", text(&info));

    let decode = vfd_in(
        &dir,
        None,
        &["decode", "--drive", "pump.yaml", "2F 52 00 10 00 32 C3"],
    );
    assert!(decode.status.success(), "{}", text(&decode));
    assert!(text(&decode).contains("of demo_pump"), "{}", text(&decode));
    assert!(text(&decode).contains("checksum ok"), "{}", text(&decode));

    let encode = vfd_in(
        &dir,
        None,
        &[
            "encode",
            "./pump.yaml",
            "binary",
            "write-ram",
            "FA01",
            "50Hz",
        ],
    );
    assert!(encode.status.success(), "{}", text(&encode));
    assert!(
        text(&encode).contains("2F 50 FA 01 13 88 15"),
        "the manual's frame: {}",
        text(&encode)
    );
}

#[test]
fn the_virtual_drive_of_a_drive_file_answers_vfd_by_path() {
    let dir = outside_folder("sim");
    let file = dir.join("pump.yaml");
    let file = file.to_str().expect("a UTF-8 path");
    let sim = Sim::spawn(&["--drive", file]);
    let read = sim.vfd(file, "binary", &["read", "ACC", "MODE"]);
    assert!(read.status.success(), "{}", text(&read));
    assert!(text(&read).contains("= 5.0 s"), "{}", text(&read));
    let write = sim.vfd(file, "binary", &["write", "ACC", "12.5s"]);
    assert!(write.status.success(), "{}", text(&write));
    let back = sim.vfd(file, "binary", &["read", "ACC"]);
    assert!(text(&back).contains("= 12.5 s"), "{}", text(&back));
    // Checked against the file's range before anything is sent.
    let refused = sim.vfd(file, "binary", &["write", "FA01", "60Hz"]);
    assert!(!refused.status.success());
    assert!(
        text(&refused).contains("nothing was sent"),
        "{}",
        text(&refused)
    );
}

#[test]
fn drive_folders_add_drives_to_list_and_to_lookup_by_id() {
    let dir = outside_folder("search");
    let elsewhere = outside_folder("search-cwd");
    let by_option = vfd_in(
        &elsewhere,
        None,
        &["--drives", dir.to_str().unwrap(), "list"],
    );
    assert!(by_option.status.success(), "{}", text(&by_option));
    assert!(
        text(&by_option).contains("demo_pump"),
        "{}",
        text(&by_option)
    );
    assert!(
        text(&by_option).contains("pump.yaml"),
        "{}",
        text(&by_option)
    );
    assert!(text(&by_option).contains("yd1000"), "built-in drives stay");

    let by_variable = vfd_in(&elsewhere, Some(&dir), &["info", "demo_pump"]);
    assert!(by_variable.status.success(), "{}", text(&by_variable));
    assert!(
        text(&by_variable).contains("Demo DP-1"),
        "{}",
        text(&by_variable)
    );

    let without = vfd_in(&elsewhere, None, &["info", "demo_pump"]);
    assert!(!without.status.success());
    assert!(
        text(&without).contains("unknown drive `demo_pump`"),
        "{}",
        text(&without)
    );
    assert!(
        text(&without).contains("path of a drive file"),
        "{}",
        text(&without)
    );
}

#[test]
fn a_drive_file_with_problems_stops_the_command_before_the_port_is_opened() {
    let dir = outside_folder("broken");
    let good = std::fs::read_to_string(dir.join("pump.yaml")).unwrap();
    let broken = good.replacen("default: 5.0", "default: 999.0", 1);
    assert_ne!(good, broken, "the fixture has the default to break");
    std::fs::write(dir.join("broken.yaml"), broken).unwrap();

    let check = vfd_in(&dir, None, &["check", "broken.yaml"]);
    assert!(!check.status.success());
    let read = vfd_in(
        &dir,
        None,
        &[
            "read",
            "--drive",
            "broken.yaml",
            "--port",
            "/dev/no-such-port",
            "ACC",
        ],
    );
    assert!(!read.status.success());
    let said = text(&read);
    // Exactly vfd check's diagnostics, and no word about the port: it was never opened.
    let diagnostics = String::from_utf8_lossy(&check.stdout);
    let first = diagnostics.lines().next().unwrap_or_default();
    assert!(first.contains("error"), "check's first line: {diagnostics}");
    assert!(
        said.contains(diagnostics.trim()),
        "{said}\n--- check said\n{diagnostics}"
    );
    assert!(said.contains("nothing was opened or sent"), "{said}");
    assert!(!said.contains("no-such-port"), "{said}");

    let list = vfd_in(&dir, Some(&dir), &["list"]);
    assert!(list.status.success(), "{}", text(&list));
    assert!(
        text(&list).contains("broken.yaml: not usable"),
        "{}",
        text(&list)
    );
}

#[test]
fn a_missing_drive_file_is_named() {
    let dir = outside_folder("missing");
    let info = vfd_in(&dir, None, &["info", "./nothere.yaml"]);
    assert!(!info.status.success());
    assert!(
        text(&info).contains("no drive file ./nothere.yaml"),
        "{}",
        text(&info)
    );
}

/// A request frame and the reply the manual prints for it.
type Exchange = (&'static [u8], &'static [u8]);

/// The made-up drive of a new family (`tests/fixtures/computer-link/`: its own protocol
/// file in `protocols/` next to it) served by `vfd sim --drive FILE`: a raw client writes
/// the example frames and reads back the printed replies, byte for byte, in the default
/// variant (CR) and, with `--variant`, in CR LF and with no terminator.
#[test]
fn vfd_sim_answers_a_new_family_drive_file_byte_for_byte() {
    use std::time::{Duration, Instant};
    use vfd_runtime::transport::{PtyTransport, Transport};
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/computer-link/heron_hl7.yaml")
        .canonicalize()
        .expect("the fixture drive");
    let file = file.to_str().expect("a UTF-8 path");
    let cases: [(&[&str], &[Exchange]); 3] = [
        (
            &[],
            &[
                (b"\x0501423FA\r", b"\x02010064\x032B\r"),
                (b"\x0501C101194D4\r", b"\x0601\r"),
                (b"\x0501700F8\r", b"\x020104\x03C5\r"),
                (b"\x0501F00066D\r", b"\x0601\r"),
            ],
        ),
        (
            &["--variant", "cr_lf"],
            &[(b"\x0501410F6\r\n", b"\x02011388\x0335\r\n")],
        ),
        (&["--variant", "none"], &[(b"\x0501C20012CDC", b"\x0601")]),
    ];
    for (extra, exchanges) in cases {
        let mut args = vec!["--drive", file];
        args.extend_from_slice(extra);
        let sim = Sim::spawn(&args);
        let mut line = PtyTransport::open_path(Path::new(&sim.port)).expect("the device opens");
        for (request, reply) in exchanges {
            line.send(request).expect("sent");
            let mut heard = Vec::new();
            let deadline = Instant::now() + Duration::from_secs(3);
            let mut buf = [0u8; 64];
            while heard.len() < reply.len() && Instant::now() < deadline {
                let n = line.receive(&mut buf, deadline).unwrap_or(0);
                heard.extend_from_slice(&buf[..n]);
            }
            assert_eq!(
                heard,
                reply.to_vec(),
                "{extra:?}: the reply to {:?}",
                String::from_utf8_lossy(request)
            );
            std::thread::sleep(Duration::from_millis(30));
        }
    }
}

#[test]
fn a_local_copy_of_a_shipped_protocol_file_that_differs_is_warned_about() {
    let dir = outside_folder("local-protocol");
    std::fs::create_dir_all(dir.join("protocols")).unwrap();
    let shipped = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../drives/protocols/toshiba-binary.yaml"),
    )
    .unwrap();
    let local = dir.join("protocols/toshiba-binary.yaml");

    std::fs::write(&local, &shipped).unwrap();
    let same = vfd_in(&dir, None, &["check", "--deny-warnings", "pump.yaml"]);
    assert!(
        !text(&same).contains("differs from the protocol file"),
        "an identical copy: {}",
        text(&same)
    );

    std::fs::write(&local, format!("{shipped}# an older copy\n")).unwrap();
    let differs = vfd_in(&dir, None, &["check", "pump.yaml"]);
    assert!(
        differs.status.success(),
        "a warning only: {}",
        text(&differs)
    );
    let said = text(&differs);
    assert!(
        said.contains("warning: protocols/toshiba-binary.yaml differs from the protocol file `toshiba-binary` shipped with the tool; the local file is used"),
        "{said}"
    );
    assert!(said.contains("= at: protocols[0].uses"), "{said}");
    assert!(
        said.contains(
            "hint: an older copy is the likely cause: delete protocols/toshiba-binary.yaml"
        ),
        "{said}"
    );
    let denied = vfd_in(&dir, None, &["check", "--deny-warnings", "pump.yaml"]);
    assert!(!denied.status.success(), "{}", text(&denied));
}

/// `tests/fixtures/integrator/NAME` copied into a fresh folder outside the workspace (the
/// shipped protocol files serve it), and its path there.
fn integrator_file(name: &str, folder: &str) -> (PathBuf, PathBuf) {
    let dir = outside_folder(folder);
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/integrator")
        .join(name);
    std::fs::copy(source, dir.join(name)).expect("the fixture drive file");
    let file = dir.join(name);
    (dir, file)
}

/// Drive files written by an integrator whose example replies show a running drive (an
/// output frequency of 60 Hz, which the virtual drive at power-up does not have): `vfd
/// check` accepts them (one with a warning naming what still differs), `vfd decode` reads
/// their frames, and `vfd read` reads them from `vfd sim` serving the same file.
#[test]
fn files_whose_examples_show_a_running_drive_check_ok_and_work_on_a_line() {
    let cases = [
        (
            "ts15_like.yaml",
            "(01RFD001770&BA)\r",
            "ts15_like.yaml: ok (5 registers, 4 examples)",
        ),
        (
            "hx_e_like.yaml",
            "\x020117702\x0362\r",
            "hx_e_like.yaml: ok (5 registers, 4 examples, 1 warning)",
        ),
    ];
    for (name, reply, ok) in cases {
        let (dir, file) = integrator_file(name, "integrator");
        let check = vfd_in(&dir, None, &["check", name]);
        assert!(check.status.success(), "{}", text(&check));
        assert!(text(&check).contains(ok), "{}", text(&check));
        assert!(!text(&check).contains("error"), "{}", text(&check));

        let decode = vfd_in(&dir, None, &["decode", "--drive", name, "--reply", reply]);
        assert!(decode.status.success(), "{}", text(&decode));
        assert!(text(&decode).contains("checksum ok"), "{}", text(&decode));
        assert!(
            text(&decode).contains("60.00 Hz") || text(&decode).contains("6000 (1770h)"),
            "{}",
            text(&decode)
        );

        let path = file.to_str().expect("a UTF-8 path");
        let sim = Sim::spawn(&["--drive", path]);
        let read = vfd_in(
            &dir,
            None,
            &[
                "read",
                "--drive",
                name,
                "--port",
                &sim.port,
                "output_frequency",
            ],
        );
        assert!(read.status.success(), "{name}: {}", text(&read));
        assert!(text(&read).contains("0.00 Hz"), "{name}: {}", text(&read));
    }
}

/// A file whose only error lies off the wire (an example's `not_simulated` that the virtual
/// drive contradicts) fails `vfd check`, but `vfd decode`, `vfd read` and `vfd sim` use it,
/// after a warning naming where the problem is and the command that lists it.
#[test]
fn a_problem_off_the_wire_is_reported_and_does_not_stop_wire_commands() {
    let (dir, file) = integrator_file("ts15_like.yaml", "off-the-wire");
    let good = std::fs::read_to_string(&file).unwrap();
    let claimed = good.replacen(
        "    value: 60.0\n",
        "    value: 60.0\n    not_simulated: \"Believed to need a running motor.\"\n",
        1,
    );
    assert_ne!(good, claimed, "the fixture has the example to change");
    std::fs::write(&file, claimed).unwrap();

    let check = vfd_in(&dir, None, &["check", "ts15_like.yaml"]);
    assert!(!check.status.success(), "{}", text(&check));
    assert!(
        text(&check).contains("error: the virtual drive gives this example's reply"),
        "{}",
        text(&check)
    );
    assert!(
        text(&check).contains("do not concern the wire"),
        "{}",
        text(&check)
    );

    let decode = vfd_in(
        &dir,
        None,
        &["decode", "--drive", "ts15_like.yaml", "(01RFD001770&BA)\r"],
    );
    assert!(decode.status.success(), "{}", text(&decode));
    assert!(text(&decode).contains("60.00 Hz"), "{}", text(&decode));
    let warned = String::from_utf8_lossy(&decode.stderr);
    assert!(
        warned.contains("problem(s) that do not concern the wire, at examples[0].not_simulated"),
        "{warned}"
    );
    assert!(warned.contains("`vfd check ts15_like.yaml`"), "{warned}");

    let path = file.to_str().expect("a UTF-8 path");
    let sim = Sim::spawn(&["--drive", path]);
    let read = vfd_in(
        &dir,
        None,
        &[
            "read",
            "--drive",
            "ts15_like.yaml",
            "--port",
            &sim.port,
            "ACC",
        ],
    );
    assert!(read.status.success(), "{}", text(&read));
    assert!(text(&read).contains("10.0 s"), "{}", text(&read));
}

/// A drive of the search path whose file has problems on the wire, named by its id: the
/// command says the file has problems and lists them, not that the drive is unknown.
#[test]
fn a_broken_file_named_by_its_id_says_what_is_wrong_with_it() {
    for file_name in ["demo_pump.yaml", "pump-copy.yaml"] {
        let dir = outside_folder("broken-by-id");
        let good = std::fs::read_to_string(dir.join("pump.yaml")).unwrap();
        std::fs::remove_file(dir.join("pump.yaml")).unwrap();
        let broken = good.replacen("default: 5.0", "default: 999.0", 1);
        std::fs::write(dir.join(file_name), broken).unwrap();
        let elsewhere = outside_folder("broken-by-id-cwd");
        let info = vfd_in(&elsewhere, Some(&dir), &["info", "demo_pump"]);
        assert!(!info.status.success());
        let said = text(&info);
        assert!(!said.contains("unknown drive"), "{file_name}: {said}");
        assert!(
            said.contains(&format!("{file_name} cannot be used: it has 1 problem(s)")),
            "{file_name}: {said}"
        );
        assert!(said.contains("registers[0].default"), "{file_name}: {said}");
        assert!(said.contains("vfd check"), "{file_name}: {said}");
    }
}
