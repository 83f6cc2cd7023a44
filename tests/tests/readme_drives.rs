//! The README's table of described drives names every drive file in `drives/`, and no other.

use std::path::Path;

#[test]
fn the_readme_table_names_every_drive_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let readme = std::fs::read_to_string(root.join("README.md")).expect("README.md reads");
    let section = readme
        .split("## The described drives")
        .nth(1)
        .expect("README.md has a section `## The described drives`");
    let section = section.split("\n## ").next().unwrap_or(section);
    let mut listed: Vec<String> = section
        .lines()
        .filter(|line| line.starts_with("| ") && !line.starts_with("| Drive"))
        .filter_map(|line| {
            let first = line.split('|').nth(1)?;
            let id = first.split('`').nth(1)?;
            Some(id.to_owned())
        })
        .collect();
    listed.sort();
    let mut files: Vec<String> = std::fs::read_dir(root.join("drives"))
        .expect("drives/ lists")
        .filter_map(|entry| entry.ok())
        .filter_map(|entry| {
            let name = entry.file_name().into_string().ok()?;
            name.strip_suffix(".yaml").map(str::to_owned)
        })
        .collect();
    files.sort();
    assert_eq!(
        listed, files,
        "the README's table of described drives and the files in drives/ differ"
    );
}
