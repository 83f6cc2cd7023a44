//! `vfd serve PLANT`: the unattended service. The library's service core
//! ([`vfd_bus::service`]) runs one worker thread per bus; its events go to the outputs
//! ([`output`]): JSON lines ([`jsonl`]) and an MQTT broker ([`mqtt`]), which also takes
//! `set` requests, as standard input does with `--stdin-writes` ([`stdin`]). SIGINT or
//! SIGTERM stop it: every station is reported offline, the outputs finish.

mod jsonl;
pub mod logger;
pub mod mqtt;
mod mqtt_output;
pub mod output;
mod stdin;

use crate::service::serve_args::ServeArgs;
use crate::Failure;
use output::Output;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;
use vfd_bus::plant::Plant;
use vfd_bus::service::event::Event;
pub use vfd_bus::service::ServiceCore;

/// The `log` target of the service's own records.
pub use vfd_bus::service::LOG_TARGET;

/// Runs the service `core` with `outputs` taking its `events` until SIGINT/SIGTERM (or
/// `stop`).
pub fn serve(
    core: ServiceCore,
    events: Receiver<Event>,
    outputs: Vec<Box<dyn Output>>,
    stdin_writes: bool,
    stop: Arc<AtomicBool>,
) -> Result<(), Failure> {
    if stdin_writes {
        stdin::spawn(core.writes(), core.reporter())
            .map_err(|e| Failure::new(format!("cannot start reading standard input: {e}")))?;
    }
    let done = Arc::new(AtomicBool::new(false));
    let outputs = output::spawn(events, outputs, stop.clone(), done.clone())
        .map_err(|e| Failure::new(format!("cannot start the outputs' thread: {e}")))?;
    let running = core
        .start(stop)
        .map_err(|error| Failure::new(error.to_string()))?;
    running.join();
    done.store(true, Ordering::SeqCst);
    let failed = outputs.join().ok().flatten();
    match failed {
        // The reader of standard output went away: the end it asked for.
        Some(why) if why.contains("Broken pipe") => Ok(()),
        Some(why) => Err(Failure::new(format!("an output failed: {why}"))),
        None => Ok(()),
    }
}

/// The outputs `args` choose: JSON lines, an MQTT client connected to its broker (which
/// takes the `set` topics into `parts`' queues), or both.
pub fn outputs(
    args: &ServeArgs,
    plant: &Plant,
    core: &ServiceCore,
) -> Result<Vec<Box<dyn Output>>, Failure> {
    let mut outputs: Vec<Box<dyn Output>> = Vec::new();
    if args.jsonl {
        outputs.push(Box::<jsonl::JsonLines>::default());
    }
    if let Some(url) = args.mqtt.as_deref() {
        let mut options = mqtt::MqttOptions::new(url, args.mqtt_password_file.as_deref())?
            .with_prefix(&args.mqtt_prefix)?;
        if let Some(id) = &args.mqtt_client_id {
            options.client_id = id.clone();
        }
        options.ca_file = args.mqtt_ca_file.clone();
        options.ha_discovery = args.ha_discovery;
        let client = mqtt::Mqtt::connect(&options, plant, core.writes())?;
        log::info!(
            target: LOG_TARGET,
            "publishing to {} under {}/",
            options.url,
            options.prefix
        );
        outputs.push(Box::new(mqtt_output::MqttOutput(client)));
    }
    Ok(outputs)
}

/// `vfd serve`.
pub fn run(catalogue: &vfd_bus::Catalogue, args: &ServeArgs) -> Result<(), Failure> {
    let plant = crate::service::plant_check::load_for_service(catalogue, &args.plant)?;
    if !args.jsonl && args.mqtt.is_none() {
        return Err(Failure::new(
            "say where the readings go: --jsonl (JSON lines on standard output), --mqtt URL, or both",
        )
        .hint("e.g. vfd serve PLANT --mqtt mqtt://127.0.0.1:1883"));
    }
    logger::start(args.verbose);
    let stop = crate::stop_flag::stop_flag()?;
    let (core, events) = ServiceCore::new(&plant);
    let outputs = outputs(args, &plant, &core)?;
    log::info!(
        target: LOG_TARGET,
        "serving {} bus(es), {} station(s) from {} (run {}: write results are numbered {}-N)",
        plant.buses.len(),
        plant.buses.iter().map(|b| b.stations.len()).sum::<usize>(),
        plant.path.display(),
        vfd_bus::service::run_id::run(),
        vfd_bus::service::run_id::run()
    );
    let result = serve(core, events, outputs, args.stdin_writes, stop);
    log::info!(target: LOG_TARGET, "stopped");
    result
}
