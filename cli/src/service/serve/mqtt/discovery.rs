//! `--ha-discovery`: a Home Assistant MQTT discovery config for each polled register, so it
//! appears as a sensor with its unit, the station as the device.
//!
//! Each config is retained on `homeassistant/sensor/UNIQUE_ID/config`, where UNIQUE_ID is
//! `vfd_PREFIX_BUS_DRIVE_CODE` with every character other than letters, digits, `_` and
//! `-` as `_`: stable as long as the plant file keeps its names.

use super::topic::Topics;
use serde_json::{json, Value};
use vfd_bus::plant::Plant;

/// Home Assistant's discovery prefix (its default).
pub const DISCOVERY_PREFIX: &str = "homeassistant";

/// `text` with every character other than `[A-Za-z0-9_-]` as `_`.
fn id_part(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Every polled register's config: (topic, retained JSON payload).
pub fn configs(topics: &Topics, plant: &Plant) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for bus in &plant.buses {
        for station in &bus.stations {
            let device_id = id_part(&format!(
                "vfd_{}_{}_{}",
                topics.prefix, bus.name, station.name
            ));
            let drive = station.drive;
            let device = json!({
                "identifiers": [device_id],
                "name": format!("{} ({})", station.name, bus.name),
                "model": drive.model,
                "manufacturer": drive.vendor,
            });
            for poll in &station.polls {
                let register = poll.register;
                let unique_id = format!("{device_id}_{}", id_part(register.code));
                let mut config = json!({
                    "name": format!("{} ({})", register.name, register.code),
                    "unique_id": unique_id,
                    "object_id": unique_id,
                    "state_topic": topics.state(&bus.name, &station.name, register.code),
                    "value_template": "{{ value_json.value }}",
                    "availability": [
                        {"topic": topics.status()},
                        {"topic": topics.available(&bus.name, &station.name)},
                    ],
                    "availability_mode": "all",
                    "payload_available": "online",
                    "payload_not_available": "offline",
                    "json_attributes_topic": topics.state(&bus.name, &station.name, register.code),
                    "device": device,
                });
                let unit = register.unit.symbol();
                if !unit.is_empty() {
                    if let Value::Object(map) = &mut config {
                        map.insert("unit_of_measurement".into(), unit.into());
                        map.insert("state_class".into(), "measurement".into());
                    }
                }
                out.push((
                    format!("{DISCOVERY_PREFIX}/sensor/{unique_id}/config"),
                    serde_json::to_vec(&config).unwrap_or_default(),
                ));
            }
        }
    }
    out
}
