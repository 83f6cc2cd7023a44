//! Emits one enum per code table, and the drive's error-code enum.

use super::bake::int_literal;
use super::*;

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
    let imports = (!items.is_empty()).then(|| quote!(use ::core::fmt; #values));
    quote! {
        /// Code tables (enumerations) of the manual.
        pub mod codes {
            #imports
            #(#items)*
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
        "Source: `{}`, section {}.",
        drive.manual, table.source
    ));
    let docs = doc_texts(&docs);
    let variants: Vec<TokenStream> = table
        .values
        .iter()
        .map(|v| {
            let variant = ident(&v.variant);
            let value = int_literal(v.value);
            let doc = doc_text(format!("{:04X}h = {}{}", v.value, v.name, zh(&v.name_zh)));
            quote! {
                #[doc = #doc]
                #variant = #value
            }
        })
        .collect();
    let arms_from: Vec<TokenStream> = table
        .values
        .iter()
        .map(|v| {
            let variant = ident(&v.variant);
            let value = int_literal(v.value);
            quote!(#value => Some(Self::#variant))
        })
        .collect();
    let arms_name: Vec<TokenStream> = table
        .values
        .iter()
        .map(|v| {
            let variant = ident(&v.variant);
            let (en, cn) = (&v.name, &v.name_zh);
            quote!(Self::#variant => (#en, #cn))
        })
        .collect();
    let all: Vec<TokenStream> = table
        .values
        .iter()
        .map(|v| {
            let variant = ident(&v.variant);
            quote!(Self::#variant)
        })
        .collect();
    let count = int_literal(all.len());
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
        #(#[doc = #docs])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(u16)]
        pub enum #name {
            #(#variants),*
        }

        impl #name {
            /// Every code, in the manual's order.
            pub const ALL: [Self; #count] = [#(#all),*];
            /// The raw code.
            pub const fn code(self) -> u16 {
                self as u16
            }
            /// The code's entry, if the table has it.
            pub const fn from_code(code: u16) -> Option<Self> {
                match code {
                    #(#arms_from,)*
                    _ => None,
                }
            }
            /// English name.
            pub const fn name(self) -> &'static str {
                self.names().0
            }
            /// The manual's Chinese name (empty when the manual gives none).
            pub const fn name_zh(self) -> &'static str {
                self.names().1
            }
            const fn names(self) -> (&'static str, &'static str) {
                match self {
                    #(#arms_name),*
                }
            }
        }

        impl fmt::Display for #name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }

        #register_value
    }
}

pub(super) fn error_code_enum(drive: &DriveIr) -> TokenStream {
    let variants: Vec<TokenStream> = drive
        .error_codes
        .codes
        .iter()
        .map(|c| {
            let variant = ident(&c.variant);
            let value = int_literal(c.code);
            let doc = doc_text(format!(
                "{:04X}h {}{}: {}",
                c.code,
                c.name,
                zh(&c.name_zh),
                c.meaning
            ));
            quote! {
                #[doc = #doc]
                #variant = #value
            }
        })
        .collect();
    let arms: Vec<TokenStream> = drive
        .error_codes
        .codes
        .iter()
        .map(|c| {
            let variant = ident(&c.variant);
            let value = int_literal(c.code);
            quote!(#value => Some(Self::#variant))
        })
        .collect();
    let info_arms: Vec<TokenStream> = drive
        .error_codes
        .codes
        .iter()
        .enumerate()
        .map(|(index, c)| {
            let variant = ident(&c.variant);
            let index = int_literal(index);
            quote!(Self::#variant => &protocols::ERROR_CODES[#index])
        })
        .collect();
    let doc = doc_text(format!(
        "Error codes of the drive's error replies (manual section {}).",
        drive.error_codes.source
    ));
    quote! {
        #[doc = #doc]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(u16)]
        pub enum ErrorCode {
            #(#variants),*
        }

        impl ErrorCode {
            /// The code's variant, if the manual lists it.
            pub const fn from_code(code: u16) -> ::core::option::Option<Self> {
                match code {
                    #(#arms,)*
                    _ => None,
                }
            }
            /// The raw code.
            pub const fn code(self) -> u16 {
                self as u16
            }
            /// The manual's entry: names and meaning.
            pub fn info(self) -> &'static ::vfd_runtime::ErrorCodeInfo {
                match self {
                    #(#info_arms),*
                }
            }
        }
    }
}
