//! Stage 4c: emits golden-frame tests from a drive's examples, one `#[test]` per example,
//! calling the checks in `vfd_runtime::testing` (the runtime's `testing` feature), so they
//! compile in any crate that depends on `vfd-runtime` with that feature.

use crate::ir::{DriveIr, ExampleIr, ExpectIr, FrameIr, ValueKind};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

/// Golden tests for every example, bit-field example and value example of `drive`.
/// `drive_path` is the path of the generated drive module as seen from the tests, e.g.
/// `crate::yd1000` or `my_drives::yd1000`.
pub fn golden_tests(drive: &DriveIr, drive_path: &str) -> TokenStream {
    let root: syn::Path = syn::parse_str(drive_path).unwrap_or_else(|_| syn::parse_quote!(crate));
    let mut tests = Vec::new();
    for example in &drive.examples {
        tests.push(example_test(&root, example));
    }
    for bitfield in &drive.bitfields {
        let ty = Ident::new(&bitfield.type_name, Span::call_site());
        for (index, example) in bitfield.examples.iter().enumerate() {
            let name = format_ident!("bits_{}_example_{}", bitfield.id, index + 1);
            let value = example.value;
            let setters = example.set.iter().map(|id| format_ident!("with_{}", id));
            let getters = example
                .set
                .iter()
                .map(|id| Ident::new(&crate::naming::method_name(id), Span::call_site()));
            let doc = format!(
                " {} (manual section {}).",
                example.description, example.source
            );
            tests.push(quote! {
                #[doc = #doc]
                #[test]
                fn #name() {
                    let built = #root::bits::#ty::new()#(.#setters(true))*;
                    assert_eq!(built.bits(), #value, "builder gives {:04X}h", built.bits());
                    let read = #root::bits::#ty(#value);
                    #(assert!(read.#getters(), "{} should be set in {:04X}h", stringify!(#getters), #value);)*
                    assert!(!read.has_reserved_bits());
                }
            });
        }
    }
    for (index, example) in drive.value_examples.iter().enumerate() {
        let name = format_ident!(
            "value_{}_example_{}",
            example.register_code.to_ascii_lowercase(),
            index + 1
        );
        let register = Ident::new(&example.register_type, Span::call_site());
        let value_ty = value_type_at(&example.value_kind, &root);
        let construct = construct_value(&example.value_kind, example.value, &value_ty);
        let raw = example.raw;
        let doc = format!(
            " {} (manual section {}).",
            example.description, example.source
        );
        tests.push(quote! {
            #[doc = #doc]
            #[test]
            fn #name() {
                use ::vfd_runtime::{Register, RegisterValue};
                type R = #root::registers::#register;
                let value = #construct;
                assert_eq!(value.to_raw(R::INFO).unwrap(), #raw, "the manual's value encodes to its raw word");
                // Scales such as 100/16384 % are lossy: decoding then encoding must give the raw word back.
                let decoded = <R as Register>::Value::from_raw(#raw, R::INFO).unwrap();
                assert_eq!(decoded.to_raw(R::INFO).unwrap(), #raw, "decoded {decoded:?} re-encodes");
            }
        });
    }
    quote! {
        #(#tests)*
    }
}

/// The value type of a register, as a path usable outside the drive module.
fn value_type_at(kind: &ValueKind, root: &syn::Path) -> TokenStream {
    crate::emit::rust::value_type_at(kind, &quote!(#root))
}

fn construct_value(kind: &ValueKind, value: f64, ty: &TokenStream) -> TokenStream {
    let float = Literal::f64_unsuffixed(value);
    match kind {
        ValueKind::Quantity(_) => quote!(#ty(#float)),
        ValueKind::Scaled => quote!(#float),
        ValueKind::Raw => {
            let v = Literal::u16_unsuffixed(value as u16);
            quote!(#v)
        }
        ValueKind::RawSigned => {
            let v = Literal::i16_unsuffixed(value as i16);
            quote!(#v)
        }
        ValueKind::RawDouble => {
            let v = Literal::u32_unsuffixed(value as u32);
            quote!(#v)
        }
        ValueKind::RawSignedDouble => {
            let v = Literal::i32_unsuffixed(value as i32);
            quote!(#v)
        }
        ValueKind::Text => quote!(::std::string::String::new()),
        ValueKind::CodeTable(_) | ValueKind::Bitfield(_) => {
            let v = Literal::u32_unsuffixed(value as u32);
            quote!(<#ty as ::vfd_runtime::RegisterValue>::from_raw(#v, R::INFO).unwrap())
        }
    }
}

fn expect_tokens(expect: &ExpectIr) -> TokenStream {
    fn option<T: quote::ToTokens>(value: Option<T>) -> TokenStream {
        match value {
            Some(value) => quote!(Some(#value)),
            None => quote!(None),
        }
    }
    let address = option(expect.address);
    let code = option(expect.code);
    let register = option(expect.register.map(|r| r as u16));
    let wire_register = option(if expect.register.is_none() {
        expect.wire_register.map(|r| r as u16)
    } else {
        None
    });
    let index = option(expect.index.map(|i| i as u16));
    let data = option(expect.data);
    let error_code = option(expect.error_code.map(|e| e as u16));
    let process = match expect.process {
        Some([first, second]) => {
            let (first, second) = (first as u16, second as u16);
            quote!(Some([#first, #second]))
        }
        None => quote!(None),
    };
    let text = option(expect.text.as_deref());
    let tripped = expect.tripped;
    quote! {
        ::vfd_runtime::testing::Expect {
            address: #address,
            code: #code,
            register: #register,
            wire_register: #wire_register,
            index: #index,
            data: #data,
            error_code: #error_code,
            process: #process,
            text: #text,
            tripped: #tripped,
        }
    }
}

fn bytes_tokens(bytes: &[u8]) -> TokenStream {
    let bytes = bytes.iter().map(|b| {
        format!("0x{b:02X}")
            .parse::<TokenStream>()
            .unwrap_or_else(|_| quote!(#b))
    });
    quote!(&[#(#bytes),*])
}

fn frame_checks(protocol: &TokenStream, frame: &FrameIr, request: bool) -> TokenStream {
    let bytes = bytes_tokens(&frame.bytes);
    let expect = expect_tokens(&frame.expect);
    let check = if request {
        quote!(::vfd_runtime::testing::request_round_trips(#protocol, #bytes, #expect);)
    } else {
        quote!(::vfd_runtime::testing::reply_round_trips(#protocol, #bytes, #expect);)
    };
    let printed = frame.printed.as_ref().map(|printed| {
        let bytes = bytes_tokens(&printed.bytes);
        let reason = &printed.rejected_as;
        let direction = if request { quote!(Request) } else { quote!(Reply) };
        quote! {
            ::vfd_runtime::testing::printed_is_rejected(#protocol, ::vfd_runtime::testing::Direction::#direction, #bytes, #reason);
        }
    });
    quote! { #check #printed }
}

fn example_test(root: &syn::Path, example: &ExampleIr) -> TokenStream {
    let name = format_ident!("example_{}", example.id);
    let protocol_name = Ident::new(&example.protocol_const, Span::call_site());
    let protocol = quote!(&#root::protocols::#protocol_name);
    let mut body = Vec::new();
    if let Some(frame) = &example.request {
        body.push(frame_checks(&protocol, frame, true));
    }
    if let Some(frame) = &example.reply {
        body.push(frame_checks(&protocol, frame, false));
    }
    if let (Some(value), Some(register), Some(kind)) =
        (example.value, &example.register_type, &example.value_kind)
    {
        let register = Ident::new(register, Span::call_site());
        let ty = value_type_at(kind, root);
        let construct = construct_value(kind, value, &ty);
        let data = example
            .reply
            .as_ref()
            .and_then(|f| f.expect.data)
            .or(example.request.as_ref().and_then(|f| f.expect.data))
            .unwrap_or(0);
        body.push(quote! {
            {
                use ::vfd_runtime::{Register, RegisterValue};
                type R = #root::registers::#register;
                let value = #construct;
                assert_eq!(<R as Register>::Value::from_raw(#data, R::INFO).unwrap(), value, "decoded value");
            }
        });
        if let Some(request) = &example.request {
            let bytes = bytes_tokens(&request.bytes);
            let build = match request.expect.command_kind.as_deref() {
                Some("write_ram") if example.register_writable => Some(quote! {
                    let request = #root::registers::#register::write_ram(#construct).expect("the manual's value is within range");
                }),
                Some("write_persistent") if example.register_persistable => Some(quote! {
                    let request = #root::registers::#register::write_persistent(#construct).expect("the manual's value is within range");
                }),
                Some("read") => Some(quote! {
                    let request = #root::registers::#register::read();
                }),
                _ => None,
            };
            let at_index = match request.expect.index {
                Some(index) if index > 0 || example.register_array => {
                    let index = index as u16;
                    quote!(let request = request.at_index(#index).expect("the manual's index is within the array");)
                }
                _ => quote!(),
            };
            if let Some(build) = build {
                body.push(quote! {
                    {
                        #build
                        #at_index
                        ::vfd_runtime::testing::typed_request_encodes(#protocol, &request, #bytes);
                    }
                });
            }
        }
    }
    let doc = format!(
        " {} ({}); manual section {}.",
        example.description, example.description_zh, example.source
    );
    quote! {
        #[doc = #doc]
        #[test]
        fn #name() {
            #(#body)*
        }
    }
}
