//! The format's vocabulary for the computer-link family, proven by a made-up drive of that
//! family outside this workspace (`fixtures/computer-link/`: the drive, its own protocol
//! file in `protocols/`, a crate around them): a request's wait digit stated by the
//! example, examples and a sequence in a named variant (CR LF, and "no terminator", an
//! empty literal), stop bits "1 or 2", a register that takes the persistent command but
//! keeps the value in RAM, and byte-wide registers whose commands (`data_types: [byte]`)
//! carry two data digits where words take four, the page switch among them (`pages.data_type:
//! byte`). Its golden tests pass out of tree, and its virtual drive answers
//! the printed requests with the printed replies, byte for byte.
//!
//! The crate is built with its own Cargo.lock (`--locked --offline`) into a folder of the
//! workspace's target directory, kept between runs.

use std::path::Path;
use vfd_tests::out_of_tree::cargo_test;

/// One golden test per example (6) and sequence (2) of `heron_hl7.yaml`.
const GOLDEN_TESTS: [&str; 8] = [
    "heron_hl7::example_read_acceleration_waiting_30ms",
    "heron_hl7::example_write_frequency_persistent_kept_in_ram",
    "heron_hl7::example_read_frequency_cr_lf",
    "heron_hl7::example_write_acceleration_no_terminator",
    "heron_hl7::example_read_motor_poles",
    "heron_hl7::example_write_motor_poles",
    "heron_hl7::sequence_read_frequency_waiting_20ms_cr_lf",
    "heron_hl7::sequence_write_jog_frequency_on_page_0",
];

/// The virtual-drive tests of `fixtures/computer-link/tests/virtual_drive.rs`.
const VIRTUAL_DRIVE_TESTS: [&str; 8] = [
    "a_read_with_a_wait_digit_gets_the_printed_reply",
    "a_byte_wide_register_is_read_and_written_with_two_data_digits",
    "a_master_reads_and_writes_a_byte_wide_register_through_the_simulator",
    "a_persistent_write_of_a_ram_register_is_accepted_and_kept_in_ram",
    "a_read_in_cr_lf_gets_the_printed_reply",
    "a_write_without_terminator_gets_the_printed_reply",
    "the_page_switch_carries_two_data_digits",
    "a_master_switches_pages_with_two_data_digits_through_the_simulator",
];

#[test]
fn a_made_up_computer_link_drive_passes_its_golden_and_virtual_drive_tests_out_of_tree() {
    let stdout = cargo_test(
        Path::new(env!("CARGO_MANIFEST_DIR")),
        Path::new(env!("CARGO_TARGET_TMPDIR")),
        "computer-link",
    )
    .stdout;
    for name in GOLDEN_TESTS.iter().chain(&VIRTUAL_DRIVE_TESTS) {
        assert!(
            stdout.contains(&format!("test {name} ... ok")),
            "`{name}` did not pass in the outside crate:\n{stdout}"
        );
    }
    let golden = stdout
        .lines()
        .filter(|line| line.starts_with("test heron_hl7::") && line.ends_with("... ok"))
        .count();
    assert_eq!(golden, GOLDEN_TESTS.len(), "golden tests passed:\n{stdout}");
}
