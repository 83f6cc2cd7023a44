//! The committed reference pages in `generated-docs/` must equal what the generator makes
//! from `drives/*.yaml` now.

#[test]
fn committed_reference_pages_are_current() {
    let generated = vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .display_root("..")
        // As `vfd generate` (cli/src/main.rs) makes them.
        .regenerate_command("cargo run -p vfd-cli -- generate")
        .crate_path("vfd_drives")
        .manuals_location("shared/seeds")
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"));
    let mut stale = Vec::new();
    let mut pages: Vec<(String, &str)> = generated
        .drives
        .iter()
        .map(|d| (format!("{}.md", d.ir.id), d.markdown.as_str()))
        .collect();
    pages.push(("README.md".to_owned(), generated.index.as_str()));
    for (name, fresh) in pages {
        let committed =
            std::fs::read_to_string(format!("../generated-docs/{name}")).unwrap_or_default();
        if committed != fresh {
            stale.push(format!("generated-docs/{name}"));
        }
    }
    assert!(
        stale.is_empty(),
        "stale reference pages: {}. Refresh them with `cargo run -p vfd-cli -- generate` and commit the result.",
        stale.join(", ")
    );
}

#[test]
fn every_drive_has_a_page_and_an_index_entry() {
    let index = std::fs::read_to_string("../generated-docs/README.md")
        .expect("generated-docs/README.md exists");
    for drive in vfd_drives::ALL_DRIVES {
        let page = std::fs::read_to_string(format!("../generated-docs/{}.md", drive.id))
            .expect("the drive has a page");
        assert!(
            index.contains(&format!("({}.md)", drive.id)),
            "{} missing from the index",
            drive.id
        );
        for register in drive.registers {
            assert!(
                page.contains(&format!("| {} |", register.code)),
                "register {} missing from {}.md",
                register.code,
                drive.id
            );
            assert!(
                page.contains(register.name_zh),
                "Chinese name of {} missing",
                register.code
            );
        }
    }
}
