//! MQTT output and input of `vfd serve`: events published under a prefix (retained states,
//! availability, write outcomes, Home Assistant discovery) and writes taken from `set`
//! topics. The topics, payloads and the write guarantee are described in `docs/mqtt.md`.

mod client;
mod discovery;
mod options;
mod outbox;
mod payload;
mod set;
mod set_value;
mod topic;

#[cfg(test)]
mod broker;
#[cfg(test)]
mod test_plant;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tls_tests;

pub use client::Mqtt;
#[cfg(test)]
use options::parse_url;
pub use options::MqttOptions;
