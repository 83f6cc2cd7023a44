//! Without options, generated output names nothing of this repository: no crate, folder or
//! command of ours appears in Rust modules, golden tests or reference pages.

#[test]
fn default_output_names_nothing_of_this_repository() {
    let generated = vfd_codegen::Builder::new()
        .drives_in("../drives")
        .expect("drives/ is readable")
        .golden_tests(true)
        .generate_in_memory()
        .unwrap_or_else(|error| panic!("the drive files do not generate:\n{error}"));
    let mut outputs: Vec<(String, &str)> = vec![
        ("index".to_owned(), generated.index.as_str()),
        ("layouts.rs".to_owned(), generated.layouts.as_str()),
    ];
    for drive in &generated.drives {
        let id = &drive.ir.id;
        outputs.push((format!("{id}.rs"), &drive.rust));
        outputs.push((format!("{id}.md"), &drive.markdown));
        let golden = drive
            .golden_tests
            .as_deref()
            .expect("golden tests were asked for");
        // A drive whose manual's frames could not be read has no golden test to call it.
        let has_examples = !drive.ir.examples.is_empty() || !drive.ir.sequences.is_empty();
        assert!(
            !has_examples || golden.contains("::vfd_runtime::testing::"),
            "{id}: golden tests call vfd_runtime::testing"
        );
        assert!(
            !has_examples || golden.contains(&format!("crate::{}::", drive.ir.module)),
            "{id}: golden tests reach the module through `crate`"
        );
        outputs.push((format!("{id}_golden.rs"), golden));
    }
    let ours = [
        "vfd_drives",
        "vfd-drives",
        "vfd_tests",
        "vfd-cli",
        "shared/seeds",
        "drives/protocols",
        "generated-docs",
        "cargo run",
        "cargo build",
    ];
    let mut found = Vec::new();
    for (name, text) in &outputs {
        for word in ours {
            if let Some(line) = text.lines().find(|line| line.contains(word)) {
                found.push(format!("{name}: `{word}` in: {line}"));
            }
        }
    }
    assert!(
        found.is_empty(),
        "default output names this repository:\n{}",
        found.join("\n")
    );
}
