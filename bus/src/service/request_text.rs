//! The text of a write request as the service takes it and repeats it. A value longer than
//! [`MAX_VALUE_BYTES`] is refused without being read (no value of any register is that
//! long), a register or station name longer than [`MAX_NAME_BYTES`] likewise, and what a
//! result or a log line repeats of a request is cut to [`ECHO_CHARS`] characters with a note
//! of its size, so that a hostile request never makes a large answer.

/// The longest value a write request may carry, in bytes (a JSON wrapping included): the
/// longest bit-field list of a shipped drive is a few hundred.
pub const MAX_VALUE_BYTES: usize = 1024;

/// The longest register, bus or drive name a request may give, in bytes.
pub const MAX_NAME_BYTES: usize = 256;

/// The most characters a result or log line repeats of a request's value or names.
pub const ECHO_CHARS: usize = 64;

/// `bytes` as text to repeat (invalid UTF-8 as U+FFFD): whole when at most
/// [`ECHO_CHARS`] characters, else its first ones and `… (N bytes)`.
pub fn echo(bytes: &[u8]) -> String {
    echo_of(bytes, bytes.len())
}

/// [`echo`] of a text of `size` bytes of which `start` is the beginning (all that was kept
/// of it).
pub fn echo_of(start: &[u8], size: usize) -> String {
    // A prefix long enough for ECHO_CHARS characters of any width, decoded on its own: a
    // long request is never decoded whole.
    let head = &start[..start.len().min(ECHO_CHARS * 4 + 4)];
    let text = String::from_utf8_lossy(head);
    match text.char_indices().nth(ECHO_CHARS) {
        None if head.len() == size => text.into_owned(),
        at => {
            let end = at.map_or(text.len(), |(end, _)| end);
            format!("{}… ({size} bytes)", &text[..end])
        }
    }
}

/// [`echo`] of a text.
pub fn echo_text(text: &str) -> String {
    echo(text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_requests_are_repeated_whole() {
        assert_eq!(echo(b"50 Hz"), "50 Hz");
        assert_eq!(echo(b""), "");
        assert_eq!(echo_text(&"é".repeat(ECHO_CHARS)), "é".repeat(ECHO_CHARS));
    }

    #[test]
    fn long_requests_are_cut_with_their_size() {
        let long = vec![b'7'; 200 * 1024];
        let echoed = echo(&long);
        assert_eq!(
            echoed,
            format!("{}… ({} bytes)", "7".repeat(ECHO_CHARS), 200 * 1024)
        );
        // Several bytes a character, and bytes that are not UTF-8, are cut at a character.
        let wide = "频".repeat(1000);
        let echoed = echo_text(&wide);
        assert!(echoed.starts_with(&"频".repeat(ECHO_CHARS)), "{echoed}");
        assert!(echoed.ends_with("… (3000 bytes)"), "{echoed}");
        let binary: Vec<u8> = (0..=255u8).cycle().take(5000).collect();
        let echoed = echo(&binary);
        assert!(echoed.ends_with("… (5000 bytes)"), "{echoed}");
        assert!(echoed.chars().count() <= ECHO_CHARS + 20, "{echoed}");
    }
}
