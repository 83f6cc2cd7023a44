//! The serial line of a drive file: settings and timing (`serial:`), line-level facts,
//! station numbers (`addressing:`) and serial ports (`ports:`).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use vfd_runtime::serial::Parity;

/// The drive's serial ports (`ports:`).
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PortsModel {
    /// The manual sections describing the ports.
    pub source: String,
    /// Anything the manual says about the ports that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// The ports, the one a client uses when it names none first.
    pub list: Vec<PortModel>,
    /// Registers (codes or ids) that both ports share (parity, station number).
    #[serde(default)]
    pub shared: Vec<String>,
    /// Registers that exist once per port: each entry maps every port id to its copy
    /// (`{ two_wire: FA00, four_wire: FA04 }`); a client that picks a port is pointed
    /// from one copy to its port's.
    #[serde(default)]
    pub registers: Vec<BTreeMap<String, String>>,
}

/// One serial port.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PortModel {
    /// Lower snake case id (`two_wire`): what `--port-kind` and the generated port
    /// constants are named by.
    pub id: String,
    /// The port's name in English.
    pub name: String,
    /// The port's name as the manual prints it in Chinese.
    #[serde(default)]
    pub name_zh: String,
    /// The registers setting this port, by what they set (`{ baud_rate: F800,
    /// protocol: F807 }`); every port names the same settings.
    #[serde(default)]
    pub settings: BTreeMap<String, String>,
}

/// The line-level facts of the serial link (the manual's specification table).
#[derive(Debug, Clone, Deserialize, JsonSchema, Default)]
#[serde(deny_unknown_fields)]
pub struct LineModel {
    /// Manual section these facts come from.
    #[serde(default)]
    pub source: String,
    /// `half` or `full` duplex (传输方式).
    pub duplex: Option<Duplex>,
    /// Who controls the line (连接控制): `master_slave` (one master polls the drives).
    pub topology: Option<Topology>,
    /// `asynchronous` or `synchronous` transmission (同步性).
    pub synchronisation: Option<Synchronisation>,
    /// Order of the bits within a character (位发送次序): `lsb_first` or `msb_first`.
    pub bit_order: Option<BitOrder>,
}

/// Half or full duplex.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Duplex {
    /// One direction at a time (two-wire RS-485).
    Half,
    /// Both directions at once (four-wire).
    Full,
}

/// Who controls the line.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Topology {
    /// Centralised control (集中控制): one master sends, the addressed drive answers.
    MasterSlave,
    /// Any station may start an exchange.
    MultiMaster,
}

/// Character synchronisation.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Synchronisation {
    /// Start and stop bits frame each character.
    Asynchronous,
    /// A shared clock frames the characters.
    Synchronous,
}

/// Bit order within a character.
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BitOrder {
    /// Least significant bit first (the UART convention).
    LsbFirst,
    /// Most significant bit first.
    MsbFirst,
}

/// A timing value that can be marked as assumed (not from the manual).
#[derive(Debug, Clone, Copy, Deserialize, JsonSchema, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TimingField {
    /// `startup_delay_ms`.
    StartupDelayMs,
    /// `frame_abandon_ms`.
    FrameAbandonMs,
    /// `processing_allowance_ms`.
    ProcessingAllowanceMs,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SerialModel {
    /// The manual section these settings come from.
    pub source: String,
    /// Anything the manual says about the serial line that fits nowhere else.
    #[serde(default)]
    pub note: String,
    /// Every baud rate the drive can be set to.
    pub baud_rates: Vec<u32>,
    /// Every parity the drive can be set to.
    pub parities: Vec<Parity>,
    /// Data bits per character (`8`), or the data bits the drive can be set to (`[7, 8]`:
    /// a setting chooses, the factory setting being `default.data_bits`).
    pub data_bits: DataBitsModel,
    /// Stop bits the drive sends, when fixed; left out with `stop_bits`.
    pub stop_bits_sent: Option<u8>,
    /// Stop bits the drive needs to receive, when fixed; left out with `stop_bits`.
    pub stop_bits_received: Option<u8>,
    /// The stop bits the drive can be set to (`[1, 2]`: "1 or 2", the drive's choice, a
    /// setting): it then sends and needs the stop bits it is set to, the factory setting
    /// being `default.stop_bits`. Give this or both `stop_bits_sent` and
    /// `stop_bits_received`.
    #[serde(default)]
    pub stop_bits: Vec<u8>,
    /// The factory setting.
    pub default: SerialDefaultModel,
    /// How long the drive takes to be ready, to give up a frame and to answer.
    pub timing: TimingModel,
    /// Line-level facts from the manual's specification table (duplex, topology,
    /// synchronisation, bit order); each may be left out.
    pub line: Option<LineModel>,
}

/// Data bits per character: fixed, or the drive's choice.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum DataBitsModel {
    /// Every character carries this many data bits.
    Fixed(u8),
    /// The drive can be set to any of these (`[7, 8]`).
    Choice(Vec<u8>),
}

impl DataBitsModel {
    /// The data bits the drive can use, in the file's order.
    pub fn choices(&self) -> Vec<u8> {
        match self {
            DataBitsModel::Fixed(bits) => vec![*bits],
            DataBitsModel::Choice(bits) => bits.clone(),
        }
    }
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SerialDefaultModel {
    /// Factory baud rate.
    pub baud: u32,
    /// Factory parity.
    pub parity: Parity,
    /// Factory data bits.
    pub data_bits: u8,
    /// Factory stop bits.
    pub stop_bits: u8,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TimingModel {
    /// No answer this long after power-on (milliseconds).
    pub startup_delay_ms: u64,
    /// The drive drops an unfinished frame after this long (milliseconds).
    pub frame_abandon_ms: u64,
    /// Added to the wire time of request and longest reply to give the reply timeout (milliseconds).
    pub processing_allowance_ms: u64,
    /// Timings that are placeholders or our own assumption rather than the manual's
    /// statement: `[startup_delay_ms, frame_abandon_ms, processing_allowance_ms]`.
    #[serde(default)]
    pub assumed: Vec<TimingField>,
}

#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AddressingModel {
    /// Lowest station number.
    pub min: u8,
    /// Highest station number.
    pub max: u8,
    /// What the manual says about addressing (broadcast, panel setting).
    #[serde(default)]
    pub note: String,
    /// Code or id of the register holding the drive's station number (DV1 07-01): the
    /// virtual drive answers at the station it holds (the value in effect: after a reset
    /// for a register that takes effect then), and a write to it moves the station.
    pub register: Option<String>,
}
