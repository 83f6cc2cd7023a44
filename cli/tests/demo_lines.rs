//! The lines `vfd demo` prints are commands a user can paste: every `vfd write` line runs.

mod common;

use common::{text, Sim};

/// Every `vfd write` line the demo prints runs when pasted (against `vfd sim` of the same
/// drive and protocol, the demo's own virtual drive being gone once it ends), the stop line
/// included.
#[test]
fn the_demo_s_write_lines_run_when_pasted() {
    let demo = std::process::Command::new(env!("CARGO_BIN_EXE_vfd"))
        .args(["demo", "--seconds", "1"])
        .output()
        .expect("vfd runs");
    assert!(demo.status.success(), "{}", text(&demo));
    let printed = String::from_utf8_lossy(&demo.stdout).into_owned();
    let writes: Vec<&str> = printed
        .lines()
        .filter_map(|line| line.strip_prefix("$ vfd write "))
        .collect();
    assert!(writes.iter().any(|w| w.contains("# stop")), "{printed}");
    let words = |line: &str| -> Vec<String> {
        let command = line.split('#').next().unwrap_or_default();
        command.split_whitespace().map(str::to_owned).collect()
    };
    let first = words(writes[0]);
    let option = |name: &str| {
        let at = first.iter().position(|w| w == name).expect(name);
        first[at + 1].clone()
    };
    let (drive, protocol) = (option("--drive"), option("--protocol"));
    let sim = Sim::start(&drive, &protocol);
    for line in &writes {
        let mut args = words(line);
        let at = args.iter().position(|w| w == "--port").expect("--port");
        args[at + 1] = sim.port.clone();
        let pasted = std::process::Command::new(env!("CARGO_BIN_EXE_vfd"))
            .arg("write")
            .args(&args)
            .output()
            .expect("vfd runs");
        assert!(
            pasted.status.success(),
            "vfd write {line}: {}",
            text(&pasted)
        );
    }
}
