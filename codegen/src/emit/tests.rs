//! Stage 4c: emits golden-frame tests from a drive's examples, one `#[test]` per example,
//! calling the checks in `vfd_runtime::testing` (the runtime's `testing` feature), so they
//! compile in any crate that depends on `vfd-runtime` with that feature.

use crate::emit::rust::bake::{int_literal, Bake};
use crate::ir::{
    DriveIr, ExampleIr, FrameIr, PrintedRejection, RegisterIr, SequenceCallIr, SequenceIr,
    SequenceResultIr, ValueKind,
};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};
use vfd_runtime::meaning::Direction;
use vfd_runtime::CommandKind;

/// Golden tests for every example, bit-field example and value example of `drive`.
/// `drive_path` is the path of the generated drive module as seen from the tests, e.g.
/// `crate::yd1000` or `my_drives::yd1000`.
pub fn golden_tests(drive: &DriveIr, drive_path: &str) -> TokenStream {
    let root: syn::Path = syn::parse_str(drive_path).unwrap_or_else(|_| syn::parse_quote!(crate));
    let mut tests = Vec::new();
    for example in &drive.examples {
        tests.push(example_test(drive, &root, example));
    }
    for sequence in &drive.sequences {
        tests.push(sequence_test(drive, &root, sequence));
    }
    for bitfield in &drive.bitfields {
        let ty = Ident::new(&bitfield.type_name, Span::call_site());
        for (index, example) in bitfield.examples.iter().enumerate() {
            let name = format_ident!("bits_{}_example_{}", bitfield.id, index + 1);
            let value = int_literal(example.value);
            let setters = example.set.iter().map(|id| format_ident!("with_{}", id));
            let getters = example
                .set
                .iter()
                .map(|id| Ident::new(&crate::naming::method_name(id), Span::call_site()));
            let field_setters: Vec<TokenStream> = example
                .fields
                .iter()
                .map(|(id, v)| {
                    let setter = format_ident!("with_{}", id);
                    let v = int_literal(*v);
                    quote!(.#setter(#v))
                })
                .collect();
            let field_checks: Vec<TokenStream> = example
                .fields
                .iter()
                .map(|(id, v)| {
                    let getter = Ident::new(&crate::naming::method_name(id), Span::call_site());
                    let v = int_literal(*v);
                    quote!(assert_eq!(read.#getter(), #v, "{} in {:04X}h", stringify!(#getter), #value);)
                })
                .collect();
            let doc = format!(
                " {} (manual section {}).",
                example.description, example.source
            );
            tests.push(quote! {
                #[doc = #doc]
                #[test]
                fn #name() {
                    let built = #root::bits::#ty::new()#(.#setters(true))*#(#field_setters)*;
                    assert_eq!(built.bits(), #value, "builder gives {:04X}h", built.bits());
                    let read = #root::bits::#ty(#value);
                    #(assert!(read.#getters(), "{} should be set in {:04X}h", stringify!(#getters), #value);)*
                    #(#field_checks)*
                    assert!(!read.has_reserved_bits());
                }
            });
        }
    }
    for (index, example) in drive.value_examples.iter().enumerate() {
        let Some(register) = drive.register(&example.register) else {
            continue;
        };
        // Named by the register's id (checked snake case); a code may hold any character.
        let name = format_ident!("value_{}_example_{}", register.id, index + 1);
        let value_ty = value_type_at(&register.value, &root);
        let construct = construct_value(&register.value, example.value, &value_ty);
        // With a scale selector among the values the example assumes: the register as
        // that selector value makes it.
        let selector = register.scale_by.as_ref().and_then(|scale_by| {
            example
                .given
                .iter()
                .find(|(code, _)| *code == scale_by.register)
                .map(|(_, value)| *value)
        });
        let info = match selector {
            Some(value) => {
                let value = int_literal(value);
                quote!(R::INFO.scaled_for(Some(#value)))
            }
            None => quote!(R::INFO),
        };
        let register = Ident::new(&register.type_name, Span::call_site());
        let raw = int_literal(example.raw);
        let doc = format!(
            " {} (manual section {}).",
            example.description, example.source
        );
        tests.push(quote! {
            #[doc = #doc]
            #[test]
            fn #name() {
                type R = #root::registers::#register;
                let info: &'static ::vfd_runtime::RegisterInfo = #info;
                let value = #construct;
                assert_eq!(value.to_raw(info).unwrap(), #raw, "the manual's value encodes to its raw word");
                // Scales such as 100/16384 % are lossy: decoding then encoding must give the raw word back.
                let decoded = <R as Register>::Value::from_raw(#raw, info).unwrap();
                assert_eq!(decoded.to_raw(info).unwrap(), #raw, "decoded {decoded:?} re-encodes");
            }
        });
    }
    for conversion in &drive.conversions {
        let function = Ident::new(&conversion.id, Span::call_site());
        for (index, (inputs, result, source)) in conversion.examples.iter().enumerate() {
            let name = format_ident!("conversion_{}_example_{}", conversion.id, index + 1);
            let args = inputs.iter().map(|v| Literal::f64_unsuffixed(*v));
            let expected = Literal::f64_unsuffixed(*result);
            let doc = format!(" {} (manual section {source}).", conversion.name);
            tests.push(quote! {
                #[doc = #doc]
                #[test]
                fn #name() {
                    let result = #root::conversions::#function(#(#args),*);
                    assert!(
                        result.is_some_and(|r| (r - #expected).abs() < 1e-6),
                        "the manual's numbers give {:?}, not {}", result, #expected
                    );
                }
            });
        }
    }
    quote! {
        #[allow(unused_imports)]
        use ::vfd_runtime::meaning::{Direction, FrameMeaning};
        #[allow(unused_imports)]
        use ::vfd_runtime::prelude::*;
        #[allow(unused_imports)]
        use ::vfd_runtime::{CommandKind, Space};
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

fn bytes_tokens(bytes: &[u8]) -> TokenStream {
    let bytes = bytes.iter().map(|b| {
        format!("0x{b:02X}")
            .parse::<TokenStream>()
            .unwrap_or_else(|_| quote!(#b))
    });
    quote!(&[#(#bytes),*])
}

fn frame_checks(
    protocol: &TokenStream,
    frame: &FrameIr,
    direction: Direction,
    request: Option<&FrameIr>,
) -> TokenStream {
    let bytes = bytes_tokens(&frame.bytes);
    let expect = frame.meaning.bake();
    let check = match direction {
        Direction::Request => {
            quote!(::vfd_runtime::testing::request_round_trips(#protocol, #bytes, &#expect);)
        }
        Direction::Reply => {
            quote!(::vfd_runtime::testing::reply_round_trips(#protocol, #bytes, &#expect);)
        }
    };
    let printed = frame.printed.as_ref().map(|printed| {
        let bytes = bytes_tokens(&printed.bytes);
        let direction_tokens = direction.bake();
        match (printed.rejected_as.decode_kind(), printed.rejected_as, request) {
            (Some(kind), _, _) => {
                let reason = kind.bake();
                quote! {
                    ::vfd_runtime::testing::printed_is_rejected(#protocol, #direction_tokens, #bytes, ::vfd_runtime::#reason);
                }
            }
            (None, PrintedRejection::DoesNotAnswerRequest, Some(request)) => {
                let request = bytes_tokens(&request.bytes);
                quote! {
                    ::vfd_runtime::testing::printed_does_not_answer(#protocol, #request, #bytes);
                }
            }
            (None, _, _) => quote! {
                ::vfd_runtime::testing::printed_means_otherwise(#protocol, #direction_tokens, #bytes, &#expect);
            },
        }
    });
    quote! { #check #printed }
}

fn example_test(drive: &DriveIr, root: &syn::Path, example: &ExampleIr) -> TokenStream {
    let name = format_ident!("example_{}", example.id);
    let protocol_name = drive
        .protocols
        .iter()
        .find(|p| p.id == example.protocol)
        .map(|p| Ident::new(&p.const_name, Span::call_site()))
        .unwrap_or_else(|| Ident::new("UNKNOWN_PROTOCOL", Span::call_site()));
    // In a named variant: the protocol with that variant's bytes (`Protocol::variant`).
    let protocol = match &example.variant {
        Some(variant) => {
            quote!(#root::protocols::#protocol_name.protocol().variant(#variant).expect("the example's variant"))
        }
        None => quote!(&#root::protocols::#protocol_name),
    };
    let mut body = Vec::new();
    if let Some(frame) = &example.request {
        body.push(frame_checks(&protocol, frame, Direction::Request, None));
    }
    if let Some(frame) = &example.reply {
        body.push(frame_checks(
            &protocol,
            frame,
            Direction::Reply,
            example.request.as_ref(),
        ));
    }
    if let Some(ignored) = &example.ignored_request {
        let bytes = bytes_tokens(&ignored.bytes);
        let reason = ignored.rejected_as.bake();
        body.push(quote! {
            ::vfd_runtime::testing::drive_ignores(&#root::DRIVE, #protocol, #bytes, ::vfd_runtime::#reason);
        });
    }
    if let (true, Some(request), Some(reply)) = (example.answers, &example.request, &example.reply)
    {
        let (request, reply) = (bytes_tokens(&request.bytes), bytes_tokens(&reply.bytes));
        body.push(quote! {
            ::vfd_runtime::testing::reply_answers(#protocol, #request, #reply);
        });
    }
    let register: Option<&RegisterIr> = example.register.as_ref().and_then(|id| drive.register(id));
    if let (Some(value), Some(described)) = (example.value, register) {
        let kind = &described.value;
        let register = Ident::new(&described.type_name, Span::call_site());
        let ty = value_type_at(kind, root);
        let construct = construct_value(kind, value, &ty);
        let data = example
            .reply
            .as_ref()
            .and_then(|f| f.meaning.data)
            .or(example.request.as_ref().and_then(|f| f.meaning.data))
            .unwrap_or(0);
        let data = int_literal(data);
        body.push(quote! {
            {
                type R = #root::registers::#register;
                let value = #construct;
                assert_eq!(<R as Register>::Value::from_raw(#data, R::INFO).unwrap(), value, "decoded value");
            }
        });
        if let Some(request) = &example.request {
            let bytes = bytes_tokens(&request.bytes);
            let typed = crate::frames::typed_request_kind(
                request.meaning.kind,
                described.writable(),
                described.persistable(),
            );
            let build = match typed {
                Some(CommandKind::WriteRam) => Some(quote! {
                    let request = #root::registers::#register::write_ram(#construct).expect("the manual's value is within range");
                }),
                Some(CommandKind::WritePersistent) => Some(quote! {
                    let request = #root::registers::#register::write_persistent(#construct).expect("the manual's value is within range");
                }),
                Some(CommandKind::Read) => Some(quote! {
                    let request = #root::registers::#register::read();
                }),
                _ => None,
            };
            let at_index = match request.meaning.index {
                Some(index) if index > 0 || described.array_len > 0 => {
                    let index = int_literal(index);
                    quote!(let request = request.at_index(#index).expect("the manual's index is within the array");)
                }
                _ => quote!(),
            };
            // An extra command (a second read) is reached only by naming its code.
            let extra = drive
                .protocols
                .iter()
                .find(|p| p.id == example.protocol)
                .and_then(|p| {
                    p.commands.iter().find(|c| {
                        c.extra
                            && Some(c.kind) == request.meaning.kind
                            && request.meaning.code == Some(c.code)
                    })
                });
            let using = match extra {
                Some(command) => {
                    let code = int_literal(command.code);
                    quote!(let request = request.using(#code);)
                }
                None => quote!(),
            };
            // The reply-wait digit the request carries is stated, as `vfd check` states it
            // (`frames::stated_fields`): the typed API has no reply wait of its own.
            let check = match request.meaning.reply_wait {
                Some(wait) => {
                    let wait = int_literal(wait);
                    quote!(::vfd_runtime::testing::typed_request_encodes_stating(
                        #protocol,
                        &request,
                        &[(::vfd_runtime::Role::ReplyWait, #wait)],
                        #bytes,
                    );)
                }
                None => {
                    quote!(::vfd_runtime::testing::typed_request_encodes(#protocol, &request, #bytes);)
                }
            };
            if let Some(build) = build {
                body.push(quote! {
                    {
                        #build
                        #using
                        #at_index
                        #check
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

/// A sequence's test: the master makes the one call against the manual's drive frames,
/// and sends exactly the manual's frames of its own.
fn sequence_test(drive: &DriveIr, root: &syn::Path, sequence: &SequenceIr) -> TokenStream {
    let name = format_ident!("sequence_{}", sequence.id);
    let protocol_name = drive
        .protocols
        .iter()
        .find(|p| p.id == sequence.protocol)
        .map(|p| Ident::new(&p.const_name, Span::call_site()))
        .unwrap_or_else(|| Ident::new("UNKNOWN_PROTOCOL", Span::call_site()));
    let Some(register) = drive.register(&sequence.register) else {
        return TokenStream::new();
    };
    let ty = Ident::new(&register.type_name, Span::call_site());
    let value_ty = value_type_at(&register.value, root);
    let steps = sequence.steps.iter().map(|step| {
        let master = step.from == crate::parse::model::Sender::Master;
        let bytes = bytes_tokens(&step.bytes);
        quote!((#master, #bytes))
    });
    let address = match sequence.address {
        Some(address) => {
            let address = int_literal(address);
            quote!(Some(#address))
        }
        None => quote!(None),
    };
    let call = match (sequence.call, &sequence.result) {
        (SequenceCallIr::Read, SequenceResultIr::Value(value)) => {
            let construct = construct_value(&register.value, *value, &value_ty);
            quote! {
                let read = master.read::<R>().expect("the manual's sequence reads");
                assert_eq!(read.into_value(), #construct, "the value read");
            }
        }
        (SequenceCallIr::Write(value), SequenceResultIr::Written) => {
            let construct = construct_value(&register.value, value, &value_ty);
            if sequence.persistent {
                quote! {
                    master.write_persistent::<R>(#construct).expect("the manual's sequence writes");
                }
            } else {
                quote! {
                    master.write_ram::<R>(#construct).expect("the manual's sequence writes");
                }
            }
        }
        (call, result) => {
            let request = match call {
                SequenceCallIr::Read => quote!(::vfd_runtime::Request::read::<R>()),
                SequenceCallIr::Write(value) => {
                    let construct = construct_value(&register.value, value, &value_ty);
                    if sequence.persistent {
                        quote!(::vfd_runtime::Request::write_persistent::<R>(#construct).expect("in range"))
                    } else {
                        quote!(::vfd_runtime::Request::write_ram::<R>(#construct).expect("in range"))
                    }
                }
                SequenceCallIr::WriteRaw(raw) => {
                    let raw = int_literal(raw);
                    let kind = if sequence.persistent {
                        quote!(CommandKind::WritePersistent)
                    } else {
                        quote!(CommandKind::WriteRam)
                    };
                    quote!(::vfd_runtime::Request::for_register(#kind, R::INFO, #raw))
                }
            };
            let check = match result {
                SequenceResultIr::Error(code, _) => {
                    let code = int_literal(*code);
                    quote! {
                        let error = outcome.expect_err("the drive refuses");
                        ::vfd_runtime::testing::refused_with(&error, #code);
                    }
                }
                SequenceResultIr::Value(_) | SequenceResultIr::Written => {
                    quote!(outcome.expect("the manual's sequence succeeds");)
                }
            };
            quote! {
                let outcome = master.transact(&#request);
                #check
            }
        }
    };
    let protocol = match &sequence.variant {
        Some(variant) => quote! {
            ::std::boxed::Box::leak(::std::boxed::Box::new(
                #root::protocols::#protocol_name.variant(#variant).expect("the sequence's variant"),
            ))
        },
        None => quote!(&#root::protocols::#protocol_name),
    };
    let reply_wait = match sequence.reply_wait {
        Some(wait) if wait > 0 => {
            let millis = int_literal(u32::from(wait) * 10);
            quote!(.with_reply_wait(::std::time::Duration::from_millis(#millis)))
        }
        _ => quote!(),
    };
    let given = match sequence.selector_given {
        Some(value) => {
            let value = int_literal(value);
            quote!(master.assume_persistence_selector(#value);)
        }
        None => quote!(),
    };
    let doc = format!(
        " {} ({}); manual section {}.",
        sequence.description, sequence.description_zh, sequence.source
    );
    quote! {
        #[doc = #doc]
        #[test]
        fn #name() {
            type R = #root::registers::#ty;
            let script = ::vfd_runtime::testing::Script::new(&[#(#steps),*]);
            let mut master = ::vfd_runtime::transaction::Master::new(
                script,
                #protocol,
                #root::DRIVE.serial.default,
                #root::DRIVE.serial.timing,
            )
            .with_address(#address)
            #reply_wait;
            #given
            #call
            master.transport().assert_followed();
        }
    }
}

#[cfg(test)]
mod naming_tests {
    use crate::validate::testing::valid_with;
    use std::path::Path;

    #[test]
    fn any_character_in_a_register_code_gives_valid_test_names() {
        let yaml = valid_with(&[
            (
                "code: FH, name: Maximum frequency",
                "code: \"H6D/HED\", name: Maximum frequency",
            ),
            ("max: FH }", "max: \"H6D/HED\" }"),
            (
                "register: FH, value: 80.0",
                "register: \"H6D/HED\", value: 80.0",
            ),
        ]);
        let drive = crate::compile_text(
            Path::new("drive.yaml"),
            yaml,
            Some(Path::new("../drives/protocols")),
        )
        .expect("valid");
        let tokens = super::golden_tests(&drive, "drive.yaml");
        syn::parse2::<syn::File>(tokens).expect("the tests parse as Rust");
    }
}
