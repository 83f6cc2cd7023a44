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
//!
//! No message can cost the connection: a message of any size or content ends in a result
//! (a refusal says why: retained, redelivered, longer than any value, not a value, an
//! unknown station, too many writes waiting) or, when no result can be published for it
//! (its result topic would be longer than MQTT allows), is dropped with a log line; either
//! way it is acknowledged. A message longer than any value is refused before it is read,
//! and a result repeats at most the first characters of a request
//! ([`vfd_bus::service::request_text`]). What the ledger keeps of a message is its packet id,
//! its size and a hash of its topic and payload, never the message.

use super::set_value::set_value;
use super::topic::{segment, Topics};
use rumqttc::Publish;
use std::collections::{HashMap, VecDeque};
use std::hash::{Hash, Hasher};
use vfd_bus::plant::Plant;
use vfd_bus::service::event::{Target, Unroutable, WriteOutcome, WriteRequest, WriteRouter};
use vfd_bus::service::request_text::{echo, echo_text, MAX_NAME_BYTES, MAX_VALUE_BYTES};

/// Answered messages remembered to recognise their redelivery.
const REMEMBERED: usize = 1024;
/// Write requests handed to the bus workers and not yet answered, at most; more are
/// refused (a flood of QoS 0 `set` messages, which the broker does not hold back).
pub const MAX_IN_FLIGHT: usize = 256;
/// The longest topic an MQTT packet carries (a two-byte length).
const MAX_TOPIC_BYTES: usize = 65_535;

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
    /// No result can be published for it: log `reason` and acknowledge it.
    Drop {
        /// Why, for the log.
        reason: String,
    },
}

/// A message identified for redelivery: its packet id, its payload's size, and a hash of
/// its topic and payload (a remembered message costs a few bytes, however long it was).
type Key = (u16, usize, u64);

fn key(publish: &Publish) -> Key {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    publish.topic.hash(&mut hasher);
    publish.payload.hash(&mut hasher);
    (publish.pkid, publish.payload.len(), hasher.finish())
}

/// What acknowledging `publish` needs (its QoS and packet id), without its payload.
pub fn ack_of(publish: &Publish) -> Publish {
    let mut ack = Publish::new("", publish.qos, Vec::new());
    ack.pkid = publish.pkid;
    ack
}

/// A register a topic segment names: its code, and where a write to it goes.
struct Code {
    code: String,
    target: Option<Target>,
}

struct Pending {
    /// The message to acknowledge, without its payload.
    ack: Publish,
    topic: String,
    key: Key,
}

/// The `set` messages in flight and recently answered.
pub struct SetLedger {
    topics: Topics,
    /// bus -> drive -> topic segment -> the register's code and where a write to it goes
    /// (resolved once, here).
    stations: HashMap<String, HashMap<String, HashMap<String, Code>>>,
    writes: WriteRouter,
    in_flight: HashMap<u64, Pending>,
    answered: VecDeque<Key>,
}

impl SetLedger {
    /// A ledger for `plant`'s stations, sending to `writes`.
    pub fn new(topics: Topics, plant: &Plant, writes: WriteRouter) -> SetLedger {
        let mut stations: HashMap<String, HashMap<String, HashMap<String, Code>>> = HashMap::new();
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
                    let target = writes
                        .directory()
                        .target(&bus.name, &station.name, register.code);
                    codes.insert(
                        segment(register.code),
                        Code {
                            code: register.code.to_string(),
                            target,
                        },
                    );
                }
            }
        }
        SetLedger {
            topics,
            stations,
            writes,
            in_flight: HashMap::new(),
            answered: VecDeque::new(),
        }
    }

    /// Decides on one incoming message (see the module documentation).
    pub fn receive(&mut self, publish: &Publish) -> Decision {
        let topic = publish.topic.clone();
        let key = key(publish);
        if self.answered.contains(&key) {
            return Decision::AckOnly;
        }
        if let Some(pending) = self.in_flight.values_mut().find(|p| p.key == key) {
            pending.ack = ack_of(publish);
            return Decision::Wait;
        }
        let result = format!("{topic}/result");
        if result.len() > MAX_TOPIC_BYTES {
            self.remember(key);
            return Decision::Drop {
                reason: format!(
                    "its topic is {} bytes: its result topic would be longer than MQTT allows ({MAX_TOPIC_BYTES})",
                    topic.len()
                ),
            };
        }
        let request = echo(&publish.payload);
        let Some((bus, drive, code)) = self.topics.parse_set(&topic) else {
            return self.refuse(
                result,
                key,
                ("", "", ""),
                request,
                "not a PREFIX/BUS/DRIVE/CODE/set topic".into(),
            );
        };
        let names = (bus, drive, code);
        if publish.retain {
            return self.refuse(result, key, names, request, "a retained set message is never applied: it was stored by the broker and sent again because the service subscribed (at its start or after a reconnect); publish writes without the retain flag, and clear the stored one with an empty retained message (mosquitto_pub -r -n -t TOPIC)".into());
        }
        if publish.dup {
            return self.refuse(result, key, names, request, "this set message was redelivered by the broker after the service restarted; it may already have been written, so it is not applied again: read the register and send the write again if it is still wanted".into());
        }
        if publish.payload.len() > MAX_VALUE_BYTES {
            let reason = format!(
                "the set message is {} bytes, more than any register's value ({MAX_VALUE_BYTES}); it was not read",
                publish.payload.len()
            );
            return self.refuse(result, key, names, request, reason);
        }
        let Some(drives) = self.stations.get(bus) else {
            let known: Vec<_> = self.stations.keys().map(String::as_str).collect();
            let reason = format!(
                "unknown bus '{}' (this service's buses: {})",
                echo_text(bus),
                sorted(known)
            );
            return self.refuse(result, key, names, request, reason);
        };
        let Some(codes) = drives.get(drive) else {
            let known: Vec<_> = drives.keys().map(String::as_str).collect();
            let reason = format!(
                "unknown drive '{}' on bus '{bus}' (its drives: {})",
                echo_text(drive),
                sorted(known)
            );
            return self.refuse(result, key, names, request, reason);
        };
        if code.len() > MAX_NAME_BYTES {
            let reason = format!(
                "the register named in the topic is {} bytes long, longer than any register's code, id or name ({MAX_NAME_BYTES})",
                code.len()
            );
            return self.refuse(result, key, names, request, reason);
        }
        // A segment that names none of the station's registers is looked up by the
        // router, and refused by the worker with what it means.
        let (register, target) = match codes.get(code) {
            Some(known) => (known.code.clone(), known.target),
            None => (code.to_string(), None),
        };
        let value = match set_value(&publish.payload, MAX_VALUE_BYTES) {
            Ok(value) => value,
            Err(reason) => return self.refuse(result, key, names, request, reason),
        };
        if self.in_flight.len() >= MAX_IN_FLIGHT {
            let reason = format!("{MAX_IN_FLIGHT} writes are already waiting for their buses; this one was not queued: send it again later");
            return self.refuse(result, key, names, request, reason);
        }
        let id = vfd_bus::service::run_id::next();
        let mut write = WriteRequest::new(bus, drive, register, value, id);
        write.target = target;
        if let Err(not_sent) = self.writes.send(write) {
            let reason = match not_sent.why {
                Unroutable::NoBus(_) => {
                    format!("bus '{bus}' takes no writes (its worker is not running)")
                }
                Unroutable::Stopped => {
                    format!("bus '{bus}''s worker has stopped; nothing was written")
                }
            };
            return self.refuse(result, key, names, request, reason);
        }
        self.in_flight.insert(
            id,
            Pending {
                ack: ack_of(publish),
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
                (pending.topic, Some(pending.ack))
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

    /// The refusal of a message on `topic`'s result topic; the names the topic gave are
    /// repeated cut ([`echo_text`]), the payload as `request` (already cut).
    fn refuse(
        &mut self,
        topic: String,
        key: Key,
        (bus, drive, code): (&str, &str, &str),
        request: String,
        reason: String,
    ) -> Decision {
        self.remember(key);
        let code = self
            .stations
            .get(bus)
            .and_then(|d| d.get(drive))
            .and_then(|c| c.get(code))
            .map_or_else(|| echo_text(code), |known| known.code.clone());
        Decision::Refuse {
            topic,
            outcome: Box::new(WriteOutcome {
                bus: echo_text(bus),
                drive: echo_text(drive),
                code,
                request,
                id: vfd_bus::service::run_id::next(),
                ok: false,
                sent: false,
                value: None,
                unit: String::new(),
                raw: None,
                error: Some(reason),
                error_code: None,
                error_meaning: None,
                time: vfd_bus::record::now().0,
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

#[cfg(test)]
mod tests {
    use super::*;
    use rumqttc::QoS;
    use std::sync::mpsc;

    fn ledger() -> (SetLedger, mpsc::Receiver<WriteRequest>) {
        let plant = super::super::test_plant::plant();
        let (router, mut queues) = WriteRouter::new(&plant);
        let topics = Topics {
            prefix: "vfd".into(),
        };
        (SetLedger::new(topics, &plant, router), queues.remove(0))
    }

    fn set(topic: &str, payload: Vec<u8>, pkid: u16) -> Publish {
        let mut publish = Publish::new(topic, QoS::AtLeastOnce, payload);
        publish.pkid = pkid;
        publish
    }

    fn set_topic() -> String {
        format!("{}/set", super::super::test_plant::state_topic())
    }

    fn refusal(decision: Decision) -> WriteOutcome {
        match decision {
            Decision::Refuse { outcome, .. } => *outcome,
            other => panic!("not refused: {other:?}"),
        }
    }

    #[test]
    fn a_set_longer_than_any_value_is_refused_unread_with_a_short_result() {
        let (mut ledger, rx) = ledger();
        let huge = vec![b'9'; 5 * 1024 * 1024];
        let outcome = refusal(ledger.receive(&set(&set_topic(), huge, 1)));
        let error = outcome.error.clone().unwrap_or_default();
        assert!(error.contains("5242880 bytes"), "{error}");
        assert!(
            outcome.request.ends_with("… (5242880 bytes)"),
            "{}",
            outcome.request
        );
        assert!(super::super::payload::outcome(&outcome).len() < 1024);
        assert!(rx.try_recv().is_err(), "nothing is queued");
        // Its redelivery is recognised (by a hash, not a copy of the payload).
        let again = ledger.receive(&set(&set_topic(), vec![b'9'; 5 * 1024 * 1024], 1));
        assert!(matches!(again, Decision::AckOnly), "{again:?}");
    }

    #[test]
    fn names_too_long_are_refused_and_repeated_cut() {
        let (mut ledger, rx) = ledger();
        let bus = "b".repeat(10_000);
        let outcome =
            refusal(ledger.receive(&set(&format!("vfd/{bus}/pump/X/set"), b"1".to_vec(), 2)));
        assert!(outcome.bus.ends_with("… (10000 bytes)"), "{}", outcome.bus);
        assert!(outcome.error.unwrap_or_default().len() < 300);
        let code = "c".repeat(MAX_NAME_BYTES + 1);
        let outcome = refusal(ledger.receive(&set(
            &format!("vfd/line1/pump/{code}/set"),
            b"1".to_vec(),
            3,
        )));
        assert!(outcome
            .error
            .unwrap_or_default()
            .contains("longer than any register's"));
        assert!(rx.try_recv().is_err(), "nothing is queued");
    }

    #[test]
    fn a_topic_too_long_for_its_result_is_dropped() {
        let (mut ledger, rx) = ledger();
        let topic = format!("vfd/line1/pump/{}/set", "x".repeat(MAX_TOPIC_BYTES - 20));
        let decision = ledger.receive(&set(&topic, b"1".to_vec(), 4));
        assert!(matches!(decision, Decision::Drop { .. }), "{decision:?}");
        assert!(rx.try_recv().is_err());
    }

    #[test]
    fn writes_beyond_the_in_flight_limit_are_refused_until_answered() {
        let (mut ledger, rx) = ledger();
        for pkid in 1..=MAX_IN_FLIGHT as u16 {
            let decision = ledger.receive(&set(&set_topic(), b"1".to_vec(), pkid));
            assert!(matches!(decision, Decision::Sent), "{decision:?}");
        }
        let over = MAX_IN_FLIGHT as u16 + 1;
        let outcome = refusal(ledger.receive(&set(&set_topic(), b"1".to_vec(), over)));
        assert!(outcome
            .error
            .unwrap_or_default()
            .contains("already waiting"));
        let first = rx.recv().unwrap();
        let (_, ack) = ledger.outcome(&WriteOutcome::pending(&first));
        assert_eq!(ack.map(|p| (p.pkid, p.payload.len())), Some((1, 0)));
        let decision = ledger.receive(&set(&set_topic(), b"1".to_vec(), over + 1));
        assert!(matches!(decision, Decision::Sent), "{decision:?}");
    }
}
