//! Drive files as outside integrators write them (`tests/fixtures/integrator/`, made up
//! after such files): their examples show a running drive (an output frequency of 60 Hz, a
//! status word saying "running"), which the virtual drive does not start in. Each must be
//! valid, with exactly the warnings of its `.expected` file (`vfd check` prints them), and
//! its virtual drive, started at power-up, must answer a typed master.
//! Run with `UPDATE_EXPECT=1` to rewrite the expectations after a deliberate change.

use std::path::Path;
use vfd_runtime::transaction::Master;
use vfd_runtime::virtual_drive::Simulator;
use vfd_runtime::{CommandKind, Request};
use vfd_tests::expectations::{check_all_rendered, entries, render_warnings, Case};

fn cases() -> Vec<Case> {
    entries(Path::new("fixtures/integrator"), |path| {
        path.extension().is_some_and(|ext| ext == "yaml")
    })
    .into_iter()
    .map(|drive| Case {
        expected: drive.with_extension("expected"),
        drive,
        protocols: Some("../drives/protocols".into()),
    })
    .collect()
}

#[test]
fn examples_of_a_running_drive_check_ok_with_the_expected_warnings() {
    let cases = cases();
    assert!(cases.len() >= 2, "found {} integrator files", cases.len());
    check_all_rendered(&cases, render_warnings);
    for case in &cases {
        let compiled = vfd_codegen::compile_with_warnings(&case.drive, case.protocols.as_deref());
        assert!(
            compiled.drive.is_ok(),
            "{} is valid:\n{}",
            case.drive.display(),
            compiled.drive.unwrap_err()
        );
    }
}

#[test]
fn the_virtual_drive_of_each_answers_a_master_from_power_up() {
    for case in cases() {
        let ir = vfd_codegen::compile(&case.drive, case.protocols.as_deref()).expect("valid");
        let drive = vfd_codegen::drive_info(&ir);
        let output = drive
            .register("output_frequency")
            .expect("an output frequency");
        let sim = Simulator::new(drive);
        sim.lock().set_address(1);
        let protocol = drive.protocols[0];
        let mut master = Master::for_protocol(
            sim.link(protocol),
            protocol,
            drive.serial.default,
            drive.serial.timing,
        )
        .with_address(Some(1));
        let request = Request::for_register(CommandKind::Read, output, 0);
        let answer = master.transact(&request).expect("the read is answered");
        assert_eq!(
            answer.data,
            Some(0),
            "{}: stopped at power-up",
            case.drive.display()
        );
    }
}
