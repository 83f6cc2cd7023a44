//! Test support: protocol files written in test strings, lowered for a small drive that
//! uses them, with compact views of what comes out.

use super::lower;
use crate::diagnostics::{Diagnostic, Diagnostics};
use crate::load::{LoadedDrive, ProtocolSource};
use crate::parse::SourceFile;
use std::path::Path;
use vfd_runtime::{FrameLayout, Part, Protocol};

/// Where the protocol file under test claims to be.
pub(super) const PROTOCOL_FILE: &str = "protocols/test.yaml";

/// A valid text protocol: a read and a write, an error reply.
pub(super) const PROTOCOL: &str = r#"protocol:
  id: test
  name: Test ASCII
  text: true
  max_frame_len: 17
  default_optional_parts: [sum]

parts:
  start: { literal: "(" }
  address: { field: address, format: decimal, width: 2, optional: if_format_matches }
  register: { field: register, format: hex, width: 4 }
  sum: { checksum: sum8, format: hex, marker: "&", covers_from: start, optional: true }
  cr: { literal: "\r" }

layouts:
  read_request: [start, address, { field: command, format: char, allowed: [R] }, register, sum, cr]
  write_request: [start, address, { field: command, format: char, allowed: [W] }, register, { field: data, format: hex, width: 4 }, sum, cr]
  reply: [start, address, { field: command, format: char, allowed: [R, W], fold_case: true }, register, { field: data, format: hex, width: 4 }, sum, cr]
  error_reply: [start, address, { field: command, format: char, allowed: [N] }, { field: error_code, format: hex, width: 4 }, sum, cr]

commands:
  - { code: R, kind: read, request: read_request, reply: reply }
  - { code: W, kind: write_persistent, request: write_request, reply: reply }

error_reply: error_reply
"#;

/// A drive file using the protocol `test`; `{reference}` is replaced by the rest of its
/// `protocols:` entry (address maps, pre-steps).
const DRIVE: &str = r#"drive:
  id: test_drive
  vendor: Test
  model: T1
  name: Test drive
  manual: none.txt

serial:
  source: "2"
  baud_rates: [9600]
  parities: [even]
  data_bits: 8
  stop_bits_sent: 1
  stop_bits_received: 1
  default: { baud: 9600, parity: even, data_bits: 8, stop_bits: 1 }
  timing:
    startup_delay_ms: 1000
    frame_abandon_ms: 1000
    processing_allowance_ms: 500

addressing:
  min: 0
  max: 31

protocols:
  - id: ascii
    uses: test
    source: "4.1"
{reference}
error_codes:
  source: "3.2"
  codes:
    - { code: 1, id: data_error, name: Data error, meaning: Out of range. }

registers: []
"#;

/// The drive file text with `reference` (lines indented by four spaces) in its entry.
pub(super) fn drive_with(reference: &str) -> String {
    DRIVE.replace("{reference}", reference)
}

/// [`PROTOCOL`] with each `(from, to)` applied; each `from` must occur exactly once.
pub(super) fn protocol_with(edits: &[(&str, &str)]) -> String {
    let mut yaml = PROTOCOL.to_owned();
    for (from, to) in edits {
        assert_eq!(
            yaml.matches(from).count(),
            1,
            "`{from}` must occur exactly once in the test protocol"
        );
        yaml = yaml.replacen(from, to, 1);
    }
    yaml
}

/// Reads a file that must have no problem.
fn read_whole<T: serde::de::DeserializeOwned + schemars::JsonSchema>(
    source: &SourceFile,
) -> Result<T, Vec<Diagnostic>> {
    let read = source.read_model::<T>();
    match read.value {
        Some(value) if read.problems.is_empty() => Ok(value),
        _ => Err(read.problems),
    }
}

/// Parses both files and lowers the protocol: the runtime protocol, or every problem found
/// (a parse error alone, as the generator reports it), in file and position order.
pub(super) fn lower_both(drive: &str, protocol: &str) -> Result<Protocol, Vec<Diagnostic>> {
    let drive_source = SourceFile::from_text(Path::new("drive.yaml"), drive.to_owned());
    let model = read_whole(&drive_source)?;
    let source = SourceFile::from_text(Path::new(PROTOCOL_FILE), protocol.to_owned());
    let file = read_whole(&source)?;
    let loaded = LoadedDrive {
        source: drive_source,
        model,
        protocol_files: vec![ProtocolSource {
            reference: 0,
            source,
            file,
            inherited: None,
        }],
        sources: Vec::new(),
        incomplete: Vec::new(),
    };
    let mut out = Diagnostics::default();
    let lowered = lower(&loaded, &mut out);
    out.attach_sources(|_| None);
    match lowered.into_iter().next() {
        Some(protocol) if out.is_empty() => Ok(protocol.runtime),
        _ => {
            assert!(!out.is_empty(), "a protocol was left out without a problem");
            Err(out.items)
        }
    }
}

/// Lowers `protocol` for the plain test drive.
pub(super) fn lower_text(protocol: &str) -> Result<Protocol, Vec<Diagnostic>> {
    lower_both(&drive_with(""), protocol)
}

/// Lowers `protocol`, which must be valid.
pub(super) fn lowered(protocol: &str) -> Protocol {
    match lower_text(protocol) {
        Ok(protocol) => protocol,
        Err(problems) => panic!("the test protocol has problems:\n{}", shown(&problems)),
    }
}

/// The problems `protocol` has, each as `line:column path: message`.
pub(super) fn problems(protocol: &str) -> Vec<String> {
    problems_of(lower_text(protocol))
}

/// The problems of a lowering that must fail, each as `line:column path: message`.
pub(super) fn problems_of(result: Result<Protocol, Vec<Diagnostic>>) -> Vec<String> {
    match result {
        Ok(_) => panic!("the test protocol lowered without problems"),
        Err(problems) => problems.iter().map(one_line).collect(),
    }
}

fn one_line(problem: &Diagnostic) -> String {
    format!(
        "{}:{} {}: {}",
        problem.position.line, problem.position.column, problem.path, problem.message
    )
}

fn shown(problems: &[Diagnostic]) -> String {
    problems.iter().map(one_line).collect::<Vec<_>>().join("\n")
}

/// The 1-based line of the only line of `yaml` containing `needle`.
pub(super) fn line_of(yaml: &str, needle: &str) -> usize {
    let lines: Vec<usize> = yaml
        .lines()
        .enumerate()
        .filter(|(_, line)| line.contains(needle))
        .map(|(index, _)| index + 1)
        .collect();
    assert_eq!(lines.len(), 1, "`{needle}` must be on exactly one line");
    lines[0]
}

/// `line:column` of `needle`, which must occur on exactly one line.
pub(super) fn at(yaml: &str, needle: &str) -> String {
    let line = line_of(yaml, needle);
    let text = yaml.lines().nth(line - 1).unwrap_or_default();
    let column = text.find(needle).unwrap_or(0) + 1;
    format!("{line}:{column}")
}

/// The layout called `name` among those the protocol's commands and error reply use.
pub(super) fn layout<'p>(protocol: &'p Protocol, name: &str) -> &'p FrameLayout {
    protocol
        .commands
        .iter()
        .flat_map(|command| [&command.request, &command.reply])
        .chain(protocol.error_reply.iter())
        .find(|layout| layout.name == name)
        .unwrap_or_else(|| panic!("no layout `{name}` is used"))
}

/// The parts of the layout called `name`.
pub(super) fn parts<'p>(protocol: &'p Protocol, name: &str) -> &'p [Part] {
    &layout(protocol, name).parts
}
