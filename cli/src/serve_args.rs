//! The command line of `vfd serve`: the plant file, `--check`, the outputs (`--jsonl`,
//! `--mqtt`) and the inputs (MQTT `set` topics, `--stdin-writes`).

use std::path::PathBuf;

/// `vfd serve PLANT`: poll the plant file's drives and publish what they read.
#[derive(Debug, Clone, clap::Args)]
pub struct ServeArgs {
    /// The plant file: buses, drives, what to poll and what may be written (docs/plant.md;
    /// an annotated example is plants/example.yaml).
    #[arg(value_name = "PLANT")]
    pub plant: PathBuf,
    /// Check the plant file and print what would be polled and allowed, or every problem
    /// at file:line:column (exit status 1); opens no port.
    #[arg(long)]
    pub check: bool,
    /// Print every reading and every change (a station on- or offline, a write, a port)
    /// as one JSON object per line on standard output.
    #[arg(long)]
    pub jsonl: bool,
    /// Take write requests as JSON lines on standard input (`{"bus": "line1", "drive":
    /// "pump1", "register": "FA01", "value": "50 Hz"}`), each checked as an MQTT `set` is;
    /// the outcome is a `written` event.
    #[arg(long)]
    pub stdin_writes: bool,
    /// Print debug records too (registers a drive refused to read, the runtime's retries).
    #[arg(long, short = 'v')]
    pub verbose: bool,
}
