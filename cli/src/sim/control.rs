//! Controlling a running `vfd sim` from its standard input, one command a line: `unplug N`
//! and `plug N` pull station N off the line and put it back (unplugged, it neither answers
//! nor acts on frames), `status` tells per station the requests received, the replies and
//! the writes. Each command is answered with one line on standard error. The end of the
//! input ends the control, not the sim (only SIGINT or SIGTERM stop it).

use crate::sim::station::SimStation;
use std::io::BufRead;

/// Reads commands from standard input on a thread of its own, for as long as the input
/// lasts (the thread ends at its end; the process does not wait for it).
pub fn spawn(stations: Vec<SimStation>) {
    let spawned = std::thread::Builder::new()
        .name("vfd sim control".into())
        .spawn(move || {
            let stdin = std::io::stdin();
            for line in stdin.lock().lines() {
                let Ok(line) = line else { break };
                if let Some(answer) = command(&stations, &line) {
                    eprintln!("vfd sim: {answer}");
                }
            }
        });
    if let Err(e) = spawned {
        eprintln!("vfd sim: no control from standard input ({e})");
    }
}

/// What `line` asks, carried out on `stations`, and the one line that answers it (`None`
/// for an empty line).
pub fn command(stations: &[SimStation], line: &str) -> Option<String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let known = "commands: unplug N, plug N (N: a station address), status";
    let answer = match words.as_slice() {
        [] => return None,
        ["status"] => stations
            .iter()
            .map(|s| {
                let tally = s.bus.simulator.tally();
                format!(
                    "station {} {}{}: {} received, {} answered, {} writes",
                    s.address,
                    s.drive.id,
                    if s.bus.simulator.lock().unplugged() {
                        " (unplugged)"
                    } else {
                        ""
                    },
                    tally.addressed,
                    tally.answered,
                    tally.writes
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        [verb @ ("unplug" | "plug"), address] => {
            let unplug = *verb == "unplug";
            match address
                .parse::<u8>()
                .ok()
                .and_then(|a| stations.iter().find(|s| s.address == a))
            {
                Some(station) => {
                    station.bus.simulator.set_unplugged(unplug);
                    format!(
                        "station {} ({}) {}",
                        station.address,
                        station.drive.id,
                        if unplug { "unplugged" } else { "plugged in" }
                    )
                }
                None => format!(
                    "no station {address} on this line (stations: {})",
                    stations
                        .iter()
                        .map(|s| s.address.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            }
        }
        _ => format!("unknown command `{}`; {known}", line.trim()),
    };
    Some(answer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::station::parse;

    #[test]
    fn commands_unplug_plug_and_tell_the_status() {
        let stations = [
            parse(&vfd_bus::Catalogue::new(), "fc51@1").unwrap(),
            parse(&vfd_bus::Catalogue::new(), "fc51@2").unwrap(),
        ];
        assert_eq!(command(&stations, "  "), None);
        assert_eq!(
            command(&stations, "unplug 2").unwrap(),
            "station 2 (fc51) unplugged"
        );
        assert!(stations[1].bus.simulator.lock().unplugged());
        let status = command(&stations, "status").unwrap();
        assert!(
            status.contains("station 2 fc51 (unplugged): 0 received, 0 answered, 0 writes"),
            "{status}"
        );
        assert_eq!(
            command(&stations, "plug 2").unwrap(),
            "station 2 (fc51) plugged in"
        );
        assert!(!stations[1].bus.simulator.lock().unplugged());
        assert!(command(&stations, "unplug 9")
            .unwrap()
            .contains("stations: 1, 2"));
        assert!(command(&stations, "reboot")
            .unwrap()
            .contains("unplug N, plug N"));
    }
}
