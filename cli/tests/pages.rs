//! `vfd` over the DV1's Eaton protocol against `vfd sim`: parameters on different pages
//! and a register with its own command code, read and written by name, each process
//! switching the page itself (a new master knows no page).

mod common;

use common::{text, Sim};

#[test]
fn dv1_parameters_on_two_pages_are_read_and_written_over_the_eaton_protocol() {
    let sim = Sim::spawn(&["--drive", "dv1", "--protocol", "eaton", "--address", "0"]);
    let args = |rest: &[&str]| -> Vec<String> {
        let mut all: Vec<String> = rest.iter().map(|s| s.to_string()).collect();
        all.splice(1..1, ["--address".to_owned(), "0".to_owned()]);
        all
    };
    let run = |rest: &[&str]| {
        let owned = args(rest);
        let borrowed: Vec<&str> = owned.iter().map(String::as_str).collect();
        sim.vfd("dv1", "eaton", &borrowed)
    };
    let read = run(&["read", "02-15", "07-08", "H6F"]);
    assert!(read.status.success(), "{}", text(&read));
    let shown = text(&read);
    let line = |code: &str| {
        shown
            .lines()
            .find(|l| l.starts_with(code))
            .unwrap_or_else(|| panic!("no line for {code}: {shown}"))
            .to_owned()
    };
    assert!(line("02-15").ends_with("= 60.00 Hz"), "{shown}");
    assert!(line("07-08").ends_with("= 1"), "{shown}");
    assert!(line("H6F").ends_with("= 0.00 Hz"), "{shown}");
    let write = run(&["write", "02-15", "50"]);
    assert!(write.status.success(), "{}", text(&write));
    let back = run(&["read", "02-15"]);
    assert!(text(&back).contains("= 50.00 Hz"), "{}", text(&back));
    // Out of range: refused before anything is sent, the value is kept.
    let beyond = run(&["write", "02-15", "500"]);
    assert!(!beyond.status.success(), "{}", text(&beyond));
    assert!(
        text(&beyond).contains("outside the range 0 to 400 Hz"),
        "{}",
        text(&beyond)
    );
    assert!(text(&run(&["read", "02-15"])).contains("= 50.00 Hz"));
}
