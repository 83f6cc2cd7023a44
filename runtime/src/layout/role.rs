//! What a field means to the transaction engine: its [`Role`].

/// What a field means to the transaction engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Role {
    /// Station (inverter) address.
    Address,
    /// Command letter or function code.
    Command,
    /// Register (communication number) address.
    Register,
    /// Data word written or read.
    Data,
    /// Error code in an error reply.
    ErrorCode,
    /// Array index of an indexed parameter.
    Index,
    /// First process word (control word out, status word back).
    #[cfg_attr(feature = "serde", serde(rename = "process_1"))]
    Process1,
    /// Second process word (reference out, output value back).
    #[cfg_attr(feature = "serde", serde(rename = "process_2"))]
    Process2,
    /// Text carried by the frame (raw bytes).
    Text,
    /// How many decimal places the data has, as a number (an Eaton data reply's unit digit:
    /// 0 for whole units, 1 for tenths, 2 for hundredths, 3 for thousandths).
    Decimals,
    /// A run of 16-bit words, each in the field's format (`u16be` or `u16le`), sized by a
    /// length part: the words a block transfer writes (request) or reads (reply). Held
    /// like a bytes field: its offset in the frame and its byte count.
    Words,
    /// How many words a block-transfer request asks the reply to carry (the reply says how
    /// many it carries with a length part counting its words).
    ReadCount,
    /// A block-transfer reply's write status: bit `n` set means the word at position `n`
    /// of the request (0: the first) was not written.
    WriteStatus,
    /// How long the drive waits before it replies, in tens of milliseconds, as the request
    /// asks (the Eaton protocol's wait-time digit, 0-F): the master adds it to its reply
    /// timeout ([`crate::transaction::Master::with_reply_wait`]), the virtual drive waits.
    ReplyWait,
}

impl Role {
    /// Every role, in the order the description format documents them.
    pub const ALL: [Role; 14] = [
        Role::Address,
        Role::Command,
        Role::Register,
        Role::Data,
        Role::ErrorCode,
        Role::Index,
        Role::Process1,
        Role::Process2,
        Role::Text,
        Role::Decimals,
        Role::Words,
        Role::ReadCount,
        Role::WriteStatus,
        Role::ReplyWait,
    ];

    /// The role's name as written in protocol description files.
    pub const fn as_str(self) -> &'static str {
        match self {
            Role::Address => "address",
            Role::Command => "command",
            Role::Register => "register",
            Role::Data => "data",
            Role::ErrorCode => "error_code",
            Role::Index => "index",
            Role::Process1 => "process_1",
            Role::Process2 => "process_2",
            Role::Text => "text",
            Role::Decimals => "decimals",
            Role::Words => "words",
            Role::ReadCount => "read_count",
            Role::WriteStatus => "write_status",
            Role::ReplyWait => "reply_wait",
        }
    }
}
