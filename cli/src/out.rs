//! Printing for people: every line goes through [`say!`], so a reader that stops early
//! (`vfd info yd1000 | head`) ends the tool quietly instead of making it panic, and other
//! write errors become one clear message.

use std::io::Write;

/// Prints one line on standard output (see the module documentation).
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::out::print_line(format_args!($($arg)*))
    };
}
pub(crate) use say;

/// Writes `line` and a newline to standard output and flushes it. A closed pipe ends the
/// program with success, as for other command-line tools; another write error ends it with
/// a message.
pub fn print_line(line: std::fmt::Arguments<'_>) {
    let mut out = std::io::stdout().lock();
    let written = out
        .write_fmt(line)
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush());
    if let Err(error) = written {
        write_failed(&error);
    }
}

/// Writes `text` as it stands (no newline), for redrawing in place.
pub fn print_raw(text: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(error) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        write_failed(&error);
    }
}

fn write_failed(error: &std::io::Error) -> ! {
    if error.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    let _ = writeln!(std::io::stderr(), "vfd: cannot write the output: {error}");
    std::process::exit(1);
}

/// Whether standard output is a terminal (redraw in place, progress bars) rather than a
/// pipe or a file (plain lines).
pub fn is_terminal() -> bool {
    use std::io::IsTerminal;
    std::io::stdout().is_terminal()
}
