//! Write request ids unique across restarts: every request of this process gets the next
//! number of one counter (whichever input it came from), and a result names it as
//! `RUN-N`, where `RUN` is this run's id, the time the service started (milliseconds since
//! 1970-01-01 UTC) and its process id (`1795740091404-4242-3`). A restarted service starts
//! its count again at 1 under a new run id, so a client that keeps the ids it has seen
//! (to drop a result QoS 1 delivered twice) never takes a new result for an old one.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::OnceLock;

static RUN: OnceLock<String> = OnceLock::new();
static NEXT: AtomicU64 = AtomicU64::new(1);

/// This run's id: `START_MS-PID`, fixed at its first use.
pub fn run() -> &'static str {
    RUN.get_or_init(|| {
        let started = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_millis());
        format!("{started}-{}", std::process::id())
    })
}

/// The next request number of this run (from 1).
pub fn next() -> u64 {
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// A request number as results name it: `RUN-N`.
pub fn name(number: u64) -> String {
    format!("{}-{number}", run())
}

/// Serializes a request number as [`name`] does (serde's `serialize_with`).
pub fn serialize<S: serde::Serializer>(number: &u64, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_str(&name(*number))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_carry_the_run_and_a_number_that_only_grows() {
        let (a, b) = (next(), next());
        assert!(b > a);
        let name = name(b);
        let (run_part, number) = name.rsplit_once('-').unwrap();
        assert_eq!(run_part, run());
        assert_eq!(number, b.to_string());
        let (started, pid) = run().split_once('-').unwrap();
        assert!(started.parse::<u128>().unwrap() > 1_700_000_000_000);
        assert_eq!(pid, std::process::id().to_string());
    }
}
