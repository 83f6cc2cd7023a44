//! Prose wrapped at a width, for the pages and the generated rustdoc: Markdown paragraphs
//! and list items break between words; tables, headings, code blocks and HTML stay whole
//! (a table row cannot break; a line of Chinese without spaces has nowhere to).

/// The width prose is wrapped at, in characters.
pub const WIDTH: usize = 100;

/// `text` (Markdown) with every prose line longer than `width` broken between words; a
/// list item's continuation lines are indented under its text, so the item stays one.
pub fn wrap_markdown(text: &str, width: usize) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / width);
    let mut in_code = false;
    for line in text.lines() {
        let fence = line.trim_start().starts_with("```");
        if fence {
            in_code = !in_code;
        }
        if in_code || fence || !is_prose(line) || line.chars().count() <= width {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        for piece in wrap_line(line, width) {
            out.push_str(&piece);
            out.push('\n');
        }
    }
    if !text.ends_with('\n') {
        out.pop();
    }
    out
}

/// One long prose line as lines of at most `width` characters where its words allow (a
/// word longer than the width stands alone): the first keeps the line's indentation and
/// list marker, the others are indented under the text.
pub fn wrap_line(line: &str, width: usize) -> Vec<String> {
    let indent = line.len() - line.trim_start().len();
    let marker = list_marker(&line[indent..]);
    let lead = &line[..indent + marker];
    let hanging = " ".repeat(indent + marker);
    let mut lines = Vec::new();
    let mut current = lead.to_owned();
    let mut has_word = false;
    for word in line[indent + marker..].split(' ').filter(|w| !w.is_empty()) {
        let fits = current.chars().count() + 1 + word.chars().count() <= width;
        if has_word && !fits {
            lines.push(std::mem::replace(&mut current, hanging.clone()));
            has_word = false;
        }
        if has_word {
            current.push(' ');
        }
        current.push_str(word);
        has_word = true;
    }
    lines.push(current);
    lines
}

/// `text` (Markdown) with wrapped prose joined again: each paragraph and list item on one
/// line, as before `wrap_markdown`; for tools (and tests) that read the pages line by
/// line.
pub fn unwrap_markdown(text: &str) -> String {
    let mut lines: Vec<String> = Vec::new();
    let mut in_code = false;
    let mut joinable = false;
    for line in text.lines() {
        let fence = line.trim_start().starts_with("```");
        if fence {
            in_code = !in_code;
        }
        let trimmed = line.trim_start();
        let continues = joinable
            && !in_code
            && !fence
            && !trimmed.is_empty()
            && is_prose(line)
            && list_marker(trimmed) == 0
            && !trimmed.starts_with('>');
        match lines.last_mut() {
            Some(last) if continues => {
                last.push(' ');
                last.push_str(trimmed);
            }
            _ => lines.push(line.to_owned()),
        }
        joinable = !in_code && !fence && !trimmed.is_empty() && is_prose(line);
    }
    let mut out = lines.join("\n");
    if text.ends_with('\n') {
        out.push('\n');
    }
    out
}

/// Whether a Markdown line is prose that may break: not a table row, heading, block quote
/// marker line, HTML, or an indented code line.
fn is_prose(line: &str) -> bool {
    let trimmed = line.trim_start();
    !(trimmed.starts_with('|')
        || trimmed.starts_with('#')
        || trimmed.starts_with('<')
        || line.starts_with("    ") && list_marker(trimmed) == 0 && !line.starts_with("     "))
}

/// The length of a list item's marker and the space after it (`- `, `* `, `12. `); 0 when
/// the line is not a list item.
fn list_marker(text: &str) -> usize {
    if text.starts_with("- ") || text.starts_with("* ") {
        return 2;
    }
    let digits = text.bytes().take_while(u8::is_ascii_digit).count();
    if digits > 0 && text[digits..].starts_with(". ") {
        return digits + 2;
    }
    0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_paragraph_breaks_between_words_within_the_width() {
        let text = "word ".repeat(50);
        let wrapped = wrap_markdown(text.trim_end(), 30);
        assert!(wrapped.lines().count() > 5);
        assert!(
            wrapped.lines().all(|l| l.chars().count() <= 30),
            "{wrapped}"
        );
        assert_eq!(
            wrapped.split_whitespace().collect::<Vec<_>>(),
            text.split_whitespace().collect::<Vec<_>>()
        );
    }

    #[test]
    fn a_list_item_continues_under_its_text() {
        let wrapped = wrap_markdown(&format!("- {}", "alpha beta ".repeat(10)), 24);
        let lines: Vec<&str> = wrapped.lines().collect();
        assert!(lines[0].starts_with("- alpha"));
        assert!(lines[1..]
            .iter()
            .all(|l| l.starts_with("  ") && !l.starts_with("   ")));
        let numbered = wrap_markdown(&format!("12. {}", "alpha beta ".repeat(10)), 24);
        let second = numbered.lines().nth(1).unwrap();
        assert!(
            second.starts_with("    ") && !second.starts_with("     "),
            "{numbered}"
        );
    }

    #[test]
    fn tables_headings_code_and_short_lines_stay_whole() {
        let long = "x ".repeat(80);
        for line in [
            format!("| {long} |"),
            format!("## {long}"),
            format!("<td>{long}</td>"),
            "short line".to_owned(),
        ] {
            assert_eq!(wrap_markdown(&line, 40), line);
        }
        let code = format!("```\n{long}\n```\n");
        assert_eq!(wrap_markdown(&code, 40), code);
    }

    #[test]
    fn unwrapping_gives_back_each_paragraph_and_item_on_one_line() {
        let text = format!(
            "# Title\n\n{}\n\n- {}\n- short\n\n| a | b |\n|---|---|\n\n```\ncode\nmore\n```\n",
            "word ".repeat(40).trim_end(),
            "item ".repeat(40).trim_end()
        );
        let wrapped = wrap_markdown(&text, 30);
        assert_ne!(wrapped, text);
        assert_eq!(unwrap_markdown(&wrapped), text);
    }

    #[test]
    fn a_word_longer_than_the_width_stands_alone() {
        let long = "y".repeat(50);
        let wrapped = wrap_markdown(&format!("a {long} b"), 20);
        assert_eq!(wrapped, format!("a\n{long}\nb"));
    }
}
