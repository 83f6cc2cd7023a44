//! Tests against a real mosquitto (started per test on a free loopback port), with
//! mosquitto_sub / mosquitto_pub as the peer and a fake producer of events. Built
//! `#[ignore]`d where mosquitto is missing (`cfg(missing_mosquitto)`, see cli/build.rs),
//! never under CI.

use super::broker::Broker;
use super::options::{Credentials, MqttOptions};
use super::test_plant::{plant, state_topic};
use super::Mqtt;
use std::sync::mpsc;
use std::time::Duration;
use vfd_bus::service::event::{
    Availability, Event, Reading, WriteOutcome, WriteRequest, WriteRouter,
};

pub(super) fn options(broker: &Broker, name: &str) -> MqttOptions {
    let mut options =
        MqttOptions::new(&broker.url(), None).unwrap_or_else(|f| panic!("{}", f.message));
    options.client_id = format!("vfd-test-{name}-{}", broker.port);
    options.credentials = None;
    options
}

fn connect(broker: &Broker, name: &str) -> (Mqtt, mpsc::Receiver<WriteRequest>) {
    let (router, mut queues) = WriteRouter::new(&plant());
    let rx = queues.remove(0);
    let mqtt = Mqtt::connect(&options(broker, name), &plant(), router)
        .unwrap_or_else(|f| panic!("{}", f.message));
    (mqtt, rx)
}

fn reading(value: f64) -> Event {
    let register = plant().buses[0].stations[0].polls[0].register;
    Event::Reading(Reading {
        bus: "line1".into(),
        drive: "pump".into(),
        model: "m".into(),
        code: register.code.into(),
        name: register.name.into(),
        name_zh: String::new(),
        value: Some(value),
        unit: "Hz".into(),
        raw: Some((value * 100.0) as u32),
        text: None,
        time: "2026-11-27T00:00:00.000Z".into(),
        epoch_ms: 0,
        tripped: Some(false),
    })
}

fn online() -> Event {
    Event::Availability(Availability {
        bus: "line1".into(),
        drive: "pump".into(),
        online: true,
        reason: None,
        time: String::new(),
    })
}

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"))
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn retained_states_availability_and_status_appear_and_shutdown_marks_offline() {
    let broker = Broker::start("states", "");
    let (mqtt, _rx) = connect(&broker, "states");
    mqtt.publish(&online());
    mqtt.publish(&reading(50.0));
    std::thread::sleep(Duration::from_millis(500));
    let state = json(&broker.first(&state_topic(), 5).expect("a retained state"));
    assert_eq!(state["value"], 50.0);
    assert_eq!(state["unit"], "Hz");
    assert_eq!(state["raw"], 5000);
    assert_eq!(state["tripped"], false);
    assert_eq!(state["time"], "2026-11-27T00:00:00.000Z");
    assert_eq!(
        broker.first("vfd/line1/pump/available", 5).as_deref(),
        Some("online")
    );
    assert_eq!(broker.first("vfd/status", 5).as_deref(), Some("online"));
    mqtt.shutdown();
    assert_eq!(
        broker.first("vfd/line1/pump/available", 5).as_deref(),
        Some("offline")
    );
    assert_eq!(broker.first("vfd/status", 5).as_deref(), Some("offline"));
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn a_killed_service_shows_offline_through_its_last_will() {
    let broker = Broker::start("will", "");
    let (mqtt, _rx) = connect(&broker, "will");
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(broker.first("vfd/status", 5).as_deref(), Some("online"));
    drop(mqtt); // no shutdown: the connection closes without DISCONNECT
    std::thread::sleep(Duration::from_millis(500));
    assert_eq!(broker.first("vfd/status", 5).as_deref(), Some("offline"));
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn a_set_message_becomes_a_write_request_and_its_outcome_is_published() {
    let broker = Broker::start("set", "");
    let (mqtt, rx) = connect(&broker, "set");
    let code = plant().buses[0].stations[0].polls[0].register.code;
    let topic = format!("{}/set", state_topic());
    let results = broker.sub_child(&format!("{topic}/result"), 1, 10);
    broker.publish(&topic, "50 Hz", false);
    let request = rx
        .recv_timeout(Duration::from_secs(5))
        .expect("a write request on line1's queue");
    assert_eq!(
        (
            request.bus.as_str(),
            request.drive.as_str(),
            request.register.as_str(),
            request.value.as_str()
        ),
        ("line1", "pump", code, "50 Hz")
    );
    mqtt.publish(&Event::Written(WriteOutcome {
        bus: "line1".into(),
        drive: "pump".into(),
        code: code.into(),
        request: "50 Hz".into(),
        id: request.id,
        ok: true,
        sent: true,
        value: Some(50.0),
        unit: "Hz".into(),
        raw: Some(5000),
        error: None,
        error_code: None,
        error_meaning: None,
        time: String::new(),
    }));
    let outcome = json(results.finish().first().expect("an outcome on set/result"));
    assert_eq!(outcome["ok"], true);
    assert_eq!(outcome["value"], 50.0);
    // Named with this run's id, so that no result of another run has it.
    assert_eq!(outcome["id"], vfd_bus::service::run_id::name(request.id));
    // A JSON value is taken too.
    broker.publish(&topic, r#"{"value": 42}"#, false);
    assert_eq!(
        rx.recv_timeout(Duration::from_secs(5))
            .expect("a second request")
            .value,
        "42"
    );
    mqtt.shutdown();
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn retained_sets_and_unknown_stations_are_refused_and_nothing_is_queued() {
    let broker = Broker::start("refuse", "");
    let topic = format!("{}/set", state_topic());
    broker.publish(&topic, "50", true); // retained before the service starts
    let results = broker.sub_child(&format!("{topic}/result"), 1, 10);
    let (mqtt, rx) = connect(&broker, "refuse");
    let outcome = json(
        results
            .finish()
            .first()
            .expect("a refusal of the retained set"),
    );
    assert_eq!(
        (outcome["ok"].clone(), outcome["sent"].clone()),
        (false.into(), false.into())
    );
    assert!(
        outcome["error"]
            .as_str()
            .unwrap_or_default()
            .contains("retained"),
        "{outcome}"
    );
    let unknown = broker.sub_child("vfd/line9/pump/X1/set/result", 1, 10);
    broker.publish("vfd/line9/pump/X1/set", "1", false);
    let outcome = json(
        unknown
            .finish()
            .first()
            .expect("a refusal of the unknown bus"),
    );
    assert!(
        outcome["error"]
            .as_str()
            .unwrap_or_default()
            .contains("unknown bus 'line9'"),
        "{outcome}"
    );
    let unknown = broker.sub_child("vfd/line1/fan/X1/set/result", 1, 10);
    broker.publish("vfd/line1/fan/X1/set", "1", false);
    let outcome = json(
        unknown
            .finish()
            .first()
            .expect("a refusal of the unknown drive"),
    );
    assert!(
        outcome["error"]
            .as_str()
            .unwrap_or_default()
            .contains("unknown drive 'fan'"),
        "{outcome}"
    );
    assert!(
        rx.recv_timeout(Duration::from_millis(300)).is_err(),
        "a refused set reached the bus queue"
    );
    mqtt.shutdown();
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn a_live_retained_set_is_applied_once_and_its_stored_copy_refused_at_the_next_start() {
    let broker = Broker::start("live-retained", "");
    let (mqtt, rx) = connect(&broker, "live-retained");
    let topic = format!("{}/set", state_topic());
    // Published with the retain flag while the service is subscribed: the broker forwards
    // it with the flag cleared (MQTT 3.1.1, 3.3.1.3), like any write. Applied.
    broker.publish(&topic, "7", true);
    let request = rx
        .recv_timeout(Duration::from_secs(5))
        .expect("the live retained set is applied");
    assert_eq!(request.value, "7");
    mqtt.publish(&Event::Written(WriteOutcome {
        ok: true,
        sent: true,
        ..WriteOutcome::pending(&request)
    }));
    mqtt.shutdown();
    // The broker stored it. The next start subscribes again and gets it flagged retained:
    // refused, not applied a second time.
    let results = broker.sub_child(&format!("{topic}/result"), 1, 10);
    let (mqtt, rx) = connect(&broker, "live-retained");
    let outcome = json(results.finish().first().expect("the stored copy answered"));
    assert_eq!(
        (outcome["ok"].clone(), outcome["sent"].clone()),
        (false.into(), false.into())
    );
    assert!(
        outcome["error"]
            .as_str()
            .unwrap_or_default()
            .contains("retained set message is never applied"),
        "{outcome}"
    );
    assert!(
        rx.recv_timeout(Duration::from_millis(500)).is_err(),
        "the stored retained set was applied again"
    );
    mqtt.shutdown();
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn after_a_broker_restart_the_states_are_republished_and_sets_work_again() {
    let mut broker = Broker::start("restart", "");
    let (mqtt, rx) = connect(&broker, "restart");
    mqtt.publish(&online());
    mqtt.publish(&reading(12.5));
    std::thread::sleep(Duration::from_millis(500));
    broker.kill();
    std::thread::sleep(Duration::from_millis(500));
    broker.run(); // persistence off: the broker forgot every retained message
    let state = broker
        .first(&state_topic(), 20)
        .expect("the state republished after the restart");
    assert_eq!(json(&state)["value"], 12.5);
    assert_eq!(
        broker.first("vfd/line1/pump/available", 5).as_deref(),
        Some("online")
    );
    assert_eq!(broker.first("vfd/status", 5).as_deref(), Some("online"));
    broker.publish(&format!("{}/set", state_topic()), "7", false);
    assert_eq!(
        rx.recv_timeout(Duration::from_secs(5))
            .expect("resubscribed")
            .value,
        "7"
    );
    mqtt.shutdown();
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn a_password_broker_takes_the_right_credentials_and_names_wrong_ones_without_the_password() {
    let dir = std::env::temp_dir().join(format!("vfd-mqtt-passwd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let passwords = dir.join("passwd");
    let made = std::process::Command::new("mosquitto_passwd")
        .args(["-b", "-c"])
        .arg(&passwords)
        .args(["svc", "s3cret-pass"])
        .status()
        .expect("mosquitto_passwd");
    assert!(made.success());
    let broker = Broker::start(
        "passwd",
        &format!(
            "allow_anonymous false\npassword_file {}\n",
            passwords.display()
        ),
    );
    let plant = plant();
    let mut options = options(&broker, "passwd");
    options.credentials = Some(Credentials {
        username: "svc".into(),
        password: "s3cret-pass".into(),
    });
    let mqtt = Mqtt::connect(&options, &plant, WriteRouter::default())
        .unwrap_or_else(|f| panic!("{}", f.message));
    mqtt.shutdown();
    options.credentials = Some(Credentials {
        username: "svc".into(),
        password: "wrong-hunter2".into(),
    });
    let failure = Mqtt::connect(&options, &plant, WriteRouter::default())
        .err()
        .expect("wrong password refused");
    let text = format!(
        "{} {}",
        failure.message,
        failure.hint.clone().unwrap_or_default()
    );
    assert!(
        text.contains("not authorized") || text.contains("refused the user name or password"),
        "{text}"
    );
    assert!(text.contains("VFD_MQTT_USERNAME"), "{text}");
    assert!(
        !text.contains("wrong-hunter2") && !text.contains("s3cret"),
        "{text}"
    );
    options.credentials = None;
    let failure = Mqtt::connect(&options, &plant, WriteRouter::default())
        .err()
        .expect("anonymous refused");
    assert!(failure
        .hint
        .unwrap_or_default()
        .contains("VFD_MQTT_USERNAME"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn a_broker_that_is_down_is_named_clearly() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let mut options = MqttOptions::new(&format!("mqtt://127.0.0.1:{port}"), None)
        .unwrap_or_else(|f| panic!("{}", f.message));
    options.credentials = None;
    let failure = Mqtt::connect(&options, &plant(), WriteRouter::default())
        .err()
        .expect("no broker");
    assert!(
        failure.message.contains(&format!("127.0.0.1:{port}"))
            && failure.message.contains("connection refused"),
        "{}",
        failure.message
    );
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn home_assistant_discovery_configs_are_retained_with_their_keys() {
    let broker = Broker::start("discovery", "");
    let mut options = options(&broker, "discovery");
    options.ha_discovery = true;
    let mqtt = Mqtt::connect(&options, &plant(), WriteRouter::default())
        .unwrap_or_else(|f| panic!("{}", f.message));
    std::thread::sleep(Duration::from_millis(500));
    let configs = broker.sub("homeassistant/sensor/+/config", 2, 5);
    assert_eq!(configs.len(), 2, "{configs:?}");
    let config = json(&configs[0]);
    for key in [
        "name",
        "unique_id",
        "state_topic",
        "value_template",
        "availability",
        "device",
    ] {
        assert!(config.get(key).is_some(), "no {key} in {config}");
    }
    assert!(config["unique_id"]
        .as_str()
        .unwrap()
        .starts_with("vfd_vfd_line1_pump_"));
    assert_eq!(config["value_template"], "{{ value_json.value }}");
    assert_eq!(config["availability"][0]["topic"], "vfd/status");
    assert_eq!(
        config["availability"][1]["topic"],
        "vfd/line1/pump/available"
    );
    let drive = vfd_bus::Catalogue::new().builtin()[0];
    assert_eq!(config["device"]["manufacturer"], drive.vendor);
    assert_eq!(config["device"]["model"], drive.model);
    mqtt.shutdown();
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn the_documented_acl_file_lets_everyone_read_and_only_the_operator_write_set_topics() {
    let acl = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/mqtt-acl.conf");
    assert!(acl.exists(), "{} is missing", acl.display());
    let dir = std::env::temp_dir().join(format!("vfd-mqtt-acl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let passwords = dir.join("passwd");
    // `reader` is a user of the password file the ACL does not name.
    for (create, user, password) in [
        (true, "vfd-serve", "svc-pw"),
        (false, "operator", "op-pw"),
        (false, "reader", "rd-pw"),
    ] {
        let mut command = std::process::Command::new("mosquitto_passwd");
        command.arg("-b");
        if create {
            command.arg("-c");
        }
        assert!(command
            .arg(&passwords)
            .args([user, password])
            .status()
            .expect("mosquitto_passwd")
            .success());
    }
    let broker = Broker::start(
        "acl",
        &format!(
            "allow_anonymous true\npassword_file {}\nacl_file {}\n",
            passwords.display(),
            acl.display()
        ),
    );
    let (router, mut queues) = WriteRouter::new(&plant());
    let rx = queues.remove(0);
    let mut options = options(&broker, "acl");
    options.credentials = Some(Credentials {
        username: "vfd-serve".into(),
        password: "svc-pw".into(),
    });
    let mqtt =
        Mqtt::connect(&options, &plant(), router).unwrap_or_else(|f| panic!("{}", f.message));
    mqtt.publish(&reading(1.0));
    // Everyone reads the states: anonymous clients, the operator, and a named user the
    // ACL file does not mention.
    assert!(
        broker.first(&state_topic(), 5).is_some(),
        "an anonymous reader got no state"
    );
    for user in [("reader", "rd-pw"), ("operator", "op-pw")] {
        assert!(
            broker.first_as(user, &state_topic(), 5).is_some(),
            "{} got no state",
            user.0
        );
    }
    let topic = format!("{}/set", state_topic());
    // Neither an anonymous client nor the reader may write a set topic: the broker drops
    // the message.
    broker.publish(&topic, "1", false);
    broker.publish_as(Some(("reader", "rd-pw")), &topic, "3", false);
    assert!(
        rx.recv_timeout(Duration::from_millis(700)).is_err(),
        "an anonymous or reader's set got through the ACL"
    );
    // The operator may.
    broker.publish_as(Some(("operator", "op-pw")), &topic, "2", false);
    assert_eq!(
        rx.recv_timeout(Duration::from_secs(5))
            .expect("the operator's set")
            .value,
        "2"
    );
    mqtt.shutdown();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn a_set_redelivered_after_a_crash_mid_write_is_answered_never_applied_again() {
    let broker = Broker::start("redeliver", "");
    let (mqtt, rx) = connect(&broker, "redeliver");
    let topic = format!("{}/set", state_topic());
    broker.publish(&topic, "50", false);
    assert_eq!(
        rx.recv_timeout(Duration::from_secs(5))
            .expect("the first delivery")
            .value,
        "50"
    );
    // Killed before the outcome: the message is not acknowledged, the session is kept.
    drop(mqtt);
    let results = broker.sub_child(&format!("{topic}/result"), 1, 10);
    let (mqtt, rx) = connect(&broker, "redeliver"); // the same client id
    let outcome = json(results.finish().first().expect("the redelivery answered"));
    assert_eq!(
        (outcome["ok"].clone(), outcome["sent"].clone()),
        (false.into(), false.into())
    );
    assert!(
        outcome["error"]
            .as_str()
            .unwrap_or_default()
            .contains("redelivered"),
        "{outcome}"
    );
    assert!(
        rx.recv_timeout(Duration::from_millis(500)).is_err(),
        "the redelivered set was applied again"
    );
    mqtt.shutdown();
}

#[test]
#[cfg_attr(
    missing_mosquitto,
    ignore = "mosquitto is not installed (apt-get install mosquitto mosquitto-clients)"
)]
fn shutdown_with_the_broker_gone_ends_in_bounded_time() {
    let mut broker = Broker::start("gone", "");
    let (mqtt, _rx) = connect(&broker, "gone");
    broker.kill();
    for value in 0..200 {
        mqtt.publish(&reading(f64::from(value)));
        mqtt.publish(&online());
    }
    let start = std::time::Instant::now();
    mqtt.shutdown();
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "shutdown took {:?}",
        start.elapsed()
    );
}
