//! Broken descriptions never panic the reader: every described drive file is mutated the
//! way hands break YAML (a line deleted, duplicated, indented or dedented, a character
//! replaced by YAML punctuation), and each result is either valid or reported with
//! positions inside the file. The generator is seeded, so a failure reproduces.

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
    for drive in ["yd1000", "fc51"] {
        let path = Path::new("../drives").join(format!("{drive}.yaml"));
        let text = std::fs::read_to_string(&path).unwrap();
        for _ in 0..100 {
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
