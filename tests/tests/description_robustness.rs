//! Broken descriptions never panic the reader: every described drive file and every
//! protocol file is mutated the way hands break YAML (a line deleted, duplicated, indented
//! or dedented, a character replaced by YAML punctuation), and each result is either valid
//! or reported with positions inside the file. The generator is seeded, so a failure
//! reproduces.

use std::path::Path;

use vfd_tests::random::Random;

fn mutate(text: &str, random: &mut Random) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let at = random.below(lines.len());
    match random.below(5) {
        0 => {
            lines.remove(at);
        }
        1 => {
            let copy = lines[at].clone();
            lines.insert(at, copy);
        }
        2 => lines[at].insert_str(0, "  "),
        3 => {
            let trimmed = lines[at].strip_prefix("  ").map(str::to_owned);
            if let Some(trimmed) = trimmed {
                lines[at] = trimmed;
            }
        }
        _ => {
            let chars: Vec<char> = lines[at].chars().collect();
            if !chars.is_empty() {
                let position = random.below(chars.len());
                let punctuation = [':', '{', '}', '[', ']', '-', '\'', '"', '#', ',', ' ', 'x'];
                let mut changed = chars.clone();
                changed[position] = punctuation[random.below(punctuation.len())];
                lines[at] = changed.into_iter().collect();
            }
        }
    }
    lines.join("\n") + "\n"
}

#[test]
fn mutated_descriptions_are_reported_without_panics() {
    let mut random = Random(0x5EED_1234_ABCD_0001);
    let mut reported = 0;
    for drive in ["yd1000", "fc51", "vf-as1", "dv1"] {
        let path = Path::new("../drives").join(format!("{drive}.yaml"));
        let text = std::fs::read_to_string(&path).unwrap();
        for _ in 0..60 {
            let broken = mutate(&text, &mut random);
            let lines = broken.lines().count();
            let result = std::panic::catch_unwind(|| {
                vfd_codegen::compile_text(
                    &path,
                    broken.clone(),
                    Some(Path::new("../drives/protocols")),
                )
            });
            let Ok(result) = result else {
                panic!("the reader panicked on:\n{broken}");
            };
            if let Err(problems) = result {
                reported += 1;
                assert!(!problems.items.is_empty());
                for problem in &problems.items {
                    assert!(
                        problem.file != path || (1..=lines).contains(&problem.position.line),
                        "{problem} points outside the file"
                    );
                    assert!(!problem.message.is_empty());
                }
            }
        }
    }
    assert!(
        reported > 30,
        "most mutations break something; only {reported} did"
    );
}

/// The same for protocol files: each is mutated in a copy of `drives/protocols/` and read
/// through a drive that uses it; problems in the protocol file point inside it.
#[test]
fn mutated_protocol_files_are_reported_without_panics() {
    let mut random = Random(0x5EED_1234_ABCD_0002);
    let dir = std::env::temp_dir().join(format!("vfd-mutated-protocols-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir("../drives/protocols").unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
    }
    let mut reported = 0;
    for (drive, protocol) in [
        ("yd1000", "toshiba-ascii"),
        ("yd1000", "toshiba-binary"),
        ("fc51", "fc-telegram"),
        ("fc51", "modbus-rtu"),
        ("dv1", "eaton-ascii"),
    ] {
        let drive_path = Path::new("../drives").join(format!("{drive}.yaml"));
        let drive_text = std::fs::read_to_string(&drive_path).unwrap();
        let original =
            std::fs::read_to_string(format!("../drives/protocols/{protocol}.yaml")).unwrap();
        let protocol_path = dir.join(format!("{protocol}.yaml"));
        for _ in 0..40 {
            let broken = mutate(&original, &mut random);
            std::fs::write(&protocol_path, &broken).unwrap();
            let lines = broken.lines().count();
            let result = std::panic::catch_unwind(|| {
                vfd_codegen::compile_text(&drive_path, drive_text.clone(), Some(&dir))
            });
            let Ok(result) = result else {
                panic!("the reader panicked on {protocol}:\n{broken}");
            };
            if let Err(problems) = result {
                reported += 1;
                for problem in &problems.items {
                    assert!(
                        problem.file != protocol_path
                            || (1..=lines).contains(&problem.position.line),
                        "{problem} points outside the file"
                    );
                    assert!(!problem.message.is_empty());
                }
            }
        }
        std::fs::write(&protocol_path, &original).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        reported > 30,
        "most mutations break something; only {reported} did"
    );
}
