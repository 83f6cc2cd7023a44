//! The one-bus plant the MQTT tests publish from (one station polling two registers of
//! the first built-in drive), shared by the broker tests and the set ledger's unit tests.

use std::time::Duration;
use vfd_bus::plant::model::Poll;
use vfd_bus::plant::{Bus, Plant, Station};

/// One bus `line1` with one station `pump` polling the first two registers of the first
/// built-in drive.
pub(super) fn plant() -> Plant {
    let drive = vfd_bus::Catalogue::new().builtin()[0];
    let polls = drive
        .registers
        .iter()
        .take(2)
        .map(|&register| Poll {
            register,
            every: Duration::from_secs(1),
        })
        .collect();
    Plant {
        path: "test.yaml".into(),
        warnings: vfd_codegen::Diagnostics::default(),
        buses: vec![Bus {
            name: "line1".into(),
            port: "/dev/null".into(),
            settings: vfd_runtime::serial::SerialSettings {
                baud: 9600,
                data_bits: 8,
                parity: vfd_runtime::serial::Parity::None,
                stop_bits: 1,
            },
            timeout: None,
            min_gap: None,
            host_latency: None,
            retries: 0,
            offline_after: 3,
            backoff_first: Duration::from_secs(1),
            backoff_cap: Duration::from_secs(60),
            stations: vec![Station {
                name: "pump".into(),
                drive,
                drive_name: drive.id.into(),
                protocol: drive.protocols[0],
                address: Some(1),
                port: None,
                polls,
                writes: vec![],
            }],
        }],
    }
}

pub(super) fn state_topic() -> String {
    format!(
        "vfd/line1/pump/{}",
        super::topic::segment(plant().buses[0].stations[0].polls[0].register.code)
    )
}
