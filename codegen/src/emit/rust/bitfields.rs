//! Emits one word type per bit-field layout, with an accessor and a builder per field.

use super::bake::int_literal;
use super::*;

pub(super) fn bits_module(drive: &DriveIr) -> TokenStream {
    let items: Vec<TokenStream> = drive
        .bitfields
        .iter()
        .map(|b| bitfield_tokens(drive, b))
        .collect();
    let imports = (!items.is_empty()).then(|| {
        quote! {
            use ::core::fmt;
            use ::vfd_runtime::bits::{self, BitWord};
            use ::vfd_runtime::info::{BitFieldInfo, BitWordInfo};
            use ::vfd_runtime::{RegisterInfo, RegisterValue, ValueError};
        }
    });
    let infos = drive.bitfields.iter().map(bitfield_info);
    quote! {
        /// Bit-field words with named accessors and builders.
        pub mod bits {
            #imports
            #(#items)*
            #(#infos)*
        }
    }
}

/// A bit-field layout as data (`BitWordInfo`), for tools that work with any drive.
fn bitfield_info(bitfield: &BitfieldIr) -> TokenStream {
    let name = super::code_tables::info_const(&bitfield.id);
    let (id, en, zh_name) = (
        str_literal(&bitfield.id),
        str_literal(&bitfield.name),
        str_literal(&bitfield.name_zh),
    );
    let fields = bitfield.fields.iter().filter(|f| !f.reserved).map(|f| {
        let (id, en, zh_name, mask, zero, one) = (
            str_literal(&f.id),
            str_literal(&f.name),
            str_literal(&f.name_zh),
            hex_u16(f.mask()),
            str_literal(&f.zero),
            str_literal(&f.one),
        );
        let codes = match &f.code_table {
            Some(table) => {
                let table = super::code_tables::info_const(table);
                quote!(Some(&super::codes::#table))
            }
            None => quote!(None),
        };
        quote!(BitFieldInfo { id: #id, name: #en, name_zh: #zh_name, mask: #mask, zero: #zero, one: #one, codes: #codes })
    });
    let doc = doc_text(format!("The bit-field layout `{}` as data.", bitfield.id));
    quote! {
        #[doc = #doc]
        pub const #name: BitWordInfo = BitWordInfo {
            id: #id,
            name: #en,
            name_zh: #zh_name,
            fields: &[#(#fields),*],
        };
    }
}

fn bitfield_tokens(drive: &DriveIr, bitfield: &BitfieldIr) -> TokenStream {
    let name = ident(&bitfield.type_name);
    let mut docs = vec![format!("**{}**{}", bitfield.name, zh(&bitfield.name_zh))];
    if !bitfield.registers.is_empty() {
        docs.push(String::new());
        docs.push(format!(
            "Value of register(s) {}.",
            bitfield.registers.join(", ")
        ));
    }
    if !bitfield.note.is_empty() {
        docs.push(String::new());
        docs.push(bitfield.note.clone());
    }
    docs.push(String::new());
    docs.push(format!(
        "Source: {}, section {}.",
        drive.manual_cited(),
        bitfield.source
    ));
    let docs = doc_texts(&docs);
    let reserved = hex_u16(bitfield.reserved_mask());
    let mut consts = Vec::new();
    let mut accessors = Vec::new();
    let mut names = Vec::new();
    for field in bitfield.fields.iter().filter(|f| !f.reserved) {
        let mask = hex_u16(field.mask());
        let mask_name = format_ident!("{}", field.id.to_ascii_uppercase());
        let getter = ident(&field.method);
        let setter = format_ident!("with_{}", field.id);
        let id = &field.id;
        let span = if field.width == 1 {
            format!("Bit {}", field.lsb)
        } else {
            format!("Bits {}:{}", field.lsb + field.width - 1, field.lsb)
        };
        let mut doc = format!("{span}: {}{}", field.name, zh(&field.name_zh));
        if !field.zero.is_empty() || !field.one.is_empty() {
            doc.push_str(&format!(
                ". 0: {}{}; 1: {}{}",
                field.zero,
                zh(&field.zero_zh),
                field.one,
                zh(&field.one_zh)
            ));
        }
        if !field.note.is_empty() {
            doc.push_str(&format!(". {}", field.note));
        }
        doc.push('.');
        let doc = doc_text(doc);
        let setter_doc = doc_text(format!(
            "The word with `{id}` ({span}) set to the value given."
        ));
        consts.push(quote! {
            #[doc = #doc]
            pub const #mask_name: u16 = #mask;
        });
        names.push(quote!((#id, Self::#mask_name)));
        if field.width == 1 {
            accessors.push(quote! {
                #[doc = #doc]
                pub const fn #getter(self) -> bool {
                    bits::flag(self.0, Self::#mask_name)
                }
                #[doc = #setter_doc]
                #[must_use]
                pub const fn #setter(self, on: bool) -> Self {
                    Self(bits::with_flag(self.0, Self::#mask_name, on))
                }
            });
        } else {
            accessors.push(quote! {
                #[doc = #doc]
                pub const fn #getter(self) -> u16 {
                    bits::field(self.0, Self::#mask_name)
                }
                #[doc = #setter_doc]
                /// Bits of `value` beyond the field's width are dropped.
                #[must_use]
                pub const fn #setter(self, value: u16) -> Self {
                    Self(bits::with_field(self.0, Self::#mask_name, value))
                }
            });
        }
    }
    let field_count = int_literal(names.len());
    quote! {
        #(#[doc = #docs])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        pub struct #name(pub u16);

        impl #name {
            /// Bits the manual marks reserved.
            pub const RESERVED: u16 = #reserved;
            #(#consts)*
            /// Named fields and their masks, from the most significant bit down.
            pub const FIELDS: [(&'static str, u16); #field_count] = [#(#names),*];
            /// All bits clear.
            pub const fn new() -> Self {
                Self(0)
            }
            /// The raw word.
            pub const fn bits(self) -> u16 {
                self.0
            }
            /// Whether any reserved bit is set.
            pub const fn has_reserved_bits(self) -> bool {
                bits::flag(self.0, Self::RESERVED)
            }
            #(#accessors)*
        }

        impl BitWord for #name {
            const FIELDS: &'static [(&'static str, u16)] = &Self::FIELDS;
            fn from_bits(bits: u16) -> Self {
                Self(bits)
            }
            fn bits(self) -> u16 {
                self.0
            }
        }

        impl RegisterValue for #name {
            fn to_raw(&self, info: &'static RegisterInfo) -> Result<u32, ValueError> {
                bits::to_raw(*self, info)
            }
            fn from_raw(raw: u32, info: &'static RegisterInfo) -> Result<Self, ValueError> {
                bits::from_raw(raw, info)
            }
        }

        impl fmt::Display for #name {
            /// The fields that are set (`run | command_enabled`), or `-` when none is.
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                bits::fmt_fields(*self, f)
            }
        }
    }
}
