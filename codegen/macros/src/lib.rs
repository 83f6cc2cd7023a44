//! Proc-macro front end of `vfd-codegen`: `include_drive!("path/to/drive.yaml")` expands
//! to the drive's typed module, exactly as the build-script API would generate it.
//!
//! The path is relative to the calling crate's `Cargo.toml`. Problems in the description
//! become a compile error at the macro call listing every message with file:line:column.
//! The expansion `include_bytes!`s its inputs, so editing the YAML recompiles the caller.
#![warn(missing_docs)]

use proc_macro::TokenStream;
use quote::quote;
use std::path::PathBuf;
use syn::{parse_macro_input, LitStr};

/// Expands to `pub mod <drive id> { ... }` for the drive file at the given path.
///
/// ```ignore
/// vfd_macros::include_drive!("drives/yd1000.yaml");
/// let request = yd1000::registers::FrequencyCommand::write_ram(vfd_runtime::units::Hertz(60.0));
/// ```
#[proc_macro]
pub fn include_drive(input: TokenStream) -> TokenStream {
    let literal = parse_macro_input!(input as LitStr);
    let manifest = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_default();
    let path = manifest.join(literal.value());
    match vfd_codegen::compile(&path, None) {
        Ok(drive) => {
            let module = vfd_codegen::emit::rust::drive_module(&drive);
            let inputs: Vec<String> = vfd_codegen::inputs_of(&drive, None)
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
