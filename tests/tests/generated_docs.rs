//! The committed reference pages in `generated-docs/` must equal what the generator makes
//! from `drives/*.yaml` now. Builds never write them: `cargo run -p vfd-cli -- generate`
//! refreshes them, and so does this test under `UPDATE_EXPECT=1`.

use std::path::PathBuf;
use vfd_tests::expectations::{entries, outdated_files, update_requested};

const REFRESH: &str = "cargo run -p vfd-cli -- generate";

#[test]
fn committed_reference_pages_are_current() {
    let generated = vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .display_root("..")
        // As `vfd generate` (cli/src/main.rs) makes them.
        .regenerate_command(REFRESH)
        .crate_path("vfd_drives")
        .manuals_location("shared/seeds")
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"));
    let docs = PathBuf::from("../generated-docs");
    let mut pages: Vec<(PathBuf, String)> = generated
        .drives
        .iter()
        .map(|d| (docs.join(format!("{}.md", d.ir.id)), d.markdown.clone()))
        .collect();
    pages.push((docs.join("README.md"), generated.index.clone()));
    let mut problems: Vec<String> = outdated_files(&pages)
        .iter()
        .map(|page| format!("stale: {}", page.first_difference()))
        .collect();
    for stray in entries(&docs, |path| {
        path.extension().is_some_and(|ext| ext == "md") && !pages.iter().any(|(p, _)| p == path)
    }) {
        if update_requested() {
            std::fs::remove_file(&stray).expect("remove a page no drive makes");
        } else {
            problems.push(format!("no drive makes {} (delete it)", stray.display()));
        }
    }
    assert!(
        problems.is_empty(),
        "generated-docs/ differs from what the drive files give now:\n{}\nRefresh it with `{REFRESH}` (or rerun this test with UPDATE_EXPECT=1) and commit the result.",
        problems.join("\n")
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
