//! The command line of `vfd serve`: the plant file, `--check`, the outputs (`--jsonl`,
//! `--mqtt`) and the inputs (MQTT `set` topics, `--stdin-writes`).

use std::path::PathBuf;

/// `vfd serve PLANT`: poll the plant file's drives and publish what they read.
#[derive(Debug, Clone, clap::Args)]
pub struct ServeArgs {
    /// The plant file: buses, drives, what to poll and what may be written (docs/plant.md;
    /// an annotated example is plants/example.yaml).
    #[arg(value_name = "PLANT")]
    pub plant: PathBuf,
    /// Check the plant file and print what would be polled and allowed, or every problem
    /// at file:line:column (exit status 1); opens no port.
    #[arg(long)]
    pub check: bool,
    /// Print every reading and every change (a station on- or offline, a write, a port)
    /// as one JSON object per line on standard output.
    #[arg(long)]
    pub jsonl: bool,
    /// Take write requests as JSON lines on standard input (`{"bus": "line1", "drive":
    /// "pump1", "register": "FA01", "value": "50 Hz"}`), each checked as an MQTT `set` is;
    /// the outcome is a `written` event.
    #[arg(long)]
    pub stdin_writes: bool,
    /// Print debug records too (registers a drive refused to read, the runtime's retries).
    #[arg(long, short = 'v')]
    pub verbose: bool,
    /// Publish to this MQTT broker: mqtt://HOST:PORT (port 1883 if left out) or mqtts://HOST:PORT (TLS,
    /// 8883). User and password come from the environment (VFD_MQTT_USERNAME,
    /// VFD_MQTT_PASSWORD or VFD_MQTT_PASSWORD_FILE) or --mqtt-password-file, never from
    /// the command line (docs/mqtt.md).
    #[arg(long, value_name = "URL")]
    pub mqtt: Option<String>,
    /// The first topic level(s) of everything published (`vfd/BUS/DRIVE/CODE`).
    #[arg(long, value_name = "PREFIX", default_value = "vfd")]
    pub mqtt_prefix: String,
    /// The MQTT client id (default: vfd-serve-HOST-PREFIX, the same at every start, so the
    /// broker keeps `set` messages sent while the service was down).
    #[arg(long, value_name = "ID")]
    pub mqtt_client_id: Option<String>,
    /// A file holding the broker password (its first line), read once at start.
    #[arg(long, value_name = "FILE")]
    pub mqtt_password_file: Option<PathBuf>,
    /// An extra CA certificate (PEM) to trust for mqtts:// (the system's roots are trusted).
    #[arg(long, value_name = "FILE")]
    pub mqtt_ca_file: Option<PathBuf>,
    /// Publish Home Assistant MQTT discovery configs: each polled register a sensor with
    /// its unit, the drive as the device.
    #[arg(long, requires = "mqtt")]
    pub ha_discovery: bool,
}
