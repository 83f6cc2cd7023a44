//! `vfd demo --plant`: the service against the built-in virtual plant, no hardware needed.
//! Two virtual buses on pseudo-terminals ([`crate::sim::plant`]) with five stations of three
//! drive models are polled by `vfd serve`'s own workers: with `--mqtt URL` the readings go
//! to that broker, else they are printed as JSON lines. Typed on standard input while it
//! runs: `unplug BUS DRIVE` / `plug BUS DRIVE` pull a station's plug and put it back, and
//! `write BUS DRIVE REGISTER VALUE` asks for a write as an MQTT `set` does.

use crate::service::serve::{self, ServiceCore};
use crate::service::serve_args::ServeArgs;
use crate::sim::plant::VirtualPlant;
use crate::Failure;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use vfd_bus::service::event::{NotSent, Unroutable, WriteRequest, WriteRouter};

/// Runs the plant demo until Ctrl-C, or for `seconds`.
pub fn run(
    catalogue: &vfd_bus::Catalogue,
    mqtt: Option<&str>,
    seconds: Option<u64>,
) -> Result<(), Failure> {
    let virtual_plant = crate::sim::plant::start(catalogue)?;
    let path = PathBuf::from("demo-plant.yaml");
    let plant = vfd_bus::plant::load_str(&virtual_plant.plant_file, &path, catalogue).map_err(
        |problems| Failure::new(format!("the built-in plant file is refused:\n{problems}")),
    )?;
    let args = ServeArgs {
        plant: path,
        check: false,
        jsonl: mqtt.is_none(),
        stdin_writes: false,
        verbose: false,
        mqtt: mqtt.map(str::to_owned),
        mqtt_prefix: "vfd".to_owned(),
        mqtt_client_id: Some("vfd-demo-plant".to_owned()),
        mqtt_password_file: None,
        mqtt_ca_file: None,
        ha_discovery: false,
    };
    introduce(&virtual_plant, mqtt);
    serve::logger::start(false);
    let stop = crate::stop_flag::stop_flag()?;
    if let Some(seconds) = seconds {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_secs(seconds));
            stop.store(true, Ordering::SeqCst);
        });
    }
    let (core, events) = ServiceCore::new(&plant);
    let outputs = serve::outputs(&args, &plant, &core)?;
    let controls = Controls {
        plant: virtual_plant,
        router: core.writes(),
        next_id: 1,
    };
    let plant_handle = Arc::new(std::sync::Mutex::new(controls));
    spawn_controls(Arc::clone(&plant_handle), Arc::clone(&stop));
    let result = serve::serve(core, events, outputs, false, stop);
    // The controls' thread may still hold its handle (waiting for a line): the plant's
    // servers stop when the last handle goes.
    if let Ok(controls) = Arc::try_unwrap(plant_handle) {
        let controls = controls.into_inner().unwrap_or_else(|p| p.into_inner());
        controls.plant.stop()?;
    }
    result
}

/// What the demo says first, on standard error (standard output is the JSON lines).
fn introduce(plant: &VirtualPlant, mqtt: Option<&str>) {
    let mut out = std::io::stderr().lock();
    let _ = writeln!(
        out,
        "vfd demo --plant: a virtual plant of {} buses, {} stations:",
        plant.buses.len(),
        plant.stations.len()
    );
    for bus in &plant.buses {
        let stations: Vec<String> = plant
            .stations
            .iter()
            .filter(|s| s.bus == bus.name)
            .map(|s| format!("{} ({} at {})", s.name, s.drive, s.address))
            .collect();
        let _ = writeln!(
            out,
            "  {} on {}, {} baud: {}",
            bus.name,
            bus.device,
            bus.settings.baud,
            stations.join(", ")
        );
    }
    let _ = writeln!(out, "polled by vfd serve with this plant file:\n");
    for line in plant.plant_file.lines() {
        let _ = writeln!(out, "    {line}");
    }
    let _ = writeln!(out);
    match mqtt {
        Some(url) => {
            let _ = writeln!(out, "publishing to {url} under vfd/; in another terminal:");
            let _ = writeln!(out, "  mosquitto_sub -h HOST -p PORT -t 'vfd/#' -v");
            let _ = writeln!(
                out,
                "  mosquitto_pub -h HOST -p PORT -t vfd/line1/fan1/FA01/set -m '50 Hz'"
            );
            let _ = writeln!(
                out,
                "  mosquitto_sub -h HOST -p PORT -t 'vfd/+/+/+/set/result' -v"
            );
        }
        None => {
            let _ = writeln!(out, "printing every reading and change as JSON lines (--mqtt URL publishes to a broker instead)");
        }
    }
    let _ = writeln!(
        out,
        "type `write line1 fan1 FA01 50Hz`, `unplug line1 fan1` or `plug line1 fan1`; Ctrl-C stops\n"
    );
}

/// The running plant and the service's write queues, for the typed controls.
struct Controls {
    plant: VirtualPlant,
    router: WriteRouter,
    next_id: u64,
}

impl Controls {
    /// Carries out one typed line; what to say back.
    fn command(&mut self, line: &str) -> Option<String> {
        let words: Vec<&str> = line.split_whitespace().collect();
        let (verb, rest) = words.split_first()?;
        Some(match (*verb, rest) {
            ("unplug" | "plug", [bus, drive]) => match self.plant.station(bus, drive) {
                Some(station) => {
                    station.simulator.set_unplugged(*verb == "unplug");
                    format!(
                        "{bus}/{drive} {}",
                        if *verb == "unplug" {
                            "unplugged"
                        } else {
                            "plugged in again"
                        }
                    )
                }
                None => format!("there is no station {drive} on {bus}"),
            },
            ("write", [bus, drive, register, value @ ..]) if !value.is_empty() => {
                let id = self.next_id;
                self.next_id += 1;
                let request = WriteRequest::new(*bus, *drive, *register, value.join(" "), id);
                match self.router.send(request) {
                    Ok(()) => format!("write {id} asked; its outcome is a `written` event"),
                    Err(NotSent {
                        why: Unroutable::NoBus(_),
                        ..
                    }) => format!("there is no bus {bus}"),
                    Err(_) => format!("bus {bus} takes no more writes: the service is stopping"),
                }
            }
            _ => "type `write BUS DRIVE REGISTER VALUE`, `unplug BUS DRIVE` or `plug BUS DRIVE`"
                .to_owned(),
        })
    }
}

/// Reads the typed controls on a thread of its own until standard input ends or the demo
/// stops.
fn spawn_controls(controls: Arc<std::sync::Mutex<Controls>>, stop: Arc<AtomicBool>) {
    let _ = std::thread::Builder::new()
        .name("demo controls".to_owned())
        .spawn(move || {
            for line in std::io::stdin().lock().lines() {
                let Ok(line) = line else { break };
                if stop.load(Ordering::SeqCst) {
                    break;
                }
                let answer = controls
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .command(line.trim());
                if let Some(answer) = answer {
                    let _ = writeln!(std::io::stderr(), "vfd demo: {answer}");
                }
            }
        });
}
