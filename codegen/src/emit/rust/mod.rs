//! Emits the typed Rust API of a drive from its IR with `quote!`, formatted in-process with
//! prettyplease: one file per drive, plus the shared frame layouts of the protocol files.
//!
//! Each kind of item has its own file: [`registers`], [`bitfields`], [`code_tables`],
//! [`protocols`]; runtime values become tokens through [`bake::Bake`] only.

pub(crate) mod bake;
mod behaviour;
mod bitfields;
mod code_tables;
mod protocols;
mod registers;
mod relations;

use crate::emit::words::zh;
use crate::ir::{BitfieldIr, CodeTableIr, DriveIr, ProtocolFileIr, ProtocolIr, RegisterIr};
use crate::ir::{SpanEndIr, ValueKind};
use crate::naming::const_name;
use bake::{int_literal, Bake};
use bitfields::bits_module;
use code_tables::{codes_module, error_code_enum};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use protocols::protocols_module;
use quote::{format_ident, quote};
use registers::registers_module;

pub(crate) use protocols::layouts_module;
pub(crate) use registers::relation_lines;

/// Where a drive module finds the frame layouts of its protocol files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layouts {
    /// The drive module holds its own `layouts` module (one drive on its own, as the
    /// proc-macro generates it).
    Inside,
    /// A `layouts` module beside the drive modules holds them, once for every drive
    /// (what [`crate::Builder`] writes into `drives.rs`).
    Beside,
}

/// The drive's module as tokens (`pub mod <id> { ... }`).
pub fn drive_module(drive: &DriveIr, layouts: Layouts) -> TokenStream {
    let module = ident(&drive.module);
    let docs = [
        format!(
            "{}{}: typed registers, protocols and code tables.",
            drive.name,
            zh(&drive.name_zh)
        ),
        String::new(),
        format!(
            "Generated from `{}`, transcribed from the manual {} (`{}`). {}",
            drive.file,
            drive.manual_named(),
            drive.manual,
            drive.description
        ),
    ];
    let mut docs = docs.to_vec();
    for warning in &drive.warnings {
        docs.push(String::new());
        docs.push(format!(
            "**Warning:** {}",
            crate::emit::words::warning_text(warning)
        ));
    }
    let docs = doc_texts(&docs);
    let (id, vendor, model, manual) = (&drive.id, &drive.vendor, &drive.model, &drive.manual);
    let manual_title = drive.manual_named();
    let (name, name_zh) = (&drive.name, &drive.name_zh);
    let (layouts_path, own_layouts) = match layouts {
        Layouts::Inside => {
            let files: Vec<&ProtocolFileIr> = drive.protocol_files.iter().collect();
            (quote!(super::layouts), Some(layouts_module(&files)))
        }
        Layouts::Beside => (quote!(super::super::layouts), None),
    };
    let serial = serial_spec(drive);
    let protocols = protocols_module(drive, &layouts_path);
    let registers = registers_module(drive);
    let bits = bits_module(drive);
    let codes = codes_module(drive);
    let errors = error_code_enum(drive);
    let scaling = reference_scaling(drive);
    let (behaviour, behaviour_ref) = behaviour::behaviour_static(drive);
    let (ports, ports_ref) = relations::ports_module(drive);
    let conversions = relations::conversions_module(drive);
    let forbidden = relations::forbidden_tokens(drive);
    let station_register = match &drive.addressing.register {
        Some(id) => quote!(Some(#id)),
        None => quote!(None),
    };
    quote! {
        #(#[doc = #docs])*
        #[allow(clippy::excessive_precision, clippy::unreadable_literal)]
        pub mod #module {
            /// Drive identifier used in file names and on the command line.
            pub const ID: &str = #id;
            /// Vendor.
            pub const VENDOR: &str = #vendor;
            /// Model.
            pub const MODEL: &str = #model;
            /// The manual the description was transcribed from (its file name).
            pub const MANUAL: &str = #manual;
            /// The manual as people name it: its title and document number.
            pub const MANUAL_TITLE: &str = #manual_title;
            /// The drive as a type: its registers and protocols name it, so a register of
            /// this drive cannot be used with another drive's protocol or master.
            #[derive(Debug, Clone, Copy)]
            pub enum Drive {}
            #serial
            /// The drive as data, for tools that work with any described drive.
            pub static DRIVE: ::vfd_runtime::DriveInfo = ::vfd_runtime::DriveInfo {
                id: ID,
                vendor: VENDOR,
                model: MODEL,
                name: #name,
                name_zh: #name_zh,
                manual: MANUAL,
                manual_title: MANUAL_TITLE,
                serial: &SERIAL,
                protocols: &protocols::ALL,
                registers: &registers::ALL,
                behaviour: #behaviour_ref,
                ports: #ports_ref,
                conversions: &conversions::ALL,
                forbidden: #forbidden,
                station_register: #station_register,
            };
            #own_layouts
            #protocols
            #registers
            #bits
            #codes
            #errors
            #scaling
            #behaviour
            #ports
            #conversions
        }
    }
}

/// Formats tokens as a Rust file, after `header` (the `@generated` comment lines).
pub fn format_file(header: &str, tokens: TokenStream) -> Result<String, String> {
    let file: syn::File =
        syn::parse2(tokens).map_err(|e| format!("generated code does not parse: {e}"))?;
    Ok(format!("{header}{}", prettyplease::unparse(&file)))
}

/// A doc-comment string for text from a description: a leading space (so it prints as
/// `/// text`), and `[`/`]` escaped so rustdoc does not take manual text such as `310[0]`
/// for an intra-doc link. Every doc string built from a description goes through here.
fn doc_text(text: impl AsRef<str>) -> String {
    let text = text.as_ref().replace('[', "\\[").replace(']', "\\]");
    if text.is_empty() {
        text
    } else {
        format!(" {text}")
    }
}

/// [`doc_text`] for each line, prose wrapped ([`crate::emit::wrap`]): one `#[doc]`
/// attribute, one `///` line, each.
fn doc_texts(lines: &[String]) -> Vec<String> {
    let wrapped = crate::emit::wrap::wrap_markdown(&lines.join("\n"), crate::emit::wrap::WIDTH - 4);
    wrapped.split('\n').map(doc_text).collect()
}

/// A string literal, the same token as `Literal::string(text)`, made faster where it is
/// made by the thousand (the registers). Outside a proc-macro, proc-macro2 escapes a string
/// char by char through `char::escape_debug`, which was a third of the time spent building
/// a register's tokens; text in which no char needs escaping is written between quotes and
/// lexed as it stands instead.
fn str_literal(text: &str) -> Literal {
    let plain = text
        .chars()
        .all(|c| c != '"' && c != '\\' && c.escape_debug().len() == 1);
    if plain {
        if let Ok(literal) = format!("\"{text}\"").parse() {
            return literal;
        }
    }
    Literal::string(text)
}

fn ident(name: &str) -> Ident {
    Ident::new(name, Span::call_site())
}

/// A `0xFA01` literal, as the manuals write addresses and masks.
fn hex_u16(value: u16) -> TokenStream {
    format!("0x{value:04X}")
        .parse()
        .unwrap_or_else(|_| quote!(#value))
}

fn f64_literal(value: f64) -> Literal {
    Literal::f64_unsuffixed(value)
}

fn serial_spec(drive: &DriveIr) -> TokenStream {
    let serial = &drive.serial;
    let bauds = serial.baud_rates.iter().map(|b| int_literal(*b));
    let parities = serial.parities.iter().map(Bake::bake);
    let default_parity = serial.default_parity.bake();
    let (baud, data_bits, stop_bits) = (
        int_literal(serial.default_baud),
        int_literal(serial.default_data_bits),
        int_literal(serial.default_stop_bits),
    );
    let (sent, received) = (
        int_literal(serial.stop_bits_sent),
        int_literal(serial.stop_bits_received),
    );
    let stop_choices = serial.stop_bits.iter().map(|b| int_literal(*b));
    let data_choices = serial.data_bits.iter().map(|b| int_literal(*b));
    let protocol_lines = serial.protocol_lines.iter().map(|line| {
        let (protocol, data_bits, parity, stop_bits, factory) = (
            line.protocol.as_str(),
            int_literal(line.data_bits),
            line.parity.bake(),
            int_literal(line.stop_bits),
            line.factory,
        );
        quote! {
            ::vfd_runtime::serial::ProtocolLine {
                protocol: #protocol,
                data_bits: #data_bits,
                parity: #parity,
                stop_bits: #stop_bits,
                factory: #factory,
            }
        }
    });
    let (startup, allowance, abandon) = (
        int_literal(serial.startup_delay_ms),
        int_literal(serial.processing_allowance_ms),
        int_literal(serial.frame_abandon_ms),
    );
    let doc = doc_text(format!(
        "Serial settings (manual section {}): {} baud, {} parity by default.",
        serial.source,
        serial.default_baud,
        serial.default_parity.as_str()
    ));
    quote! {
        #[doc = #doc]
        pub const SERIAL: ::vfd_runtime::serial::SerialSpec = {
            use ::std::time::Duration;
            use ::vfd_runtime::serial::{DriveTiming, Parity, SerialSettings, SerialSpec};
            SerialSpec {
                baud_rates: &[#(#bauds),*],
                parities: &[#(#parities),*],
                default: SerialSettings {
                    baud: #baud,
                    data_bits: #data_bits,
                    parity: #default_parity,
                    stop_bits: #stop_bits,
                },
                data_bits: &[#(#data_choices),*],
                protocol_lines: &[#(#protocol_lines),*],
                stop_bits_sent: #sent,
                stop_bits_received: #received,
                stop_bits: &[#(#stop_choices),*],
                timing: DriveTiming {
                    startup_delay: Duration::from_millis(#startup),
                    processing_allowance: Duration::from_millis(#allowance),
                    frame_abandon: Duration::from_millis(#abandon),
                },
            }
        };
    }
}

/// The Rust type a register's values have, as seen from inside the `registers` module
/// (which imports the quantity types and the `bits` and `codes` modules).
fn value_type(kind: &ValueKind) -> TokenStream {
    match kind {
        ValueKind::Quantity(name) => {
            let name = ident(name);
            quote!(#name)
        }
        ValueKind::CodeTable(name) => {
            let name = ident(name);
            quote!(codes::#name)
        }
        ValueKind::Bitfield(name) => {
            let name = ident(name);
            quote!(bits::#name)
        }
        other => value_type_at(other, &quote!(super)),
    }
}

/// The Rust type a register's values have, with generated types reached through `module`
/// (the drive module's path).
pub fn value_type_at(kind: &ValueKind, module: &TokenStream) -> TokenStream {
    match kind {
        ValueKind::Quantity(name) => {
            let name = ident(name);
            quote!(::vfd_runtime::units::#name)
        }
        ValueKind::CodeTable(name) => {
            let name = ident(name);
            quote!(#module::codes::#name)
        }
        ValueKind::Bitfield(name) => {
            let name = ident(name);
            quote!(#module::bits::#name)
        }
        ValueKind::Raw => quote!(u16),
        ValueKind::RawSigned => quote!(i16),
        ValueKind::Scaled => quote!(f64),
        ValueKind::RawDouble => quote!(u32),
        ValueKind::RawSignedDouble => quote!(i32),
        ValueKind::Text => quote!(::std::string::String),
    }
}

fn reference_scaling(drive: &DriveIr) -> TokenStream {
    let Some(scaling) = &drive.reference_scaling else {
        return quote!();
    };
    let full = int_literal(scaling.full_scale_raw);
    let applies = scaling.applies_to.iter().map(String::as_str);
    let selector = &scaling.selector;
    let end = |end: &SpanEndIr| match end {
        SpanEndIr::Number(value) => {
            let value = f64_literal(*value);
            quote!(SpanEnd::Number(#value))
        }
        SpanEndIr::Register(id) => quote!(SpanEnd::Register(#id)),
    };
    let modes = scaling.modes.iter().map(|mode| {
        let (value, low, high, description) = (
            int_literal(mode.selector),
            end(&mode.low),
            end(&mode.high),
            &mode.description,
        );
        quote!(ScalingMode { selector: #value, low: #low, high: #high, description: #description })
    });
    let doc = doc_text(format!(
        "Reference scaling (manual: {}): {:X}h is 100 %; register `{selector}` chooses the span. {}",
        scaling.source, scaling.full_scale_raw, scaling.note
    ));
    quote! {
        #[doc = #doc]
        pub static REFERENCE_SCALING: ::vfd_runtime::scaling::ReferenceScaling = {
            use ::vfd_runtime::scaling::{ReferenceScaling, ScalingMode, SpanEnd};
            ReferenceScaling {
                full_scale_raw: #full,
                applies_to: &[#(#applies),*],
                selector: #selector,
                modes: &[#(#modes),*],
            }
        };
    }
}
