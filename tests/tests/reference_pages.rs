//! The reference pages read right (issues 20 and 22): they drop what a drive has nothing
//! for, derive every sentence about registers, codes and timing from the drive's own data,
//! show the behaviour model's assumptions, and print codes, registers and frames as the
//! manuals write them. Each test states its rule for every drive the repository has (and a
//! small fixture drive), so a template or view change that brings a confusing spot back
//! fails here.

use vfd_codegen::ir::{DriveIr, ProtocolIr};
use vfd_codegen::OutputNames;
use vfd_runtime::layout::{Format, Part, Role};

/// Every shipped drive's IR and page, as `vfd generate` makes them.
fn shipped() -> Vec<(DriveIr, String)> {
    vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"))
        .drives
        .into_iter()
        .map(|d| (d.ir, unwrapped(&d.markdown)))
        .collect()
}

/// A page with its paragraphs and list items on one line each, as the assertions read it.
fn unwrapped(page: &str) -> String {
    vfd_codegen::unwrap_markdown(page)
}

fn shipped_page(id: &str) -> (DriveIr, String) {
    shipped()
        .into_iter()
        .find(|(ir, _)| ir.id == id)
        .unwrap_or_else(|| panic!("no drive {id}"))
}

/// A small fixture drive: one register, no bit fields, code tables, examples, errata or
/// behaviour model.
fn fixture_page() -> (DriveIr, String) {
    let ir = vfd_codegen::compile(
        std::path::Path::new("fixtures/error-tables/drive.yaml"),
        Some(std::path::Path::new("../drives/protocols")),
    )
    .unwrap_or_else(|d| panic!("the fixture compiles:\n{d:?}"));
    let page = vfd_codegen::markdown_page(&ir, &OutputNames::default()).expect("renders");
    (ir, unwrapped(&page))
}

/// The text of a protocol's section (from its `### ... — `id`` heading to the next `###`
/// heading of the same level).
fn protocol_section<'a>(page: &'a str, id: &str) -> &'a str {
    let heading = format!("— `{id}`\n");
    let start = page
        .find(&heading)
        .unwrap_or_else(|| panic!("no section for protocol {id}"));
    let rest = &page[start..];
    let end = rest[heading.len()..]
        .find("\n### ")
        .or_else(|| rest[heading.len()..].find("\n## "))
        .map_or(rest.len(), |e| e + heading.len());
    &rest[..end]
}

/// The frame layouts of a protocol's requests.
fn request_layouts<'a>(
    ir: &'a DriveIr,
    protocol: &'a ProtocolIr,
) -> impl Iterator<Item = &'a vfd_runtime::FrameLayout> + 'a {
    let file = ir.protocol_files.iter().find(|f| f.id == protocol.uses);
    protocol
        .commands
        .iter()
        .filter_map(move |c| file.and_then(|f| f.layouts.iter().find(|l| l.name == c.request)))
}

/// The row of the page's table whose line starts with `start`.
fn row<'a>(page: &'a str, start: &str) -> &'a str {
    page.lines()
        .find(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no row starting {start:?}"))
}

#[test]
fn a_page_drops_the_sections_a_drive_has_nothing_for() {
    let (_, page) = fixture_page();
    for heading in [
        "## Bit fields",
        "## Code tables",
        "## Value examples",
        "## Example frames",
        "## Manual errata",
        "(#bit-fields)",
        "(#code-tables)",
        "(#value-examples)",
        "(#example-frames)",
        "(#manual-errata)",
        "\nNotes:",
        "Ranges naming another register",
        "† marks",
        "links its code table",
        "()",
    ] {
        assert!(
            !page.contains(heading),
            "the fixture's page shows {heading:?}:\n{page}"
        );
    }
    for kept in [
        "## Registers",
        "## Error replies",
        "## Virtual drive",
        "(#virtual-drive)",
    ] {
        assert!(page.contains(kept), "the fixture's page lacks {kept:?}");
    }
    // The shipped drives have each section they have something for. Where a section is
    // missing, the drive's `drive.manual_note` says why: the GS2's pages read print no
    // example frame; the WJ200's and the VFD-B's no erratum; the PI500's Appendix I pages
    // with the 03H/06H examples were in no stored copy; the FR-E700's 4.18 pages with
    // frames were in none either.
    for (ir, page) in shipped() {
        for (heading, has) in [
            ("## Bit fields", !ir.bitfields.is_empty()),
            ("## Code tables", !ir.code_tables.is_empty()),
            ("## Example frames", !ir.examples.is_empty()),
            ("## Manual errata", !ir.manual_errata.is_empty()),
        ] {
            assert!(
                !has || page.contains(heading),
                "{}: {heading} missing",
                ir.id
            );
        }
    }
}

#[test]
fn the_range_sentence_names_exactly_the_registers_that_bound_ranges() {
    for (ir, page) in shipped() {
        let mut named: Vec<&str> = Vec::new();
        for r in &ir.registers {
            for bound in [&r.min, &r.max].into_iter().flatten() {
                if let Some(code) = bound.register.as_deref() {
                    if !named.contains(&code) {
                        named.push(code);
                    }
                }
            }
        }
        let sentence = "Ranges naming another register";
        if named.is_empty() {
            assert!(
                !page.contains(sentence),
                "{}: the range sentence is boilerplate",
                ir.id
            );
        } else {
            let expected = format!("{sentence} ({})", named.join(", "));
            assert!(page.contains(&expected), "{}: expected {expected:?}", ir.id);
        }
    }
    let (_, dv1) = shipped_page("dv1");
    assert!(!dv1.contains("(FH, UL, LL)"), "the DV1 has no FH, UL or LL");
}

#[test]
fn the_behaviour_models_assumptions_are_on_the_page_and_a_drive_without_one_is_told() {
    for (ir, page) in shipped() {
        let behaviour = ir
            .behaviour
            .as_ref()
            .expect("every shipped drive has a model");
        assert!(
            page.contains(behaviour.note.trim()),
            "{}: the behaviour note is not on the page",
            ir.id
        );
        let section = &page[page.find("## Virtual drive").expect("section")..];
        for protocol in &ir.protocols {
            assert!(
                section.contains(&format!("| `{}` |", protocol.id)),
                "{}: no refusal row for {}",
                ir.id,
                protocol.id
            );
        }
    }
    let (_, page) = fixture_page();
    assert!(page.contains("no behaviour model"), "{page}");
    assert!(page.contains("never runs"));
    assert!(page.contains("stays silent on every refused request"));
}

#[test]
fn code_registers_and_multi_bit_fields_link_their_code_table_instead_of_a_decimal_range() {
    for (ir, page) in shipped() {
        for table in &ir.code_tables {
            assert!(
                page.contains(&format!("<a id=\"code-table-{}\"></a>", table.id)),
                "{}: no anchor for code table {}",
                ir.id,
                table.id
            );
        }
        for r in ir.registers.iter().filter(|r| r.code_table.is_some()) {
            let label = vfd_runtime::info::manual_number(r.space, r.address, &r.code);
            let line = row(&page, &format!("| `{label}` | {} |", r.code));
            let link = format!("(#code-table-{})", r.code_table.as_deref().unwrap());
            assert!(
                line.contains(&link),
                "{}: {} does not link {link}: {line}",
                ir.id,
                r.code
            );
        }
        for b in &ir.bitfields {
            for f in b.fields.iter().filter(|f| f.width > 1) {
                if let Some(table) = &f.code_table {
                    let bits = format!("| {}:{} | `{}` |", f.lsb + f.width - 1, f.lsb, f.id);
                    let line = row(&page, &bits);
                    assert!(
                        line.contains(&format!("(#code-table-{table})")),
                        "{}: field {} of {} does not link its table: {line}",
                        ir.id,
                        f.id,
                        b.id
                    );
                }
            }
        }
    }
    // DV1 1101h: the code 9696h, not "38550 … 38550".
    let (_, dv1) = shipped_page("dv1");
    assert!(!dv1.contains("38550"), "a code shown as a decimal range");
}

#[test]
fn the_serial_table_gives_each_protocols_character_format_with_its_factory_setting() {
    for (ir, page) in shipped() {
        for table in &ir.code_tables {
            let selector = ir
                .registers
                .iter()
                .find(|r| r.code_table.as_deref() == Some(&table.id));
            for value in table.values.iter().filter(|v| v.line.is_some()) {
                let Some(protocol) = &value.protocol else {
                    continue;
                };
                let Some((data_bits, parity, stop_bits)) = value.line.and_then(|l| l.format())
                else {
                    continue;
                };
                let parity = match parity {
                    vfd_runtime::serial::Parity::None => 'N',
                    vfd_runtime::serial::Parity::Even => 'E',
                    vfd_runtime::serial::Parity::Odd => 'O',
                };
                let format = format!("{data_bits}{parity}{stop_bits}");
                let line = row(&page, &format!("| Character format, `{protocol}` |"));
                let factory = selector.and_then(|s| s.default) == Some(f64::from(value.value));
                let shown = if factory {
                    format!("**{format}**")
                } else {
                    format!("{format} (")
                };
                assert!(line.contains(&shown), "{}: {shown} missing: {line}", ir.id);
            }
        }
    }
    // The DV1's Modbus RTU factory format is 8E1 (07-07 = 4), not the Eaton 8N1.
    let (_, dv1) = shipped_page("dv1");
    assert!(row(&dv1, "| Character format, `modbus` |").contains("**8E1** (07-07 = 4"));
}

#[test]
fn error_codes_are_printed_in_the_manuals_notation() {
    for (ir, page) in shipped() {
        // Every table the drive's protocols name their error replies from.
        let tables: Vec<&vfd_codegen::ir::ErrorCodesIr> = std::iter::once(&ir.error_codes)
            .chain(ir.protocols.iter().filter_map(|p| match &p.error_table {
                vfd_codegen::ir::ErrorTableIr::Protocol(table) => Some(table),
                vfd_codegen::ir::ErrorTableIr::Drive => None,
            }))
            .collect();
        // Example rows: the code as the manual prints it (the DV1's H0C), else in hex.
        for line in page
            .lines()
            .filter(|l| l.contains("| error reply") && l.contains(": error "))
        {
            let code = line
                .split(": error ")
                .nth(1)
                .and_then(|rest| rest.split_whitespace().next())
                .unwrap_or_else(|| panic!("{}: no code in {line}", ir.id));
            let printed = tables
                .iter()
                .flat_map(|t| t.codes.iter())
                .any(|c| !c.printed.is_empty() && c.printed == code);
            let hex = code.ends_with('h')
                && code[..code.len() - 1]
                    .chars()
                    .all(|c| c.is_ascii_hexdigit());
            assert!(
                printed || hex,
                "{}: error code {code:?} neither as printed nor in hex: {line}",
                ir.id
            );
        }
        // A protocol whose error reply carries one byte, and whose table states no
        // notation, shows its codes as two hex digits.
        for protocol in &ir.protocols {
            let file = ir
                .protocol_files
                .iter()
                .find(|f| f.id == protocol.uses)
                .unwrap();
            let Some(layout) = protocol
                .error_reply
                .as_deref()
                .and_then(|name| file.layouts.iter().find(|l| l.name == name))
            else {
                continue;
            };
            let one_byte = layout.parts.iter().any(|p| {
                matches!(p, Part::Field(f) if f.role == Role::ErrorCode && f.format == Format::U8)
            });
            let heading = format!("### Error replies of {} (`{}`)", protocol.name, protocol.id);
            if let (true, Some(start)) = (one_byte, page.find(&heading)) {
                let table = &page[start..];
                let table = &table[..table[4..].find("\n#").map_or(table.len(), |e| e + 4)];
                for line in table.lines().filter(|l| l.starts_with("| 0")) {
                    let code = line.split(' ').nth(1).unwrap();
                    assert!(
                        code.len() == 3 || !code.ends_with('h'),
                        "{}: {code} is not one byte: {line}",
                        ir.id
                    );
                }
            }
        }
    }
    let (_, dv1) = shipped_page("dv1");
    assert!(dv1.contains("error H0C Data range error"));
    assert!(dv1.contains("| H0C | Data range error |"));
    assert!(!dv1.contains("error 12"));
    let (_, fc51) = shipped_page("fc51");
    // The FC 51 prints its Errornum in decimal: 17, not 11h.
    assert!(fc51.contains("| 17 | Cannot change in the current mode |"));
    let (_, vf_as1) = shipped_page("vf-as1");
    assert!(vf_as1.contains("| 01 | Command code error |"));
    // A Modbus exception in an example is named from the Modbus table, not the drive's.
    assert!(vf_as1.contains("error reply `83h`: error 03 Data range error"));
}

#[test]
fn shared_protocol_text_shows_only_what_applies_to_the_drive() {
    for (ir, page) in shipped() {
        for protocol in &ir.protocols {
            let section = protocol_section(&page, &protocol.id);
            // One sentence on the gap between frames, not two that contradict.
            let gaps = section
                .lines()
                .filter(|l| {
                    l.starts_with("- Frames are separated")
                        || l.starts_with("- The silence between frames")
                })
                .count();
            assert!(gaps <= 1, "{} {}: {gaps} gap sentences", ir.id, protocol.id);
            // Bytes before the start: one rule.
            assert!(
                !(section.contains("are skipped") && section.contains("reject the frame")),
                "{} {}: two rules for bytes before the start",
                ir.id,
                protocol.id
            );
            // Group broadcasts only where the station field takes a wildcard.
            let wildcard = request_layouts(&ir, protocol).any(|l| {
                l.parts.iter().any(|p| {
                    matches!(p, Part::Field(f) if f.role == Role::Address
                        && f.broadcast.as_ref().is_some_and(|b| b.wildcard.is_some()))
                })
            });
            assert_eq!(
                section.contains("group of stations"),
                wildcard && protocol.broadcast.is_some(),
                "{} {}: group broadcasts offered wrongly",
                ir.id,
                protocol.id
            );
            // The exception layout lists only the functions the drive has.
            if let Some(error) = &protocol.error_reply {
                let codes: Vec<u32> = protocol
                    .commands
                    .iter()
                    .filter_map(|c| c.error_code)
                    .collect();
                if codes.len() == protocol.commands.len() {
                    let table = &section[section
                        .find(&format!("#### {} / {error}\n", protocol.id))
                        .expect("error layout shown")..];
                    let line = table
                        .lines()
                        .find(|l| l.contains("field (command)"))
                        .expect("command field");
                    let listed = line.split("one of ").nth(1).unwrap_or("");
                    // What follows a `;` is the reply to a function the drive lacks.
                    let listed = listed.split(';').next().unwrap_or("");
                    for code in listed.trim_end_matches(" |").split(", ") {
                        let value = u32::from_str_radix(code.trim_end_matches('h'), 16).unwrap();
                        assert!(
                            codes.contains(&value),
                            "{} {}: {code} offered, which no command of the drive answers with",
                            ir.id,
                            protocol.id
                        );
                    }
                }
            }
        }
        let coils = ir
            .protocols
            .iter()
            .flat_map(|p| &p.commands)
            .any(|c| c.space == vfd_runtime::Space::Coil);
        assert_eq!(page.contains("coil data"), coils, "{}: coil text", ir.id);
        assert!(
            !page.contains("Coil data packs"),
            "{}: generic coil text",
            ir.id
        );
    }
    let (_, dv1) = shipped_page("dv1");
    assert!(
        !dv1.contains("8Fh") && !dv1.contains("85h"),
        "DV1 lists functions it lacks"
    );
    assert!(!dv1.contains("3.5 character times of silence (derived"));
    let (_, vf_as1) = shipped_page("vf-as1");
    let ascii = protocol_section(&vf_as1, "ascii");
    assert!(ascii.contains("reject the frame") && !ascii.contains("ignored"));
}

#[test]
fn unknown_registers_are_printed_in_hex() {
    for (ir, page) in shipped() {
        for (index, _) in page.match_indices(" (none described there)") {
            let word = page[..index].rsplit(' ').next().unwrap();
            assert!(
                word.ends_with('h') && word.len() == 5,
                "{}: unknown register {word:?} not in hex",
                ir.id
            );
        }
    }
    let (_, vf_as1) = shipped_page("vf-as1");
    assert!(!vf_as1.contains("register 4660") && !vf_as1.contains("register 65535"));
    assert!(vf_as1.contains("register 1234h"));
}

#[test]
fn conversion_examples_compute_as_written() {
    for (ir, page) in shipped() {
        for c in &ir.conversions {
            let line = row(&page, &format!("| `{}` |", c.id));
            for (inputs, _, _) in &c.examples {
                for (input, value) in c.inputs.iter().zip(inputs) {
                    let expected = match &input.register {
                        Some(code) if (input.times - 1.0).abs() > f64::EPSILON => format!(
                            "{code} = {value}, so `{}` = {}",
                            input.name,
                            value * input.times
                        ),
                        Some(code) => format!("{code} = {value}"),
                        None => format!("`{}` = {value}", input.name),
                    };
                    assert!(
                        line.contains(&expected),
                        "{}: {expected:?} missing: {line}",
                        ir.id
                    );
                }
            }
        }
    }
    let (_, vf_as1) = shipped_page("vf-as1");
    assert!(vf_as1.contains("FA13 = 1800, F856 = 2, so `poles` = 4 → 6000"));
    assert!(!vf_as1.contains("speed = 1800, poles = 2"));
}

#[test]
fn per_port_registers_are_named_without_a_port() {
    for (ir, page) in shipped() {
        let Some(ports) = &ir.ports else { continue };
        let table = &page[page
            .find("Registers that exist once per port")
            .expect("table")..];
        let table = &table[..table.find("\n\n## ").unwrap_or(table.len())];
        for port in &ports.ports {
            assert!(
                !table.contains(&format!(" ({}) |", port.name)),
                "{}: a row names the port {}",
                ir.id,
                port.name
            );
        }
    }
    let (_, vf_as1) = shipped_page("vf-as1");
    assert!(vf_as1.contains("| Command word 1 | FA00 | FA04 |"));
}

#[test]
fn printed_frames_keep_the_manuals_spacing_and_say_which_layout_read_them() {
    for (ir, page) in shipped() {
        for example in &ir.examples {
            for frame in [&example.request, &example.reply].into_iter().flatten() {
                if let Some(printed) = frame.printed.as_ref().filter(|p| !p.written.is_empty()) {
                    let shown = format!("The manual prints `{}`", printed.written);
                    assert!(page.contains(&shown), "{}: {shown:?} missing", ir.id);
                }
            }
        }
    }
    let (_, yd1000) = shipped_page("yd1000");
    assert!(yd1000.contains("The manual prints `2F 52 00 10 0064 FA`"));
    assert!(yd1000.contains(
        "the printed `R` (52h) is the read command's, so the bytes are read as `read_request`"
    ));
}

#[test]
fn the_dv1_monitor_block_gaps_are_on_the_page() {
    let (_, dv1) = shipped_page("dv1");
    let note = row(&dv1, "- **H1014**");
    for gap in ["1016h", "1018h", "1021h-1026h"] {
        assert!(note.contains(gap), "{gap} not in the 1014h note: {note}");
    }
}

#[test]
fn the_library_s_default_for_bytes_before_the_start_is_marked_assumed() {
    for (ir, page) in shipped() {
        for protocol in &ir.protocols {
            let section = protocol_section(&page, &protocol.id);
            let Some(line) = section.lines().find(|l| l.contains("are skipped")) else {
                continue;
            };
            assert_eq!(
                line.contains("(assumed"),
                !protocol.before_start_stated,
                "{}/{}: {line}",
                ir.id,
                protocol.id
            );
        }
    }
    // The YD1000 manual states it (3, ASCII 方式 (1): 变频器忽略‘(’以前的数据); the DV1's does not.
    let (ir, _) = shipped_page("yd1000");
    assert!(ir.protocols.iter().all(|p| p.before_start_stated));
    let (_, page) = shipped_page("dv1");
    assert!(protocol_section(&page, "eaton")
        .contains("skipped: the frame begins at its start (assumed"));
}

#[test]
fn the_dv1_longest_modbus_frames_are_its_twelve_register_writes() {
    // 10h with 12 registers (l. 427, 439): 33 bytes in RTU, 67 characters in ASCII.
    let (ir, page) = shipped_page("dv1");
    for (id, longest) in [("modbus", 33), ("modbus_ascii", 67)] {
        let protocol = ir.protocols.iter().find(|p| p.id == id).expect(id);
        assert_eq!(protocol.max_frame_len, longest, "{id}");
        assert!(
            protocol_section(&page, id).contains(&format!("- Longest frame: {longest} bytes.")),
            "{id}"
        );
    }
}
