//! Emits a drive's protocols: the runtime `Protocol` values, with their frame layouts,
//! commands, error codes and pre-steps.

use super::*;

pub(super) fn protocols_module(drive: &DriveIr) -> TokenStream {
    let mut items = Vec::new();
    let error_codes: Vec<TokenStream> = drive
        .error_codes
        .codes
        .iter()
        .map(|code| {
            let (value, id, name, name_zh, meaning) = (
                code.code,
                &code.id,
                &code.name,
                &code.name_zh,
                &code.meaning,
            );
            quote! {
                ::vfd_runtime::ErrorCodeInfo {
                    code: #value,
                    id: ::std::borrow::Cow::Borrowed(#id),
                    name: ::std::borrow::Cow::Borrowed(#name),
                    name_zh: ::std::borrow::Cow::Borrowed(#name_zh),
                    meaning: ::std::borrow::Cow::Borrowed(#meaning),
                }
            }
        })
        .collect();
    let error_count = error_codes.len();
    items.push(quote! {
        /// The manual's error codes, shared by the drive's protocols.
        pub static ERROR_CODES: [::vfd_runtime::ErrorCodeInfo; #error_count] = [#(#error_codes),*];
    });
    let mut all = Vec::new();
    for protocol in &drive.protocols {
        items.push(protocol_items(protocol));
        let name = ident(&protocol.const_name);
        all.push(quote!(&#name));
    }
    let count = all.len();
    quote! {
        /// The protocols this drive speaks, as data the runtime interprets.
        pub mod protocols {
            #(#items)*
            /// Every protocol of the drive.
            pub static ALL: [&::vfd_runtime::Protocol; #count] = [#(#all),*];
        }
    }
}

/// `::vfd_runtime::<type_path>::<Variant>` for a unit enum value, by its `Debug` name.
pub(super) fn variant(type_path: &str, value: impl std::fmt::Debug) -> TokenStream {
    format!("::vfd_runtime::{type_path}::{value:?}")
        .parse()
        .unwrap_or_default()
}

fn cow_str(text: &str) -> TokenStream {
    quote!(::std::borrow::Cow::Borrowed(#text))
}

fn cow_list<T>(items: &[T], each: impl Fn(&T) -> TokenStream) -> TokenStream {
    let items = items.iter().map(each);
    quote!(::std::borrow::Cow::Borrowed(&[#(#items),*]))
}

fn protocol_items(protocol: &ProtocolIr) -> TokenStream {
    let prefix = &protocol.const_name;
    let runtime = &protocol.runtime;
    let mut items = Vec::new();
    let mut emitted = std::collections::BTreeSet::new();
    let mut layout_expr = |layout: &FrameLayout, items: &mut Vec<TokenStream>| -> TokenStream {
        let parts_name = format_ident!("{}_{}", prefix, const_name(&layout.name));
        let parts: Vec<TokenStream> = layout.parts.iter().map(part_tokens).collect();
        let count = parts.len();
        let name = cow_str(&layout.name);
        if emitted.insert(parts_name.to_string()) {
            items.push(quote! {
                static #parts_name: [::vfd_runtime::Part; #count] = [#(#parts),*];
            });
        }
        quote! {
            ::vfd_runtime::FrameLayout { name: #name, parts: ::std::borrow::Cow::Borrowed(&#parts_name) }
        }
    };
    let mut commands = Vec::new();
    for command in runtime.commands.iter() {
        let code = command.code;
        let kind = variant("CommandKind", command.kind);
        let data_types = cow_list(&command.data_types, |t| variant("DataType", t));
        let space = variant("Space", command.space);
        let (multiply, offset) = (command.address_map.multiply, command.address_map.offset);
        let request = layout_expr(&command.request, &mut items);
        let reply = layout_expr(&command.reply, &mut items);
        let reply_codes = cow_list(&command.reply_codes, |c| quote!(#c));
        commands.push(quote! {
            ::vfd_runtime::CommandSpec {
                code: #code,
                kind: #kind,
                data_types: #data_types,
                space: #space,
                address_map: ::vfd_runtime::AddressMap { multiply: #multiply, offset: #offset },
                request: #request,
                reply: #reply,
                reply_codes: #reply_codes,
            }
        });
    }
    let error_reply = match &runtime.error_reply {
        Some(layout) => {
            let expr = layout_expr(layout, &mut items);
            quote!(Some(#expr))
        }
        None => quote!(None),
    };
    let commands_name = format_ident!("{}_COMMANDS", prefix);
    let command_count = commands.len();
    let name = ident(prefix);
    let id = cow_str(&protocol.id);
    let title = cow_str(&runtime.name);
    let tripped = runtime.lowercase_means_tripped;
    let max = runtime.max_frame_len;
    let (min_address, max_address) = runtime.address_range;
    let optional = cow_list(&runtime.default_optional_parts, |p| cow_str(p));
    let pre_steps = cow_list(&runtime.pre_steps, |step| match *step {
        vfd_runtime::PreStep::Index { register } => {
            quote!(::vfd_runtime::PreStep::Index { register: #register })
        }
        vfd_runtime::PreStep::Persistence {
            space,
            register,
            data_type,
            ram,
            persistent,
        } => {
            let space = variant("Space", space);
            let data_type = variant("DataType", data_type);
            quote!(::vfd_runtime::PreStep::Persistence { space: #space, register: #register, data_type: #data_type, ram: #ram, persistent: #persistent })
        }
    });
    let [first, second] = runtime.default_process;
    let gap = runtime.frame_gap_chars;
    let doc = format!(
        " {} ({}), described in the protocol file `{}.yaml`; manual section {}.",
        protocol.name, protocol.name_zh, protocol.uses, protocol.source
    );
    let description = format!(" {}", protocol.description);
    quote! {
        #(#items)*
        static #commands_name: [::vfd_runtime::CommandSpec; #command_count] = [#(#commands),*];
        #[doc = #doc]
        #[doc = ""]
        #[doc = #description]
        pub static #name: ::vfd_runtime::Protocol = ::vfd_runtime::Protocol {
            id: #id,
            name: #title,
            commands: ::std::borrow::Cow::Borrowed(&#commands_name),
            error_reply: #error_reply,
            lowercase_means_tripped: #tripped,
            max_frame_len: #max,
            address_range: (#min_address, #max_address),
            default_optional_parts: #optional,
            error_codes: ::std::borrow::Cow::Borrowed(&ERROR_CODES),
            pre_steps: #pre_steps,
            default_process: [#first, #second],
            frame_gap_chars: #gap,
        };
    }
}

fn part_tokens(part: &Part) -> TokenStream {
    match part {
        Part::Literal {
            name,
            bytes,
            optional,
        } => {
            let name = cow_str(name);
            let bytes = Literal::byte_string(bytes);
            quote!(::vfd_runtime::Part::Literal { name: #name, bytes: ::std::borrow::Cow::Borrowed(#bytes), optional: #optional })
        }
        Part::Field(field) => {
            let name = cow_str(&field.name);
            let role = variant("Role", field.role);
            let format = variant("Format", field.format);
            let (width, min_width) = (field.width, field.min_width);
            let optional = match field.optional {
                None => quote!(None),
                Some(Presence::IfFormatMatches) => {
                    quote!(Some(::vfd_runtime::Presence::IfFormatMatches))
                }
                Some(Presence::IfByteAtMost(limit)) => {
                    quote!(Some(::vfd_runtime::Presence::IfByteAtMost(#limit)))
                }
            };
            let allowed = cow_list(&field.allowed, |v| quote!(#v));
            let fold_case = field.fold_case;
            let sized_by = variant("SizedBy", field.sized_by);
            quote! {
                ::vfd_runtime::Part::Field(::vfd_runtime::FieldSpec {
                    name: #name,
                    role: #role,
                    format: #format,
                    width: #width,
                    min_width: #min_width,
                    optional: #optional,
                    allowed: #allowed,
                    fold_case: #fold_case,
                    sized_by: #sized_by,
                })
            }
        }
        Part::Checksum(spec) => {
            let name = cow_str(&spec.name);
            let algorithm = variant("ChecksumAlgorithm", spec.algorithm);
            let format = variant("Format", spec.format);
            let marker = Literal::byte_string(&spec.marker);
            let (covers_from, optional) = (spec.covers_from, spec.optional);
            quote! {
                ::vfd_runtime::Part::Checksum(::vfd_runtime::ChecksumSpec {
                    name: #name,
                    algorithm: #algorithm,
                    format: #format,
                    marker: ::std::borrow::Cow::Borrowed(#marker),
                    covers_from: #covers_from,
                    optional: #optional,
                })
            }
        }
        Part::Word(word) => {
            let name = cow_str(&word.name);
            let format = variant("Format", word.format);
            let fields = cow_list(&word.fields, |bits| {
                let name = cow_str(&bits.name);
                let role = variant("Role", bits.role);
                let (lsb, width) = (bits.lsb, bits.width);
                let allowed = cow_list(&bits.allowed, |v| quote!(#v));
                quote!(::vfd_runtime::BitsSpec { name: #name, role: #role, lsb: #lsb, width: #width, allowed: #allowed })
            });
            quote!(::vfd_runtime::Part::Word(::vfd_runtime::WordSpec { name: #name, format: #format, fields: #fields }))
        }
        Part::Length(length) => {
            let name = cow_str(&length.name);
            let format = variant("Format", length.format);
            let counts = match length.counts {
                vfd_runtime::Counts::Parts { from, through } => {
                    quote!(::vfd_runtime::Counts::Parts { from: #from, through: #through })
                }
                vfd_runtime::Counts::DataSize => quote!(::vfd_runtime::Counts::DataSize),
            };
            let (times, per) = (length.times, length.per);
            quote!(::vfd_runtime::Part::Length(::vfd_runtime::LengthSpec { name: #name, format: #format, counts: #counts, times: #times, per: #per }))
        }
    }
}
