//! Emits one enum per code table, and the drive's error-code enum, through one function:
//! a `#[repr(u16)]` enum, its `TABLE` of codes with English and Chinese names, and lookups
//! that search the table (so the code per value is its variant and its table row).

use super::bake::int_literal;
use super::*;

/// One value of an enum to emit.
struct Value<'a> {
    variant: &'a str,
    code: u16,
    doc: String,
    name: &'a str,
    name_zh: &'a str,
}

pub(super) fn codes_module(drive: &DriveIr) -> TokenStream {
    let items: Vec<TokenStream> = drive
        .code_tables
        .iter()
        .map(|t| code_table_tokens(drive, t))
        .collect();
    let values = drive.code_tables.iter().any(|t| t.exhaustive).then(|| {
        quote!(
            use ::vfd_runtime::{RegisterInfo, RegisterValue, ValueError};
        )
    });
    let infos = drive.code_tables.iter().map(code_table_info);
    let info_import = (!drive.code_tables.is_empty()).then(|| {
        quote!(
            use ::vfd_runtime::info::{CodeInfo, CodeTableInfo};
        )
    });
    quote! {
        /// Code tables (enumerations) of the manual.
        pub mod codes {
            #values
            #info_import
            #(#items)*
            #(#infos)*
        }
    }
}

/// The name of the const holding a code table or bit-field layout as data (`PARITY`).
pub(super) fn info_const(id: &str) -> Ident {
    format_ident!("{}", id.to_ascii_uppercase())
}

/// A code table as data (`CodeTableInfo`), for tools that work with any drive.
fn code_table_info(table: &CodeTableIr) -> TokenStream {
    let name = info_const(&table.id);
    let (id, en, zh_name, exhaustive) = (
        str_literal(&table.id),
        str_literal(&table.name),
        str_literal(&table.name_zh),
        table.exhaustive,
    );
    let values = table.values.iter().map(|v| {
        let (value, id, en, zh_name) = (
            int_literal(v.value),
            str_literal(&v.id),
            str_literal(&v.name),
            str_literal(&v.name_zh),
        );
        quote!(CodeInfo { value: #value, id: #id, name: #en, name_zh: #zh_name })
    });
    let doc = doc_text(format!("The code table `{}` as data.", table.id));
    quote! {
        #[doc = #doc]
        pub const #name: CodeTableInfo = CodeTableInfo {
            id: #id,
            name: #en,
            name_zh: #zh_name,
            exhaustive: #exhaustive,
            values: &[#(#values),*],
        };
    }
}

/// The enum, its `TABLE`, `code`, `from_code`, `name`, `name_zh` and `Display`.
fn code_enum(name: &Ident, docs: &[String], values: &[Value<'_>]) -> TokenStream {
    let docs = doc_texts(docs);
    let variants = values.iter().map(|v| {
        let (variant, code, doc) = (ident(v.variant), int_literal(v.code), doc_text(&v.doc));
        quote! {
            #[doc = #doc]
            #variant = #code
        }
    });
    let rows = values.iter().map(|v| {
        let (variant, code, en, zh) = (ident(v.variant), int_literal(v.code), v.name, v.name_zh);
        quote!((Self::#variant, #code, #en, #zh))
    });
    let count = int_literal(values.len());
    quote! {
        #(#[doc = #docs])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(u16)]
        pub enum #name {
            #(#variants),*
        }

        impl #name {
            /// Every code with its number, English and Chinese name (empty when the manual
            /// gives none), in the manual's order.
            pub const TABLE: [::vfd_runtime::codes::CodeRow<Self>; #count] = [#(#rows),*];
            /// The raw code.
            pub const fn code(self) -> u16 {
                self as u16
            }
            /// The code's entry, if the table has it.
            pub const fn from_code(code: u16) -> Option<Self> {
                ::vfd_runtime::codes::find(&Self::TABLE, code)
            }
            /// English name.
            pub const fn name(self) -> &'static str {
                ::vfd_runtime::codes::names(&Self::TABLE, self as u16).0
            }
            /// The manual's Chinese name (empty when the manual gives none).
            pub const fn name_zh(self) -> &'static str {
                ::vfd_runtime::codes::names(&Self::TABLE, self as u16).1
            }
        }

        impl ::core::fmt::Display for #name {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                f.write_str(self.name())
            }
        }
    }
}

fn code_table_tokens(drive: &DriveIr, table: &CodeTableIr) -> TokenStream {
    let name = ident(&table.type_name);
    let mut docs = vec![format!("**{}**{}", table.name, zh(&table.name_zh))];
    if !table.note.is_empty() {
        docs.push(String::new());
        docs.push(table.note.clone());
    }
    docs.push(String::new());
    docs.push(format!(
        "Source: {}, section {}.",
        drive.manual_cited(),
        table.source
    ));
    let values: Vec<Value<'_>> = table
        .values
        .iter()
        .map(|v| Value {
            variant: &v.variant,
            code: v.value,
            doc: format!("{:04X}h = {}{}", v.value, v.name, zh(&v.name_zh)),
            name: &v.name,
            name_zh: &v.name_zh,
        })
        .collect();
    let code_enum = code_enum(&name, &docs, &values);
    let id = &table.id;
    let register_value = table.exhaustive.then(|| {
        quote! {
            impl RegisterValue for #name {
                fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
                    ::vfd_runtime::units::scaled_to_raw(f64::from(self.code()), info)
                }
                fn from_raw(raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError> {
                    u16::try_from(raw)
                        .ok()
                        .and_then(Self::from_code)
                        .ok_or(ValueError::UnknownCode { register: info, table: #id, raw })
                }
            }
        }
    });
    quote! {
        #code_enum
        #register_value
    }
}

pub(super) fn error_code_enum(drive: &DriveIr) -> TokenStream {
    let values: Vec<Value<'_>> = drive
        .error_codes
        .codes
        .iter()
        .map(|c| Value {
            variant: &c.variant,
            code: c.code,
            doc: format!(
                "{:04X}h {}{}: {}",
                c.code,
                c.name,
                zh(&c.name_zh),
                c.meaning
            ),
            name: &c.name,
            name_zh: &c.name_zh,
        })
        .collect();
    let docs = [format!(
        "Error codes of the drive's error replies (manual section {}).",
        drive.error_codes.source
    )];
    let name = ident("ErrorCode");
    let code_enum = code_enum(&name, &docs, &values);
    quote! {
        #code_enum

        impl ErrorCode {
            /// The manual's entry: names and meaning.
            pub fn info(self) -> Option<&'static ::vfd_runtime::ErrorCodeInfo> {
                protocols::ERROR_CODES.iter().find(|entry| entry.code == self as u16)
            }
        }
    }
}
