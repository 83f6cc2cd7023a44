//! The traits that make register access typed, and the protocol-independent [`Request`]
//! they build. The metadata they carry lives in [`crate::info`] and [`crate::kinds`] and
//! is re-exported here.
//!
//! Every register gets its requests from the traits' provided functions
//! (`R::read()`, `R::write_ram(value)`, `R::write_persistent(value)` and the `_at` forms for
//! array elements); bring them into scope with `use vfd_runtime::prelude::*`.

use crate::error::ValueError;
pub use crate::info::RegisterInfo;
pub use crate::kinds::Access;
use crate::kinds::{CommandKind, DataType, Space};
use std::marker::PhantomData;

/// A value that can be stored in a register: a quantity, a code-table enum, a bit-field
/// word or a raw number.
pub trait RegisterValue: Sized {
    /// Converts to the raw value (a word or a double word), refusing values outside the
    /// register's range.
    fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError>;
    /// Converts a raw value read from the drive.
    fn from_raw(raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError>;
}

/// A register of a described drive. Generated code implements it for one unit struct per register.
pub trait Register {
    /// The drive the register belongs to (a marker type in each generated drive module):
    /// its requests are encoded only by that drive's protocols and sent only by a master
    /// of that drive.
    type Drive: 'static;
    /// The register's metadata.
    const INFO: &'static RegisterInfo;
    /// The typed value read from and written to it.
    type Value: RegisterValue;

    /// A request reading this register (a text read for text parameters).
    fn read() -> DriveRequest<Self::Drive>
    where
        Self: Sized,
    {
        DriveRequest::new(Request::read::<Self>())
    }

    /// A request reading element `index` of this array register. Refuses indexes beyond
    /// the array.
    fn read_at(index: u16) -> Result<DriveRequest<Self::Drive>, ValueError>
    where
        Self: Sized,
    {
        Self::read().at_index(index)
    }

    /// The register as it is when its scale selector holds `selector` (for registers whose
    /// scale another register chooses, `scale_by` in the description: a time in 0.01 s or
    /// 0.1 s steps). Registers with a fixed scale are themselves for any `selector`;
    /// refuses a selector value the description gives no scale for.
    fn scaled_info(selector: u32) -> Result<&'static RegisterInfo, ValueError>
    where
        Self: Sized,
    {
        match Self::INFO.scale_by {
            None => Ok(Self::INFO),
            Some(scale_by) => scale_by.choice(selector).ok_or(ValueError::UnknownScale {
                register: Self::INFO,
                selector: scale_by.register,
                value: selector,
            }),
        }
    }

    /// The typed value of a raw word read from this register while its scale selector
    /// holds `selector` (see [`Register::scaled_info`]).
    fn value_scaled(raw: u32, selector: u32) -> Result<Self::Value, ValueError>
    where
        Self: Sized,
    {
        Self::Value::from_raw(raw, Self::scaled_info(selector)?)
    }
}

/// A register that may be written (implemented only for writable registers, so writing a
/// read-only register does not compile).
pub trait Writable: Register {
    /// A request writing `value` in RAM only (lost at power-off). Refuses values outside
    /// the register's range.
    fn write_ram(value: Self::Value) -> Result<DriveRequest<Self::Drive>, ValueError>
    where
        Self: Sized,
    {
        Request::write_ram::<Self>(value).map(DriveRequest::new)
    }

    /// A request writing `value` in RAM only, in the scale and range the selector value
    /// `selector` chooses (see [`Register::scaled_info`]): 10 s is 03E8h when the selector
    /// chooses 0.01 s steps and 0064h when it chooses 0.1 s.
    fn write_ram_scaled(
        value: Self::Value,
        selector: u32,
    ) -> Result<DriveRequest<Self::Drive>, ValueError>
    where
        Self: Sized,
    {
        let info = Self::scaled_info(selector)?;
        let data = value.to_raw(info)?;
        Ok(DriveRequest::new(Request::for_register(
            CommandKind::WriteRam,
            info,
            data,
        )))
    }

    /// A request writing `value` to element `index` of this array register, in RAM only.
    fn write_ram_at(index: u16, value: Self::Value) -> Result<DriveRequest<Self::Drive>, ValueError>
    where
        Self: Sized,
    {
        Self::write_ram(value)?.at_index(index)
    }
}

/// A register whose value may be written persistently (EEPROM); not implemented for
/// RAM-only registers.
pub trait Persistable: Writable {
    /// A request writing `value` in RAM and EEPROM. EEPROM endures a limited number of
    /// writes: prefer [`Writable::write_ram`] for values that change often.
    fn write_persistent(value: Self::Value) -> Result<DriveRequest<Self::Drive>, ValueError>
    where
        Self: Sized,
    {
        Request::write_persistent::<Self>(value).map(DriveRequest::new)
    }

    /// A request writing `value` to element `index` of this array register, in RAM and
    /// EEPROM.
    fn write_persistent_at(
        index: u16,
        value: Self::Value,
    ) -> Result<DriveRequest<Self::Drive>, ValueError>
    where
        Self: Sized,
    {
        Self::write_persistent(value)?.at_index(index)
    }
}

/// A request, independent of the protocol that will carry it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Request {
    /// What to do.
    pub kind: CommandKind,
    /// Register or parameter number (before the protocol's address map).
    pub register: u16,
    /// Address space of `register`.
    pub space: Space,
    /// `register` is already a wire number: do not map it.
    pub wire_register: bool,
    /// Array index, for indexed parameters.
    pub index: Option<u16>,
    /// Data (ignored for reads).
    pub data: u32,
    /// Shape of the data.
    pub data_type: DataType,
    /// Process words to send along (control word, reference), where the protocol carries them.
    pub process: Option<[u16; 2]>,
    /// The register's metadata, when the request was built from a typed register.
    pub info: Option<&'static RegisterInfo>,
    /// The code of the command to carry it, where the protocol has several for its kind
    /// (a Toshiba read by G instead of R): see [`Request::using`]. `None`: the protocol's
    /// first command of the kind that is not an extra.
    pub command: Option<u32>,
}

impl Request {
    /// A request for the register `info` describes, with raw `data` (no range check; the
    /// typed constructors check). Tools that pick registers at run time use this.
    pub fn for_register(kind: CommandKind, info: &'static RegisterInfo, data: u32) -> Request {
        Request {
            kind,
            register: info.address,
            space: info.space,
            wire_register: false,
            index: None,
            data,
            data_type: info.data_type,
            process: None,
            info: Some(info),
            command: None,
        }
    }

    /// Reads register `R`.
    pub fn read<R: Register>() -> Request {
        let kind = if R::INFO.data_type == DataType::Text {
            CommandKind::ReadText
        } else {
            CommandKind::Read
        };
        Request::for_register(kind, R::INFO, 0)
    }

    /// Writes `value` to register `R` in RAM only. Refuses values outside the register's range.
    pub fn write_ram<R: Writable>(value: R::Value) -> Result<Request, ValueError> {
        let data = value.to_raw(R::INFO)?;
        Ok(Request::for_register(CommandKind::WriteRam, R::INFO, data))
    }

    /// Writes `value` to register `R` in RAM and EEPROM. EEPROM endures a limited number of
    /// writes (the manuals say 1,000 to 10,000): use [`Request::write_ram`] for values that
    /// change often.
    pub fn write_persistent<R: Persistable>(value: R::Value) -> Result<Request, ValueError> {
        let data = value.to_raw(R::INFO)?;
        Ok(Request::for_register(
            CommandKind::WritePersistent,
            R::INFO,
            data,
        ))
    }

    /// Exchanges process words: `control` and `reference` out, status and output value back.
    pub fn process(control: u16, reference: u16) -> Request {
        Request {
            kind: CommandKind::Process,
            register: 0,
            space: Space::Parameter,
            wire_register: false,
            index: None,
            data: 0,
            data_type: DataType::Word,
            process: Some([control, reference]),
            info: None,
            command: None,
        }
    }

    /// A request built from raw numbers (a word in the parameter space), with no range checks.
    pub fn raw(kind: CommandKind, register: u16, data: u32) -> Request {
        Request {
            kind,
            register,
            space: Space::Parameter,
            wire_register: false,
            index: None,
            data,
            data_type: DataType::Word,
            process: None,
            info: None,
            command: None,
        }
    }

    /// The same request for array element `index`. Refuses indexes beyond the register's
    /// array. (A [`crate::transaction::Master`] does the same with `read_at`, `write_ram_at`
    /// and `write_persistent_at`; generated registers with `read_at` and `write_ram_at`.)
    pub fn at_index(mut self, index: u16) -> Result<Request, ValueError> {
        if let Some(info) = self.info {
            if u32::from(index) >= u32::from(info.array_len) {
                return Err(ValueError::IndexOutOfRange {
                    register: info,
                    index,
                    len: info.array_len,
                });
            }
        }
        self.index = Some(index);
        Ok(self)
    }

    /// The same request carried by the command with code `code` (a letter as a number:
    /// `u32::from(b'G')`), where the protocol has several commands for its kind. For a
    /// command whose lower case says the sender has tripped, the lower-case letter sends
    /// that. Encoding fails with [`crate::EncodeError::NoSuchCommand`] when the protocol
    /// (as the drive speaks it) has no such command for this kind of request.
    pub fn using(mut self, code: u32) -> Request {
        self.command = Some(code);
        self
    }

    /// The same request with another data type.
    pub fn with_data_type(mut self, data_type: DataType) -> Request {
        self.data_type = data_type;
        self
    }

    /// The same request in another address space.
    pub fn in_space(mut self, space: Space) -> Request {
        self.space = space;
        self
    }

    /// Describes the request for error messages.
    pub fn describe(&self) -> String {
        let target = match self.info {
            Some(info) => info.label(),
            None if self.space == Space::Coil => format!("coil {}", self.register),
            None => format!("register {:04X}", self.register),
        };
        let target = match self.index {
            Some(index) => format!("{target}[{index}]"),
            None => target,
        };
        match self.kind {
            CommandKind::Read => format!("read of {target}"),
            CommandKind::ReadText => format!("text read of {target}"),
            CommandKind::WriteRam => format!("RAM write of {:04X}h to {target}", self.data),
            CommandKind::WritePersistent => {
                format!("persistent write of {:04X}h to {target}", self.data)
            }
            CommandKind::Process => match self.process {
                Some([control, reference]) => {
                    format!("process exchange (control {control:04X}h, reference {reference:04X}h)")
                }
                None => "process exchange".to_owned(),
            },
            CommandKind::Block => "block transfer".to_owned(),
            CommandKind::Echo => format!("diagnostic echo of {:04X}h", self.data),
        }
    }
}

/// A [`Request`] built for one drive's registers (the `D` of [`Register::Drive`]): only
/// that drive's protocols ([`crate::protocol::DriveProtocol`]) encode it and only a master
/// of that drive sends it, so a register of another drive does not compile there. It
/// dereferences to the untyped request.
pub struct DriveRequest<D> {
    request: Request,
    drive: PhantomData<fn() -> D>,
}

impl<D> DriveRequest<D> {
    /// Marks `request` as one for drive `D`.
    pub const fn new(request: Request) -> Self {
        DriveRequest {
            request,
            drive: PhantomData,
        }
    }

    /// The same request for element `index` of an array register; refuses indexes beyond
    /// the array (see [`Request::at_index`]).
    pub fn at_index(self, index: u16) -> Result<Self, ValueError> {
        self.request.at_index(index).map(DriveRequest::new)
    }

    /// The same request carried by the command with code `code` (see [`Request::using`]).
    pub fn using(self, code: u32) -> Self {
        DriveRequest::new(self.request.using(code))
    }

    /// The untyped request.
    pub const fn into_request(self) -> Request {
        self.request
    }
}

impl<D> std::ops::Deref for DriveRequest<D> {
    type Target = Request;
    fn deref(&self) -> &Request {
        &self.request
    }
}

impl<D> Clone for DriveRequest<D> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<D> Copy for DriveRequest<D> {}

impl<D> PartialEq for DriveRequest<D> {
    fn eq(&self, other: &Self) -> bool {
        self.request == other.request
    }
}

impl<D> std::fmt::Debug for DriveRequest<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.request.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::Unit;

    /// A register written the way generated code may write it: only what differs from
    /// [`RegisterInfo::DEFAULT`].
    /// The drive of the test registers.
    enum TestDrive {}

    struct MaximumFrequency;
    impl Register for MaximumFrequency {
        type Drive = TestDrive;
        const INFO: &'static RegisterInfo = &RegisterInfo {
            address: 0x0011,
            id: "maximum_frequency",
            code: "FH",
            name: "Maximum frequency",
            name_zh: "最高频率",
            unit: Unit::Hertz,
            scale: 0.01,
            raw_min: 3000,
            raw_max: 40000,
            ..RegisterInfo::DEFAULT
        };
        type Value = f64;
    }
    impl Writable for MaximumFrequency {}
    impl Persistable for MaximumFrequency {}

    struct Presets;
    impl Register for Presets {
        type Drive = TestDrive;
        const INFO: &'static RegisterInfo = &RegisterInfo {
            address: 310,
            code: "310",
            array_len: 4,
            ..RegisterInfo::DEFAULT
        };
        type Value = u16;
    }
    impl Writable for Presets {}
    impl Persistable for Presets {}

    #[test]
    fn every_register_gets_its_requests_from_the_traits() {
        assert_eq!(
            MaximumFrequency::read().into_request(),
            Request::for_register(CommandKind::Read, MaximumFrequency::INFO, 0)
        );
        let ram = MaximumFrequency::write_ram(60.0).unwrap();
        assert_eq!((ram.kind, ram.data), (CommandKind::WriteRam, 6000));
        let persistent = MaximumFrequency::write_persistent(60.0).unwrap();
        assert_eq!(persistent.kind, CommandKind::WritePersistent);
        assert!(matches!(
            MaximumFrequency::write_ram(500.0),
            Err(ValueError::OutOfRange { max: 400.0, .. })
        ));
    }

    #[test]
    fn array_elements_are_addressed_with_the_at_functions() {
        assert_eq!(Presets::read_at(3).unwrap().index, Some(3));
        let write = Presets::write_ram_at(2, 7).unwrap();
        assert_eq!(
            (write.kind, write.index, write.data),
            (CommandKind::WriteRam, Some(2), 7)
        );
        let write = Presets::write_persistent_at(1, 7).unwrap();
        assert_eq!(
            (write.kind, write.index),
            (CommandKind::WritePersistent, Some(1))
        );
        assert!(matches!(
            Presets::read_at(4),
            Err(ValueError::IndexOutOfRange {
                index: 4,
                len: 4,
                ..
            })
        ));
    }

    #[test]
    fn the_default_register_is_a_plain_read_write_word() {
        let info = Presets::INFO;
        assert_eq!(
            (info.access, info.data_type, info.space, info.unit),
            (
                Access::ReadWrite,
                DataType::Word,
                Space::Parameter,
                Unit::None
            )
        );
        assert_eq!((info.scale, info.raw_min, info.raw_max), (1.0, 0, 0xFFFF));
        assert_eq!(
            MaximumFrequency::INFO.label(),
            "register 0011 FH (Maximum frequency / 最高频率)"
        );
    }
}
