//! `--format text|json|jsonl|csv`: writes the records of [`vfd_bus::record`] as one JSON
//! document, one JSON object per line (flushed at once, for a pipe reader), or CSV with a
//! header row and RFC 4180 quoting (the `csv` crate quotes and escapes). Text output stays
//! with each command.

use crate::out::print_raw;
use serde::Serialize;

/// How a command prints its results.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Format {
    /// For people (the default).
    #[default]
    Text,
    /// One JSON document: an array of records.
    Json,
    /// One JSON object per line (JSON Lines), each flushed as it is made.
    Jsonl,
    /// A header row, then one row per record (RFC 4180).
    Csv,
}

impl Format {
    /// Whether this is the text format (the command prints for people).
    pub fn is_text(self) -> bool {
        self == Format::Text
    }
}

/// Writes records in one machine-readable format.
pub struct Emitter {
    format: Format,
    /// `json`: the records so far (each an object, fields in their declared order),
    /// written by [`Emitter::finish`].
    collected: Vec<String>,
    /// `csv`: the writer, which writes the header row before the first record.
    csv: csv::Writer<ToStdout>,
}

impl Emitter {
    /// An emitter for `format` (nothing is written for [`Format::Text`]).
    pub fn new(format: Format) -> Emitter {
        Emitter {
            format,
            collected: Vec::new(),
            csv: csv::WriterBuilder::new()
                .terminator(csv::Terminator::CRLF)
                .from_writer(ToStdout),
        }
    }

    /// Writes (or, for `json`, keeps) one record.
    pub fn record<T: Serialize>(&mut self, record: &T) {
        match self.format {
            Format::Text => {}
            Format::Json => self
                .collected
                .push(serde_json::to_string_pretty(record).unwrap_or_default()),
            Format::Jsonl => {
                let mut line = serde_json::to_string(record).unwrap_or_default();
                line.push('\n');
                print_raw(&line);
            }
            Format::Csv => {
                // Each row is flushed at once, for a pipe reader.
                if let Err(error) = self.csv.serialize(record).and_then(|()| {
                    self.csv.flush()?;
                    Ok(())
                }) {
                    eprintln!("vfd: cannot write a CSV row: {error}");
                }
            }
        }
    }

    /// Ends the output: `json` writes its array.
    pub fn finish(&mut self) {
        if self.format == Format::Json {
            let records: Vec<String> = self
                .collected
                .drain(..)
                .map(|record| format!("  {}", record.replace('\n', "\n  ")))
                .collect();
            if records.is_empty() {
                print_raw("[]\n");
            } else {
                print_raw(&format!("[\n{}\n]\n", records.join(",\n")));
            }
        }
    }
}

/// Standard output through [`print_raw`], so a closed pipe ends the tool quietly.
struct ToStdout;

impl std::io::Write for ToStdout {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        print_raw(&String::from_utf8_lossy(bytes));
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
