//! Emits one word type per bit-field layout, with an accessor and a builder per field.

use super::*;

pub(super) fn bits_module(drive: &DriveIr) -> TokenStream {
    let items: Vec<TokenStream> = drive
        .bitfields
        .iter()
        .map(|b| bitfield_tokens(drive, b))
        .collect();
    quote! {
        /// Bit-field words with named accessors and builders.
        pub mod bits {
            #(#items)*
        }
    }
}

fn bitfield_tokens(drive: &DriveIr, bitfield: &BitfieldIr) -> TokenStream {
    let name = ident(&bitfield.type_name);
    let mut docs = vec![format!(" **{}** ({})", bitfield.name, bitfield.name_zh)];
    if !bitfield.registers.is_empty() {
        docs.push(String::new());
        docs.push(format!(
            " Value of register(s) {}.",
            bitfield.registers.join(", ")
        ));
    }
    if !bitfield.note.is_empty() {
        docs.push(String::new());
        docs.push(format!(" {}", bitfield.note));
    }
    docs.push(String::new());
    docs.push(format!(
        " Source: `{}`, section {}.",
        drive.manual, bitfield.source
    ));
    let reserved = hex_u16(bitfield.reserved_mask);
    let mut consts = Vec::new();
    let mut accessors = Vec::new();
    let mut names = Vec::new();
    for field in bitfield.fields.iter().filter(|f| !f.reserved) {
        let mask = hex_u16(field.mask);
        let mask_name = format_ident!("{}", field.id.to_ascii_uppercase());
        let getter = ident(&field.method);
        let setter = format_ident!("with_{}", field.id);
        let id = &field.id;
        let mut doc = format!(
            " Bit {}: {} ({})",
            field.bits_label, field.name, field.name_zh
        );
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
        consts.push(quote! {
            #[doc = #doc]
            pub const #mask_name: u16 = #mask;
        });
        names.push(quote!((#id, Self::#mask_name)));
        if field.width == 1 {
            accessors.push(quote! {
                #[doc = #doc]
                pub const fn #getter(self) -> bool {
                    self.0 & #mask != 0
                }
                #[doc = #doc]
                #[must_use]
                pub const fn #setter(self, on: bool) -> Self {
                    if on { Self(self.0 | #mask) } else { Self(self.0 & !#mask) }
                }
            });
        } else {
            let lsb = u32::from(field.lsb);
            let (get, put) = if lsb == 0 {
                (quote!(self.0 & #mask), quote!(value & #mask))
            } else {
                (
                    quote!((self.0 & #mask) >> #lsb),
                    quote!((value << #lsb) & #mask),
                )
            };
            accessors.push(quote! {
                #[doc = #doc]
                pub const fn #getter(self) -> u16 {
                    #get
                }
                #[doc = #doc]
                /// Bits of `value` beyond the field's width are dropped.
                #[must_use]
                pub const fn #setter(self, value: u16) -> Self {
                    Self((self.0 & !#mask) | #put)
                }
            });
        }
    }
    let field_count = names.len();
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
                self.0 & Self::RESERVED != 0
            }
            #(#accessors)*
        }

        impl ::vfd_runtime::RegisterValue for #name {
            fn to_raw(&self, _info: &'static ::vfd_runtime::RegisterInfo) -> ::core::result::Result<u32, ::vfd_runtime::ValueError> {
                Ok(u32::from(self.0))
            }
            /// Keeps the low 16 bits (bit-field words are one word wide).
            fn from_raw(raw: u32, _info: &'static ::vfd_runtime::RegisterInfo) -> ::core::result::Result<Self, ::vfd_runtime::ValueError> {
                Ok(Self(raw as u16))
            }
        }

        impl ::core::fmt::Display for #name {
            /// Lists the fields that are set (`run | command_enabled`), or `-` when none is.
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                let mut first = true;
                for (name, mask) in Self::FIELDS {
                    if self.0 & mask != 0 {
                        if !first {
                            f.write_str(" | ")?;
                        }
                        f.write_str(name)?;
                        first = false;
                    }
                }
                if first {
                    f.write_str("-")?;
                }
                Ok(())
            }
        }
    }
}
