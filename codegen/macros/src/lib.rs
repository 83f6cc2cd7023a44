//! Proc-macro front end of `vfd-codegen`: `include_drive!("path/to/drive.yaml")` expands
//! to the drive's typed module, exactly as the build-script API would generate it.
//!
//! The path is relative to the calling crate's `Cargo.toml`; protocol files are looked up
//! in `protocols/` next to the drive file unless `protocols = "dir"` names another folder
//! (also relative to `Cargo.toml`). Problems in the description
//! become a compile error at the macro call listing every message with file:line:column.
//! The expansion `include_bytes!`s its inputs, so editing the YAML recompiles the caller.
#![warn(missing_docs)]

use proc_macro::TokenStream;
use quote::quote;
use std::path::PathBuf;
use syn::parse::{Parse, ParseStream};
use syn::{parse_macro_input, Ident, LitStr, Token};

/// The macro's arguments: `"drive.yaml"` and optionally `, protocols = "dir"`.
struct Args {
    drive: LitStr,
    protocols: Option<LitStr>,
}

impl Parse for Args {
    fn parse(input: ParseStream<'_>) -> syn::Result<Self> {
        let drive: LitStr = input.parse()?;
        let mut protocols = None;
        if input.parse::<Option<Token![,]>>()?.is_some() && !input.is_empty() {
            let key: Ident = input.parse()?;
            if key != "protocols" {
                return Err(syn::Error::new(
                    key.span(),
                    "expected `protocols = \"dir\"` (the folder holding the protocol files)",
                ));
            }
            input.parse::<Token![=]>()?;
            protocols = Some(input.parse()?);
            input.parse::<Option<Token![,]>>()?;
        }
        if !input.is_empty() {
            return Err(input.error("unexpected tokens after the arguments"));
        }
        Ok(Args { drive, protocols })
    }
}

/// Expands to `pub mod <drive id> { ... }` for the drive file at the given path.
///
/// ```ignore
/// vfd_macros::include_drive!("drives/yd1000.yaml");
/// let request = yd1000::registers::FrequencyCommand::write_ram(vfd_runtime::units::Hertz(60.0));
///
/// // Protocol files in another folder than `protocols/` next to the drive file:
/// mod mine { vfd_macros::include_drive!("my_drive.yaml", protocols = "../shared/protocols"); }
/// ```
#[proc_macro]
pub fn include_drive(input: TokenStream) -> TokenStream {
    let Args {
        drive: literal,
        protocols,
    } = parse_macro_input!(input as Args);
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_default();
    let path = manifest.join(literal.value());
    let protocols = protocols.map(|dir| manifest.join(dir.value()));
    match vfd_codegen::compile(&path, protocols.as_deref()) {
        Ok(drive) => {
            let module = vfd_codegen::rust_tokens(&drive);
            let inputs: Vec<String> = vfd_codegen::inputs_of(&drive, protocols.as_deref())
                .iter()
                .map(|p| {
                    p.canonicalize()
                        .unwrap_or_else(|_| p.clone())
                        .display()
                        .to_string()
                })
                .collect();
            quote! {
                #module
                const _: () = { #( let _ = include_bytes!(#inputs); )* };
            }
            .into()
        }
        Err(diagnostics) => syn::Error::new(literal.span(), diagnostics.to_string())
            .to_compile_error()
            .into(),
    }
}
