//! The broker connection: [`Mqtt::connect`] waits (bounded) for the broker to accept,
//! [`Mqtt::publish`] queues an event without waiting, one thread sends the queue and one
//! drives the connection (reconnecting with a doubling back-off, logged once per outage,
//! then resubscribing and republishing every retained state), and [`Mqtt::shutdown`]
//! marks everything offline and disconnects.

use super::discovery;
use super::options::{tls_config, MqttOptions};
use super::outbox::{Item, Kind, Outbox, READING_CAP};
use super::payload;
use super::set::{ack_of, Decision, SetLedger};
use super::topic::Topics;
use crate::Failure;
use rumqttc::{
    Client, ConnectReturnCode, ConnectionError, Event as MqttEvent, LastWill, Packet, QoS,
    TlsConfiguration, Transport,
};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use vfd_bus::plant::Plant;
use vfd_bus::service::event::{Event, WriteRouter};
use vfd_bus::service::request_text::echo_text;

/// The longest wait for the broker's first answer.
const CONNECT_WAIT: Duration = Duration::from_secs(10);
/// The first wait before a reconnect; doubled after each failed try.
const BACKOFF_FIRST: Duration = Duration::from_millis(250);
/// The longest wait between reconnect tries.
const BACKOFF_CAP: Duration = Duration::from_secs(15);
/// A topic unsubscribed from only to wake the connection thread.
const WAKE_TOPIC: &str = "vfd-serve/wake";
/// The longest [`Mqtt::shutdown`] waits for the last messages to go out.
const SHUTDOWN_WAIT: Duration = Duration::from_secs(3);
/// The largest packet MQTT 3.1.1 can carry (its remaining length, 256 MiB - 1), taken in
/// both directions. Anything smaller would let one large message the broker forwards end
/// the connection, and the broker would send it again after every reconnect (the session
/// is persistent): a loop that takes the service off the broker. Each incoming packet is
/// read whole before it is looked at, so a large `set` costs its size in memory until it
/// is refused; docs/mqtt.md shows the broker setting that bounds it.
const MAX_PACKET: usize = 268_435_455;

/// A connected MQTT output and `set` input.
pub struct Mqtt {
    client: Client,
    outbox: Arc<Outbox>,
    ledger: Arc<Mutex<SetLedger>>,
    topics: Topics,
    stations: Vec<(String, String)>,
    stop: Arc<AtomicBool>,
    abort: Arc<AtomicBool>,
    sender: Option<JoinHandle<()>>,
    connection: Option<JoinHandle<()>>,
}

impl Mqtt {
    /// Connects to the broker and waits (at most 10 s) for it to accept and (at most 10 s
    /// more) to confirm the `set` subscription; publishes the service `online`, every station `offline` until its first answer, the discovery
    /// configs (with `ha_discovery`), and subscribes to the `set` topics.
    pub fn connect(
        options: &MqttOptions,
        plant: &Plant,
        writes: WriteRouter,
    ) -> Result<Mqtt, Failure> {
        let topics = Topics {
            prefix: options.prefix.clone(),
        };
        let url = &options.url;
        let mut mqtt = rumqttc::MqttOptions::new(&options.client_id, &url.host, url.port);
        mqtt.set_keep_alive(Duration::from_secs(15))
            .set_clean_session(false)
            .set_manual_acks(true)
            .set_max_packet_size(MAX_PACKET, MAX_PACKET)
            .set_last_will(LastWill::new(
                topics.status(),
                "offline",
                QoS::AtLeastOnce,
                true,
            ));
        if let Some(credentials) = &options.credentials {
            mqtt.set_credentials(&credentials.username, &credentials.password);
        }
        if url.tls {
            let config = tls_config(options.ca_file.as_deref())?;
            mqtt.set_transport(Transport::tls_with_config(TlsConfiguration::Rustls(config)));
        }
        let (client, mut connection) = Client::new(mqtt, 64);
        // Small messages out at once (no Nagle delay behind an unacknowledged one): a
        // result or a state waits for nothing.
        let mut network = connection.eventloop.network_options();
        network.set_tcp_nodelay(true);
        connection.eventloop.set_network_options(network);
        let outbox = Arc::new(Outbox::new(READING_CAP));
        let ledger = Arc::new(Mutex::new(SetLedger::new(topics.clone(), plant, writes)));
        let stop = Arc::new(AtomicBool::new(false));
        let abort = Arc::new(AtomicBool::new(false));
        let (first_tx, first_rx) = mpsc::channel::<Result<(), ConnectionError>>();
        let (subscribed_tx, subscribed_rx) = mpsc::channel::<()>();
        let conn_thread = {
            let outbox = Arc::clone(&outbox);
            let ledger = Arc::clone(&ledger);
            let stop = Arc::clone(&stop);
            let abort = Arc::clone(&abort);
            let url = url.to_string();
            std::thread::Builder::new()
                .name("mqtt-connection".into())
                .spawn(move || {
                    let mut first = Some(first_tx);
                    let mut subscribed = Some(subscribed_tx);
                    let mut outage: Option<Instant> = None;
                    let mut backoff = vfd_bus::BackOff::new(BACKOFF_FIRST, BACKOFF_CAP);
                    for event in connection.iter() {
                        match event {
                            Ok(MqttEvent::Incoming(Packet::ConnAck(_))) => {
                                if let Some(tx) = first.take() {
                                    let _ = tx.send(Ok(()));
                                } else if let Some(since) = outage.take() {
                                    log::info!("MQTT: reconnected to {url} after {:.1} s; republishing the states", since.elapsed().as_secs_f64());
                                }
                                backoff.reset();
                                outbox.resync();
                            }
                            Ok(MqttEvent::Incoming(Packet::Publish(publish))) => {
                                let decision = ledger.lock().unwrap_or_else(|e| e.into_inner()).receive(&publish);
                                let ack = Item::Ack(Box::new(ack_of(&publish)));
                                match decision {
                                    Decision::Sent | Decision::Wait => {}
                                    Decision::AckOnly => outbox.push(ack),
                                    Decision::Refuse { topic, outcome } => {
                                        log::warn!("MQTT: refused {}: {}", echo_text(&publish.topic), outcome.error.as_deref().unwrap_or(""));
                                        outbox.push(Item::Message { topic, payload: payload::outcome(&outcome) });
                                        outbox.push(ack);
                                    }
                                    Decision::Drop { reason } => {
                                        log::warn!("MQTT: dropped a set message on {} ({} bytes): {reason}", echo_text(&publish.topic), publish.payload.len());
                                        outbox.push(ack);
                                    }
                                }
                            }
                            Ok(MqttEvent::Incoming(Packet::SubAck(_))) => {
                                if let Some(tx) = subscribed.take() {
                                    let _ = tx.send(());
                                }
                            }
                            Ok(MqttEvent::Outgoing(rumqttc::Outgoing::Disconnect)) => break,
                            Ok(_) => {}
                            Err(error) => {
                                if let Some(tx) = first.take() {
                                    let _ = tx.send(Err(error));
                                    return;
                                }
                                if stop.load(Ordering::Relaxed) {
                                    return;
                                }
                                if outage.is_none() {
                                    log::warn!("MQTT: lost the broker at {url}: {}; reconnecting with back-off up to {} s", describe(&error), BACKOFF_CAP.as_secs());
                                    outage = Some(Instant::now());
                                }
                                let until = Instant::now() + backoff.next_wait();
                                while Instant::now() < until && !stop.load(Ordering::Relaxed) {
                                    std::thread::sleep(Duration::from_millis(50));
                                }
                            }
                        }
                        if abort.load(Ordering::Relaxed) {
                            // Dropping the connection closes the socket without a
                            // DISCONNECT: the broker publishes the last will.
                            return;
                        }
                    }
                })
                .map_err(|e| Failure::new(format!("cannot start the MQTT thread: {e}")))?
        };
        let first = first_rx.recv_timeout(CONNECT_WAIT);
        let refused = match first {
            Ok(Ok(())) => None,
            Ok(Err(error)) => Some(connect_failure(&error, options)),
            Err(_) => Some(
                Failure::new(format!(
                    "the MQTT broker at {url} did not accept the connection within {} s",
                    CONNECT_WAIT.as_secs()
                ))
                .hint("check the host and port, and that it speaks MQTT (mqtts:// for TLS)"),
            ),
        };
        if let Some(failure) = refused {
            stop.store(true, Ordering::Relaxed);
            abort.store(true, Ordering::Relaxed);
            let _ = client.try_unsubscribe(WAKE_TOPIC);
            return Err(failure);
        }
        log::info!("MQTT: connected to {url} as {}", options.client_id);
        let sender = {
            let client = client.clone();
            let outbox = Arc::clone(&outbox);
            let stop = Arc::clone(&stop);
            let filter = topics.set_filter();
            std::thread::Builder::new()
                .name("mqtt-sender".into())
                .spawn(move || send_loop(&client, &outbox, &stop, &filter))
                .map_err(|e| Failure::new(format!("cannot start the MQTT thread: {e}")))?
        };
        let mut stations = Vec::new();
        outbox.state(topics.status(), b"online".to_vec(), Kind::Kept);
        for bus in &plant.buses {
            for station in &bus.stations {
                stations.push((bus.name.clone(), station.name.clone()));
                outbox.state(
                    topics.available(&bus.name, &station.name),
                    b"offline".to_vec(),
                    Kind::Kept,
                );
            }
        }
        if options.ha_discovery {
            for (topic, config) in discovery::configs(&topics, plant) {
                outbox.state(topic, config, Kind::Kept);
            }
        }
        // Ready for writes once the broker has the subscription.
        if subscribed_rx.recv_timeout(CONNECT_WAIT).is_err() {
            log::warn!("MQTT: the broker at {url} has not confirmed the subscription to {} yet; set messages may wait", topics.set_filter());
        }
        Ok(Mqtt {
            client,
            outbox,
            ledger,
            topics,
            stations,
            stop,
            abort,
            sender: Some(sender),
            connection: Some(conn_thread),
        })
    }

    /// Queues what `event` publishes; never waits for the broker.
    pub fn publish(&self, event: &Event) {
        match event {
            Event::Reading(reading) => self.outbox.state(
                self.topics
                    .state(&reading.bus, &reading.drive, &reading.code),
                payload::state(reading),
                Kind::Reading,
            ),
            Event::Availability(availability) => self.outbox.state(
                self.topics
                    .available(&availability.bus, &availability.drive),
                if availability.online {
                    b"online".to_vec()
                } else {
                    b"offline".to_vec()
                },
                Kind::Kept,
            ),
            Event::Written(outcome) => {
                let (topic, ack) = self
                    .ledger
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .outcome(outcome);
                self.outbox.push(Item::Message {
                    topic,
                    payload: payload::outcome(outcome),
                });
                if let Some(publish) = ack {
                    self.outbox.push(Item::Ack(Box::new(publish)));
                }
            }
            Event::Port(_) => {}
        }
    }

    /// Publishes every station and the service `offline`, sends what is queued and
    /// disconnects, in at most a few seconds.
    pub fn shutdown(mut self) {
        for (bus, drive) in &self.stations {
            self.outbox.state(
                self.topics.available(bus, drive),
                b"offline".to_vec(),
                Kind::Kept,
            );
        }
        self.outbox
            .state(self.topics.status(), b"offline".to_vec(), Kind::Kept);
        let dropped = self.outbox.dropped();
        if dropped > 0 {
            log::warn!(
                target: crate::service::serve::LOG_TARGET,
                "{dropped} reading(s) were not published: the broker was slower than the buses (each topic kept its latest state)"
            );
        }
        let deadline = Instant::now() + SHUTDOWN_WAIT;
        while !self.outbox.is_empty() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(20));
        }
        self.outbox.close();
        self.stop.store(true, Ordering::Relaxed);
        if let Some(sender) = self.sender.take() {
            join_within(sender, Duration::from_secs(1));
        }
        let _ = self.client.try_disconnect();
        if let Some(connection) = self.connection.take() {
            join_within(
                connection,
                deadline.saturating_duration_since(Instant::now()) + Duration::from_secs(1),
            );
        }
    }
}

impl Drop for Mqtt {
    /// Without [`Mqtt::shutdown`] (a crash): the connection is closed without a
    /// DISCONNECT, so the broker publishes the last will (`PREFIX/status` `offline`).
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        self.outbox.close();
        if let Some(sender) = self.sender.take() {
            join_within(sender, Duration::from_secs(1));
        }
        // Wake the connection thread (it waits for the broker or a request) so that it
        // sees `abort` and drops the connection.
        self.abort.store(true, Ordering::Relaxed);
        let _ = self.client.try_unsubscribe(WAKE_TOPIC);
        if let Some(connection) = self.connection.take() {
            join_within(connection, Duration::from_secs(2));
        }
    }
}

/// Waits for `thread` at most `wait` (a stuck thread is left behind, never waited on).
fn join_within(thread: JoinHandle<()>, wait: Duration) {
    let deadline = Instant::now() + wait;
    while !thread.is_finished() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    if thread.is_finished() {
        let _ = thread.join();
    }
}

/// Sends the outbox's items until it is closed and empty.
fn send_loop(client: &Client, outbox: &Outbox, stop: &AtomicBool, filter: &str) {
    loop {
        let Some(item) = outbox.next(Duration::from_millis(100)) else {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            continue;
        };
        let sent = match item {
            Item::State { topic, payload } => {
                client.publish(topic, QoS::AtLeastOnce, true, payload)
            }
            Item::Message { topic, payload } => {
                client.publish(topic, QoS::AtLeastOnce, false, payload)
            }
            Item::Ack(publish) => client.ack(&publish),
            Item::Resync => {
                let subscribed = client.subscribe(filter, QoS::AtLeastOnce);
                for (topic, payload) in outbox.snapshot() {
                    let _ = client.publish(topic, QoS::AtLeastOnce, true, payload);
                }
                subscribed
            }
        };
        if sent.is_err() {
            return;
        }
    }
}

/// What a failed first connection means, for people (never the credentials).
fn connect_failure(error: &ConnectionError, options: &MqttOptions) -> Failure {
    let url = &options.url;
    match error {
        ConnectionError::ConnectionRefused(ConnectReturnCode::BadUserNamePassword) => Failure::new(format!(
            "the MQTT broker at {url} refused the user name or password"
        ))
        .hint(if options.credentials.is_some() {
            "check VFD_MQTT_USERNAME and the password (VFD_MQTT_PASSWORD, VFD_MQTT_PASSWORD_FILE or --mqtt-password-file)"
        } else {
            "it wants credentials: set VFD_MQTT_USERNAME and VFD_MQTT_PASSWORD (or a password file)"
        }),
        ConnectionError::ConnectionRefused(ConnectReturnCode::NotAuthorized) => Failure::new(format!(
            "the MQTT broker at {url} refused the connection: not authorized (mosquitto says this for a wrong user name or password)"
        ))
        .hint(if options.credentials.is_some() {
            "check VFD_MQTT_USERNAME and the password (VFD_MQTT_PASSWORD, VFD_MQTT_PASSWORD_FILE or --mqtt-password-file), and that the broker lets this user connect"
        } else {
            "it wants credentials: set VFD_MQTT_USERNAME and VFD_MQTT_PASSWORD (or a password file)"
        }),
        ConnectionError::ConnectionRefused(code) => Failure::new(format!(
            "the MQTT broker at {url} refused the connection ({code:?})"
        )),
        other => match tls_problem(other) {
            Some(problem) => tls_failure(problem, options),
            None if url.tls && closed_in_handshake(other) => Failure::new(format!(
                "the MQTT broker at {url} closed the connection during the TLS handshake: {}",
                describe(other)
            ))
            .hint(format!(
                "does port {} speak TLS? (mqtt:// for a plain listener; mosquitto: `certfile` and `keyfile` on the listener)",
                url.port
            )),
            None => Failure::new(format!("cannot connect to the MQTT broker at {url}: {}", describe(other)))
                .hint("is the broker running and listening there? (mosquitto: `listener PORT`)"),
        },
    }
}

/// The TLS error under a connection error, where the handshake failed.
fn tls_problem(error: &ConnectionError) -> Option<&rustls::Error> {
    let io = match error {
        ConnectionError::Tls(rumqttc::TlsError::TLS(tls)) => return Some(tls),
        ConnectionError::Tls(rumqttc::TlsError::Io(io)) | ConnectionError::Io(io) => io,
        _ => return None,
    };
    io.get_ref()?.downcast_ref::<rustls::Error>()
}

/// Whether the connection ended during the TLS handshake (a listener that does not speak
/// TLS closes it on the first bytes).
fn closed_in_handshake(error: &ConnectionError) -> bool {
    use std::io::ErrorKind;
    matches!(
        error,
        ConnectionError::Tls(rumqttc::TlsError::Io(io))
            if matches!(io.kind(), ErrorKind::UnexpectedEof | ErrorKind::ConnectionReset | ErrorKind::ConnectionAborted)
    )
}

/// A failed TLS handshake, with what to check: the CA file for a certificate nobody
/// trusted, the host name in the URL for a certificate of another name.
fn tls_failure(problem: &rustls::Error, options: &MqttOptions) -> Failure {
    use rustls::CertificateError;
    let url = &options.url;
    let failure = Failure::new(format!(
        "the TLS handshake with the MQTT broker at {url} failed: {problem}"
    ));
    let ca = match &options.ca_file {
        Some(file) => format!("the CA file {} (--mqtt-ca-file)", file.display()),
        None => "the system's CA certificates (no --mqtt-ca-file given)".to_owned(),
    };
    match problem {
        rustls::Error::InvalidCertificate(CertificateError::UnknownIssuer | CertificateError::BadSignature) => failure.hint(format!(
            "the broker's certificate is not signed by a CA this service trusts: {ca}; give the CA that signed the broker's certificate with --mqtt-ca-file FILE (PEM)"
        )),
        rustls::Error::InvalidCertificate(
            CertificateError::NotValidForName | CertificateError::NotValidForNameContext { .. },
        ) => failure.hint(format!(
            "the broker's certificate is not for the host name `{}`: use the name (or address) the certificate names in the URL (mqtts://NAME:{}), or have a certificate made for `{}`",
            url.host, url.port, url.host
        )),
        rustls::Error::InvalidCertificate(
            CertificateError::Expired
            | CertificateError::ExpiredContext { .. }
            | CertificateError::NotValidYet
            | CertificateError::NotValidYetContext { .. },
        ) => failure.hint("the broker's certificate is outside its validity period: renew it, or check this host's clock"),
        rustls::Error::InvalidMessage(_) => failure.hint(format!(
            "the broker did not answer as a TLS server: does port {} speak TLS? (mqtt:// for a plain listener; mosquitto: `certfile` and `keyfile` on the listener)",
            url.port
        )),
        _ => failure.hint(format!(
            "check {ca}, and that the host name in the URL is one the broker's certificate names"
        )),
    }
}

/// A connection error in words.
fn describe(error: &ConnectionError) -> String {
    match error {
        ConnectionError::Io(io) if io.kind() == std::io::ErrorKind::ConnectionRefused => {
            "connection refused (nothing listens there)".into()
        }
        ConnectionError::Io(io) => format!("I/O error: {io}"),
        other => other.to_string(),
    }
}
