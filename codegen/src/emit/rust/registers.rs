//! Emits one marker type per register, with its `RegisterInfo` and value type.

use super::protocols::variant;
use super::*;

fn register_doc(drive: &DriveIr, register: &RegisterIr) -> Vec<String> {
    let mut lines = vec![
        format!(
            " **{} — {}** ({})",
            register.code, register.name, register.name_zh
        ),
        String::new(),
    ];
    let mut facts = vec![format!("address `{}h`", register.address_hex)];
    if !register.unit.is_empty() {
        facts.push(format!(
            "unit {} in steps of {}",
            register.unit, register.scale
        ));
    } else if (register.scale - 1.0).abs() > f64::EPSILON {
        facts.push(format!("steps of {}", register.scale));
    }
    facts.push(format!("range {}", register.range_display));
    facts.push(format!("default {}", register.default_display));
    facts.push(register.access.clone());
    if register.ram_only {
        facts.push("RAM only (no persistent write)".into());
    }
    facts.push(if register.writable_while_running {
        "writable while running".into()
    } else {
        "not writable while running".into()
    });
    if register.panel_only {
        facts.push("effective only when set from the panel".into());
    }
    if register.takes_effect == "after_reset" {
        facts.push("takes effect after a reset".into());
    }
    lines.push(format!(" {}.", facts.join(", ")));
    for text in [&register.description, &register.note] {
        if !text.is_empty() {
            lines.push(String::new());
            lines.push(format!(" {text}"));
        }
    }
    lines.push(String::new());
    lines.push(format!(
        " Source: `{}`, section {}.",
        drive.manual, register.source
    ));
    lines
}

pub(super) fn registers_module(drive: &DriveIr) -> TokenStream {
    let mut items = Vec::new();
    let mut all = Vec::new();
    for register in &drive.registers {
        let name = ident(&register.type_name);
        let docs = register_doc(drive, register);
        let value = value_type(&register.value_kind);
        let address = hex_u16(register.address);
        let (id, code, title, name_zh) = (
            &register.id,
            &register.code,
            &register.name,
            &register.name_zh,
        );
        let unit = ident(&register.unit_variant);
        let scale = f64_literal(register.scale);
        let signed = register.signed;
        let (raw_min, raw_max) = (register.raw_min, register.raw_max);
        let data_type = variant(
            "DataType",
            match register.data_type.as_str() {
                "double_word" => vfd_runtime::DataType::DoubleWord,
                "bit" => vfd_runtime::DataType::Bit,
                "text" => vfd_runtime::DataType::Text,
                _ => vfd_runtime::DataType::Word,
            },
        );
        let space = variant(
            "Space",
            if register.space == "coil" {
                vfd_runtime::Space::Coil
            } else {
                vfd_runtime::Space::Parameter
            },
        );
        let array_len = register.array_len;
        let bound = |b: &Option<String>| match b {
            Some(name) => quote!(Some(#name)),
            None => quote!(None),
        };
        let (min_bound, max_bound) = (bound(&register.min_bound), bound(&register.max_bound));
        let access = match register.access.as_str() {
            "read-only" => quote!(ReadOnly),
            "write-only" => quote!(WriteOnly),
            _ => quote!(ReadWrite),
        };
        let (ram_only, while_running, panel_only) = (
            register.ram_only,
            register.writable_while_running,
            register.panel_only,
        );
        let mut methods = vec![quote! {
            /// The register's address.
            pub const ADDRESS: u16 = #address;
            /// A request reading this register.
            pub fn read() -> ::vfd_runtime::Request {
                ::vfd_runtime::Request::read::<Self>()
            }
        }];
        if register.array_len > 0 {
            let len = register.array_len;
            let doc = format!(
                " A request reading element `index` (0 to {}) of this array parameter.",
                len - 1
            );
            methods.push(quote! {
                /// Number of array elements.
                pub const ARRAY_LEN: u8 = #len;
                #[doc = #doc]
                pub fn read_at(index: u16) -> ::core::result::Result<::vfd_runtime::Request, ::vfd_runtime::ValueError> {
                    ::vfd_runtime::Request::read::<Self>().at_index(index)
                }
            });
        }
        let mut marker_impls = Vec::new();
        if register.writable && register.array_len > 0 {
            methods.push(quote! {
                /// A request writing `value` to element `index` of this array parameter, in RAM only.
                pub fn write_ram_at(index: u16, value: #value) -> ::core::result::Result<::vfd_runtime::Request, ::vfd_runtime::ValueError> {
                    ::vfd_runtime::Request::write_ram::<Self>(value)?.at_index(index)
                }
            });
        }
        if register.writable {
            methods.push(quote! {
                /// A request writing `value` to RAM only (lost at power-off). Refuses values outside the range.
                pub fn write_ram(value: #value) -> ::core::result::Result<::vfd_runtime::Request, ::vfd_runtime::ValueError> {
                    ::vfd_runtime::Request::write_ram::<Self>(value)
                }
            });
            marker_impls.push(quote!(impl ::vfd_runtime::Writable for #name {}));
            if !register.ram_only {
                methods.push(quote! {
                    /// A request writing `value` to RAM and EEPROM (persistent). EEPROM wears out
                    /// after a limited number of writes: prefer [`Self::write_ram`] for values that change often.
                    pub fn write_persistent(value: #value) -> ::core::result::Result<::vfd_runtime::Request, ::vfd_runtime::ValueError> {
                        ::vfd_runtime::Request::write_persistent::<Self>(value)
                    }
                });
                marker_impls.push(quote!(impl ::vfd_runtime::Persistable for #name {}));
            }
        }
        items.push(quote! {
            #(#[doc = #docs])*
            #[derive(Debug, Clone, Copy)]
            pub struct #name;

            impl #name {
                #(#methods)*
            }

            impl ::vfd_runtime::Register for #name {
                const INFO: &'static ::vfd_runtime::RegisterInfo = &::vfd_runtime::RegisterInfo {
                    address: #address,
                    id: #id,
                    code: #code,
                    name: #title,
                    name_zh: #name_zh,
                    unit: ::vfd_runtime::units::Unit::#unit,
                    scale: #scale,
                    signed: #signed,
                    raw_min: #raw_min,
                    raw_max: #raw_max,
                    min_bound: #min_bound,
                    max_bound: #max_bound,
                    access: ::vfd_runtime::Access::#access,
                    ram_only: #ram_only,
                    writable_while_running: #while_running,
                    panel_only: #panel_only,
                    data_type: #data_type,
                    space: #space,
                    array_len: #array_len,
                };
                type Value = #value;
            }

            #(#marker_impls)*
        });
        all.push(quote!(<#name as ::vfd_runtime::Register>::INFO));
    }
    let count = all.len();
    quote! {
        /// One type per register; each implements [`vfd_runtime::Register`].
        pub mod registers {
            #(#items)*

            /// Every register, in the manual's order.
            pub static ALL: [&::vfd_runtime::RegisterInfo; #count] = [#(#all),*];

            /// The register at `address`.
            pub fn by_address(address: u16) -> ::core::option::Option<&'static ::vfd_runtime::RegisterInfo> {
                ALL.iter().copied().find(|info| info.address == address)
            }

            /// The register with this manual code (`FH`, case-insensitive) or identifier (`maximum_frequency`).
            pub fn by_name(name: &str) -> ::core::option::Option<&'static ::vfd_runtime::RegisterInfo> {
                ALL.iter().copied().find(|info| info.code == name || info.id == name)
                    .or_else(|| ALL.iter().copied().find(|info| info.code.eq_ignore_ascii_case(name)))
            }
        }
    }
}
