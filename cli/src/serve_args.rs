//! The command line of `vfd serve`: the plant file and `--check`. (The service's outputs,
//! `--jsonl` and `--mqtt`, join these options where the service is built.)

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
}
