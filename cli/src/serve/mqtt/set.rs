//! `set` messages: each becomes a write request to its bus's worker, or is refused at once;
//! its outcome is published on `…/set/result` before the message is acknowledged, and a
//! message redelivered by the broker is never applied a second time.
//!
//! The guarantee (see `docs/mqtt.md`): a `set` message is applied at most once, and every
//! one gets an answer on its result topic. The service subscribes at QoS 1 with a
//! persistent session and acknowledges a message only once its outcome is queued for
//! the broker. A redelivery (the DUP flag) of a message this process has already answered
//! is acknowledged again without a second write; a redelivery this process has not seen
//! (it was sent before a crash or kill, when the write may or may not have reached the
//! drive) is refused with that reason, never applied blindly.

use super::payload;
use super::topic::{segment, Topics};
use crate::plant::Plant;
use crate::serve::event::{WriteOutcome, WriteRequest, WriteRouter};
use rumqttc::Publish;
use std::collections::{HashMap, VecDeque};

/// Answered messages remembered to recognise their redelivery.
const REMEMBERED: usize = 1024;

/// What to do with a `set` message.
#[derive(Debug)]
pub enum Decision {
    /// Sent to the bus worker; its outcome will come back with this id.
    Sent,
    /// Refused now: publish the outcome on the result topic, then acknowledge.
    Refuse {
        /// `…/set/result`.
        topic: String,
        /// The refusal.
        outcome: Box<WriteOutcome>,
    },
    /// Already answered (a redelivery): acknowledge only.
    AckOnly,
    /// Still being written (a redelivery while in flight): the outcome will acknowledge it.
    Wait,
}

/// A message identified for redelivery: topic, packet id, payload.
type Key = (String, u16, Vec<u8>);

struct Pending {
    publish: Publish,
    topic: String,
    key: Key,
}

/// The `set` messages in flight and recently answered.
pub struct SetLedger {
    topics: Topics,
    /// bus -> drive -> topic segment -> the register's code.
    stations: HashMap<String, HashMap<String, HashMap<String, String>>>,
    writes: WriteRouter,
    next_id: u64,
    in_flight: HashMap<u64, Pending>,
    answered: VecDeque<Key>,
}

impl SetLedger {
    /// A ledger for `plant`'s stations, sending to `writes`.
    pub fn new(topics: Topics, plant: &Plant, writes: WriteRouter) -> SetLedger {
        let mut stations: HashMap<String, HashMap<String, HashMap<String, String>>> =
            HashMap::new();
        for bus in &plant.buses {
            let drives = stations.entry(bus.name.clone()).or_default();
            for station in &bus.stations {
                let codes = drives.entry(station.name.clone()).or_default();
                let registers = station
                    .polls
                    .iter()
                    .map(|p| p.register)
                    .chain(station.writes.iter().map(|w| w.register));
                for register in registers {
                    codes.insert(segment(register.code), register.code.to_string());
                }
            }
        }
        SetLedger {
            topics,
            stations,
            writes,
            next_id: 1,
            in_flight: HashMap::new(),
            answered: VecDeque::new(),
        }
    }

    /// Decides on one incoming message (see the module documentation).
    pub fn receive(&mut self, publish: &Publish) -> Decision {
        let topic = publish.topic.clone();
        let result = format!("{topic}/result");
        let key: Key = (topic.clone(), publish.pkid, publish.payload.to_vec());
        if self.answered.contains(&key) {
            return Decision::AckOnly;
        }
        if let Some(pending) = self.in_flight.values_mut().find(|p| p.key == key) {
            pending.publish = publish.clone();
            return Decision::Wait;
        }
        let Some((bus, drive, code)) = self.topics.parse_set(&topic) else {
            return self.refuse(
                result,
                key,
                ("", "", ""),
                "",
                "not a PREFIX/BUS/DRIVE/CODE/set topic".into(),
            );
        };
        let request = String::from_utf8_lossy(&publish.payload).into_owned();
        let names = (bus, drive, code);
        if publish.retain {
            return self.refuse(result, key, names, &request, "a retained set message is never applied (it would be written again at every start); publish it without the retain flag, and clear the retained one with an empty retained message".into());
        }
        if publish.dup {
            return self.refuse(result, key, names, &request, "this set message was redelivered by the broker after the service restarted; it may already have been written, so it is not applied again: read the register and send the write again if it is still wanted".into());
        }
        let Some(drives) = self.stations.get(bus) else {
            let known: Vec<_> = self.stations.keys().map(String::as_str).collect();
            return self.refuse(
                result,
                key,
                names,
                &request,
                format!(
                    "unknown bus '{bus}' (this service's buses: {})",
                    sorted(known)
                ),
            );
        };
        let Some(codes) = drives.get(drive) else {
            let known: Vec<_> = drives.keys().map(String::as_str).collect();
            return self.refuse(
                result,
                key,
                names,
                &request,
                format!(
                    "unknown drive '{drive}' on bus '{bus}' (its drives: {})",
                    sorted(known)
                ),
            );
        };
        let register = codes.get(code).cloned().unwrap_or_else(|| code.to_string());
        let value = match payload::set_value(&publish.payload) {
            Ok(value) => value,
            Err(reason) => return self.refuse(result, key, names, &request, reason),
        };
        let Some(queue) = self.writes.buses.get(bus) else {
            return self.refuse(
                result,
                key,
                names,
                &request,
                format!("bus '{bus}' takes no writes (its worker is not running)"),
            );
        };
        let id = self.next_id;
        self.next_id += 1;
        let sent = queue.send(WriteRequest {
            bus: bus.to_string(),
            drive: drive.to_string(),
            register,
            value,
            id,
        });
        if sent.is_err() {
            return self.refuse(
                result,
                key,
                names,
                &request,
                format!("bus '{bus}''s worker has stopped; nothing was written"),
            );
        }
        self.in_flight.insert(
            id,
            Pending {
                publish: publish.clone(),
                topic: result,
                key,
            },
        );
        Decision::Sent
    }

    /// The outcome of request `outcome.id` arrived: where to publish it, and the message to
    /// acknowledge after it (`None` for an outcome that is not this input's).
    pub fn outcome(&mut self, outcome: &WriteOutcome) -> (String, Option<Publish>) {
        match self.in_flight.remove(&outcome.id) {
            Some(pending) => {
                self.remember(pending.key);
                (pending.topic, Some(pending.publish))
            }
            None => (
                format!(
                    "{}/set/result",
                    self.topics
                        .state(&outcome.bus, &outcome.drive, &outcome.code)
                ),
                None,
            ),
        }
    }

    fn remember(&mut self, key: Key) {
        if self.answered.len() >= REMEMBERED {
            self.answered.pop_front();
        }
        self.answered.push_back(key);
    }

    fn refuse(
        &mut self,
        topic: String,
        key: Key,
        (bus, drive, code): (&str, &str, &str),
        request: &str,
        reason: String,
    ) -> Decision {
        self.remember(key);
        let id = self.next_id;
        self.next_id += 1;
        let code = self
            .stations
            .get(bus)
            .and_then(|d| d.get(drive))
            .and_then(|c| c.get(code))
            .map_or(code, String::as_str);
        Decision::Refuse {
            topic,
            outcome: Box::new(WriteOutcome {
                bus: bus.to_string(),
                drive: drive.to_string(),
                code: code.to_string(),
                request: request.to_string(),
                id,
                ok: false,
                sent: false,
                value: None,
                unit: String::new(),
                raw: None,
                error: Some(reason),
                error_code: None,
                error_meaning: None,
                time: crate::record::now().0,
            }),
        }
    }
}

fn sorted(mut names: Vec<&str>) -> String {
    names.sort_unstable();
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}
