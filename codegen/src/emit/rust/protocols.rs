//! Emits protocols: each protocol file's frame layouts once (a `layouts` module shared by
//! every drive that uses the file), and per drive a `protocols` module with its error codes
//! and one runtime `Protocol` per protocol, whose commands name the shared layouts.

use super::bake::{int_literal, Bake};
use super::*;
use crate::ir::{CommandIr, ErrorCodeIr, ErrorTableIr, ProtocolFileIr};

/// `layouts::<file>` modules, one per protocol file, each holding one `const` per layout.
pub(crate) fn layouts_module(files: &[&ProtocolFileIr]) -> TokenStream {
    let modules = files.iter().map(|file| {
        let module = ident(&file.module);
        let doc = doc_text(format!(
            "{}{}: frame layouts of the protocol file `{}`.",
            file.name,
            zh(&file.name_zh),
            file.id
        ));
        let layouts = file.layouts.iter().map(|layout| {
            let name = ident(&const_name(&layout.name));
            let doc = doc_text(format!("The `{}` layout.", layout.name));
            let decode = format_ident!("decode_{}", crate::naming::module_name(&layout.name));
            let encode = format_ident!("encode_{}", crate::naming::module_name(&layout.name));
            let (items, value) = super::bake::compiled_plan(layout, &name, &decode, &encode);
            quote! {
                #[doc = #doc]
                pub const #name: FrameLayout = #value;
                #items
            }
        });
        let imports = layout_imports(file);
        quote! {
            #[doc = #doc]
            pub mod #module {
                #imports
                #(#layouts)*
            }
        }
    });
    quote! {
        /// Frame layouts, one module per protocol file, shared by every drive that uses it.
        pub mod layouts {
            #(#modules)*
        }
    }
}

/// The runtime type names a protocol file's layouts use.
fn layout_imports(file: &ProtocolFileIr) -> TokenStream {
    use vfd_runtime::Part;
    let parts = file.layouts.iter().flat_map(|l| l.parts.iter());
    let mut names = std::collections::BTreeSet::from(["Encoding", "FrameLayout", "Part"]);
    for part in parts {
        match part {
            Part::Literal { .. } => {}
            Part::Field(field) => {
                names.extend(["FieldSpec", "Role", "Format"]);
                if field.optional.is_some() {
                    names.insert("Presence");
                }
                if field.sized_by != vfd_runtime::SizedBy::Format {
                    names.insert("SizedBy");
                }
                if field.broadcast.is_some() {
                    names.insert("BroadcastAddress");
                }
            }
            Part::Checksum(_) => {
                names.extend(["ChecksumSpec", "ChecksumAlgorithm", "Format"]);
            }
            Part::Word(_) => {
                names.extend(["WordSpec", "BitsSpec", "Role", "Format"]);
            }
            Part::Length(_) => {
                names.extend(["LengthSpec", "Counts", "Format"]);
            }
        }
    }
    let names = names.into_iter().map(ident);
    quote! {
        use ::std::borrow::Cow;
        use ::vfd_runtime::{#(#names),*};
    }
}

/// The drive's `protocols` module. `layouts` is the path from inside it to the `layouts`
/// module (`super::layouts` when the drive holds its own, `super::super::layouts` when
/// several drives share one).
pub(crate) fn protocols_module(drive: &DriveIr, layouts: &TokenStream) -> TokenStream {
    let error_codes = drive.error_codes.codes.iter().map(error_code_tokens);
    let error_count = int_literal(drive.error_codes.codes.len());
    let protocols = drive
        .protocols
        .iter()
        .map(|p| protocol_items(drive, p, layouts));
    let all = drive.protocols.iter().map(|p| {
        let name = ident(&p.const_name);
        quote!(#name.protocol())
    });
    let count = int_literal(drive.protocols.len());
    let mut imports = vec![
        quote!(CommandSpec),
        quote!(CommandKind),
        quote!(DriveProtocol),
        quote!(ErrorCodeInfo),
        quote!(Protocol),
    ];
    let commands = || drive.protocols.iter().flat_map(|p| p.commands.iter());
    if commands().any(|c| !c.data_types.is_empty()) {
        imports.push(quote!(DataType));
    }
    if commands().any(|c| c.space != vfd_runtime::Space::Parameter)
        || drive.protocols.iter().any(|p| {
            p.pre_steps
                .iter()
                .any(|s| matches!(s, vfd_runtime::PreStep::Persistence { .. }))
        })
    {
        imports.push(quote!(Space));
    }
    if drive.protocols.iter().any(|p| {
        p.pre_steps
            .iter()
            .any(|s| matches!(s, vfd_runtime::PreStep::Persistence { .. }))
    }) {
        imports.push(quote!(DataType));
    }
    if commands().any(|c| c.address_map != vfd_runtime::AddressMap::IDENTITY) {
        imports.push(quote!(AddressMap));
    }
    if drive.protocols.iter().any(|p| !p.pre_steps.is_empty()) {
        imports.push(quote!(PreStep));
    }
    let mut seen = std::collections::BTreeSet::new();
    imports.retain(|name| seen.insert(name.to_string()));
    let files = drive.protocol_files.iter().map(|file| {
        let module = ident(&file.module);
        quote!(#module)
    });
    quote! {
        /// The protocols this drive speaks, as data the runtime interprets.
        pub mod protocols {
            use ::std::borrow::Cow;
            use ::vfd_runtime::{#(#imports),*};
            use #layouts::{#(#files),*};

            /// The manual's error codes, shared by the drive's protocols they apply to.
            pub static ERROR_CODES: [ErrorCodeInfo; #error_count] = [#(#error_codes),*];
            #(#protocols)*
            /// Every protocol of the drive.
            pub static ALL: [&Protocol; #count] = [#(#all),*];
        }
    }
}

fn error_code_tokens(code: &ErrorCodeIr) -> TokenStream {
    let value = int_literal(code.code);
    let (id, name, name_zh, meaning) = (&code.id, &code.name, &code.name_zh, &code.meaning);
    if code.printed.is_empty() {
        quote!(ErrorCodeInfo::new(#value, #id, #name, #name_zh, #meaning))
    } else {
        let printed = &code.printed;
        quote!(ErrorCodeInfo::new_printed(#value, #id, #name, #name_zh, #meaning, #printed))
    }
}

fn command_tokens(command: &CommandIr, file: &Ident) -> TokenStream {
    let code = match u8::try_from(command.code) {
        Ok(byte) if byte.is_ascii_alphabetic() => {
            let byte = Literal::byte_character(byte);
            quote!(#byte as u32)
        }
        _ => {
            let code = int_literal(command.code);
            quote!(#code)
        }
    };
    let kind = command.kind.bake();
    let request = ident(&const_name(&command.request));
    let reply = ident(&const_name(&command.reply));
    let mut tokens = quote!(CommandSpec::new(#code, #kind, #file::#request, #file::#reply));
    if !command.data_types.is_empty() {
        let types = command.data_types.iter().map(Bake::bake);
        tokens.extend(quote!(.with_data_types(&[#(#types),*])));
    }
    if command.space != vfd_runtime::Space::Parameter {
        let space = command.space.bake();
        tokens.extend(quote!(.with_space(#space)));
    }
    if command.address_map != vfd_runtime::AddressMap::IDENTITY {
        let map = command.address_map.bake();
        tokens.extend(quote!(.with_address_map(#map)));
    }
    if !command.reply_codes.is_empty() {
        let codes = command.reply_codes.iter().map(|c| int_literal(*c));
        tokens.extend(quote!(.with_reply_codes(&[#(#codes),*])));
    }
    if let Some(code) = command.error_code {
        let code = int_literal(code);
        tokens.extend(quote!(.with_error_code(#code)));
    }
    if command.no_reply {
        tokens.extend(quote!(.without_reply()));
    }
    if command.extra {
        tokens.extend(quote!(.as_extra()));
    }
    if command.lowercase_means_sender_tripped {
        tokens.extend(quote!(.with_lowercase_sender_tripped()));
    }
    if command.stored_by_instruction {
        tokens.extend(quote!(.with_storage_by_instruction()));
    }
    if !command.registers.is_empty() {
        let registers = command.registers.iter().map(|r| int_literal(*r));
        tokens.extend(quote!(.with_registers(&[#(#registers),*])));
    }
    if let Some((ok, again)) = &command.follow_up {
        let (ok, again) = (ident(&const_name(ok)), ident(&const_name(again)));
        tokens.extend(quote!(.with_follow_up(#file::#ok, #file::#again)));
    }
    if let Some((register, step, received_by)) = &command.percent_of {
        let step = Literal::f64_unsuffixed(*step);
        tokens.extend(
            quote!(.with_percent_of(#register, #step, &[#(Cow::Borrowed(#received_by)),*])),
        );
    }
    tokens
}

fn protocol_items(drive: &DriveIr, protocol: &ProtocolIr, layouts: &TokenStream) -> TokenStream {
    let _ = layouts;
    let file = drive
        .protocol_files
        .iter()
        .find(|f| f.id == protocol.uses)
        .map(|f| ident(&f.module))
        .unwrap_or_else(|| ident(&crate::naming::module_name(&protocol.uses)));
    let name = ident(&protocol.const_name);
    let commands_name = format_ident!("{}_COMMANDS", protocol.const_name);
    let untyped = format_ident!("{}_PROTOCOL", protocol.const_name);
    let commands = protocol.commands.iter().map(|c| command_tokens(c, &file));
    let command_count = int_literal(protocol.commands.len());
    let error_reply = match &protocol.error_reply {
        Some(layout) => {
            let layout = ident(&const_name(layout));
            quote!(Some(#file::#layout))
        }
        None => quote!(None),
    };
    let (id, title) = (&protocol.id, &protocol.name);
    let tripped = protocol.lowercase_means_tripped;
    let max = int_literal(protocol.max_frame_len);
    let (min_address, max_address) = (
        int_literal(protocol.address_range.0),
        int_literal(protocol.address_range.1),
    );
    let optional = protocol
        .default_optional_parts
        .iter()
        .map(|p| quote!(Cow::Borrowed(#p)));
    let pre_steps = protocol.pre_steps.iter().map(Bake::bake);
    let [first, second] = protocol.default_process.unwrap_or([0, 0]).map(int_literal);
    let gap = Literal::f32_unsuffixed(protocol.frame_gap_chars);
    let max_words = int_literal(protocol.max_words_per_read);
    let max_words_written = int_literal(protocol.max_words_per_write);
    let partial_blocks = protocol.partial_blocks;
    let timing = link_timing_tokens(&protocol.timing);
    let number = |n: Option<u16>| match n {
        Some(n) => {
            let n = int_literal(n);
            quote!(Some(#n))
        }
        None => quote!(None),
    };
    let wire_numbers = protocol.wire_numbers.iter().map(|w| {
        let (register, read, write) = (int_literal(w.register), number(w.read), number(w.write));
        let data = w.data.iter().map(|v| int_literal(*v));
        quote!(::vfd_runtime::protocol::WireNumber { register: #register, read: #read, write: #write, data: ::std::borrow::Cow::Borrowed(&[#(#data),*]) })
    });
    let broadcast = match &protocol.broadcast {
        Some(rule) => {
            let codes = rule.commands.iter().map(|c| int_literal(*c));
            let answered_by = match rule.answered_by {
                vfd_runtime::BroadcastAnswer::None => quote!(None),
                vfd_runtime::BroadcastAnswer::LowestMatching => quote!(LowestMatching),
            };
            quote!(Some(::vfd_runtime::broadcast::BroadcastRule {
                commands: Cow::Borrowed(&[#(#codes),*]),
                answered_by: ::vfd_runtime::broadcast::BroadcastAnswer::#answered_by,
            }))
        }
        None => quote!(None),
    };
    let paging = match &protocol.paging {
        Some(paging) => {
            let read = number(paging.select_read);
            let write = int_literal(paging.select_write);
            let ranges = paging.ranges.iter().map(|r| {
                let (first, last, size, first_page) = (
                    int_literal(r.first),
                    int_literal(r.last),
                    int_literal(r.size),
                    int_literal(r.first_page),
                );
                let missing = r.missing.iter().map(|p| int_literal(*p));
                quote!(::vfd_runtime::protocol::PageRange {
                    first: #first, last: #last, size: #size, first_page: #first_page,
                    missing: Cow::Borrowed(&[#(#missing),*]),
                })
            });
            let forgotten = paging.forgotten_after.iter().map(|n| int_literal(*n));
            let initial = int_literal(paging.initial);
            let data_type = paging.select_data_type.bake();
            quote!(Some(::vfd_runtime::protocol::Paging {
                select_read: #read,
                select_write: #write,
                select_data_type: ::vfd_runtime::#data_type,
                ranges: Cow::Borrowed(&[#(#ranges),*]),
                forgotten_after: Cow::Borrowed(&[#(#forgotten),*]),
                initial: #initial,
            }))
        }
        None => quote!(None),
    };
    let persistence = match &protocol.persistence {
        Some(selector) => {
            let (space, data_type) = (selector.space.bake(), selector.data_type.bake());
            let register = int_literal(selector.register);
            let (ram, persistent) = (int_literal(selector.ram), int_literal(selector.persistent));
            let spans = selector.registers.iter().map(|&(from, to)| {
                let (from, to) = (int_literal(from), int_literal(to));
                quote!((#from, #to))
            });
            quote!(Some(::vfd_runtime::PersistenceSelector {
                register: #register,
                space: ::vfd_runtime::#space,
                data_type: ::vfd_runtime::#data_type,
                ram: #ram,
                persistent: #persistent,
                registers: Cow::Borrowed(&[#(#spans),*]),
            }))
        }
        None => quote!(None),
    };
    let block = match &protocol.block {
        Some(block) => {
            let block = block.bake();
            quote!(Some(#block))
        }
        None => quote!(None),
    };
    let variants = variants_tokens(protocol.variants.as_ref());
    let unsupported_function = match &protocol.unsupported_function {
        Some(entry) => {
            let code = int_literal(entry.error_code);
            quote!(Some(#code))
        }
        None => quote!(None),
    };
    let doc = doc_text(format!(
        "{}, from the protocol file `{}`; manual section {}.",
        protocol.name, protocol.uses, protocol.source
    ));
    // Error replies are named from the drive's table, or from the protocol's own.
    let (error_table, error_codes) = match &protocol.error_table {
        ErrorTableIr::Drive => (TokenStream::new(), quote!(ERROR_CODES)),
        ErrorTableIr::Protocol(table) => {
            let name = format_ident!("{}_ERROR_CODES", protocol.const_name);
            let count = int_literal(table.codes.len());
            let codes = table.codes.iter().map(error_code_tokens);
            let doc = doc_text(format!(
                "The error codes of {} replies ({}): the drive's table does not apply \
                 to this protocol.",
                protocol.name, table.source
            ));
            (
                quote! {
                    #[doc = #doc]
                    pub static #name: [ErrorCodeInfo; #count] = [#(#codes),*];
                },
                quote!(#name),
            )
        }
    };
    quote! {
        #error_table
        static #commands_name: [CommandSpec; #command_count] = [#(#commands),*];
        #[doc = #doc]
        pub static #name: DriveProtocol<super::Drive> = DriveProtocol::new(&#untyped);
        static #untyped: Protocol = Protocol {
            id: Cow::Borrowed(#id),
            name: Cow::Borrowed(#title),
            commands: Cow::Borrowed(&#commands_name),
            error_reply: #error_reply,
            lowercase_means_tripped: #tripped,
            max_frame_len: #max,
            address_range: (#min_address, #max_address),
            default_optional_parts: Cow::Borrowed(&[#(#optional),*]),
            error_codes: Cow::Borrowed(&#error_codes),
            pre_steps: Cow::Borrowed(&[#(#pre_steps),*]),
            default_process: [#first, #second],
            frame_gap_chars: #gap,
            max_words_per_read: #max_words,
            max_words_per_write: #max_words_written,
            partial_blocks: #partial_blocks,
            block: #block,
            timing: #timing,
            broadcast: #broadcast,
            wire_numbers: Cow::Borrowed(&[#(#wire_numbers),*]),
            paging: #paging,
            persistence: #persistence,
            variants: #variants,
            unsupported_function: #unsupported_function,
            variant_cache: ::vfd_runtime::protocol::VariantCache::new(),
        };
    }
}

/// A protocol's `variants` literal (`None` when it has none).
fn variants_tokens(variants: Option<&vfd_runtime::variant::Variants>) -> TokenStream {
    let Some(variants) = variants else {
        return quote!(None);
    };
    let current = int_literal(variants.current);
    let choices = variants.choices.iter().map(|choice| {
        let (id, name, name_zh) = (
            choice.id.as_ref(),
            choice.name.as_ref(),
            choice.name_zh.as_ref(),
        );
        let literals = choice.literals.iter().map(|literal| {
            let part = literal.part.as_ref();
            let bytes = Literal::byte_string(&literal.bytes);
            quote!(::vfd_runtime::variant::VariantLiteral {
                part: Cow::Borrowed(#part),
                bytes: Cow::Borrowed(#bytes),
            })
        });
        quote!(::vfd_runtime::variant::Variant {
            id: Cow::Borrowed(#id),
            name: Cow::Borrowed(#name),
            name_zh: Cow::Borrowed(#name_zh),
            literals: Cow::Borrowed(&[#(#literals),*]),
        })
    });
    let selected_by = match &variants.selected_by {
        Some(selector) => {
            let register = int_literal(selector.register);
            let values = selector.values.iter().map(|v| {
                let (value, variant) = (int_literal(v.value), int_literal(v.variant));
                quote!(::vfd_runtime::variant::VariantValue { value: #value, variant: #variant })
            });
            quote!(Some(::vfd_runtime::variant::VariantSelector {
                register: #register,
                values: Cow::Borrowed(&[#(#values),*]),
            }))
        }
        None => quote!(None),
    };
    let mismatch = match variants.mismatch_error {
        Some(code) => {
            let code = int_literal(code);
            quote!(Some(#code))
        }
        None => quote!(None),
    };
    quote!(Some(::vfd_runtime::variant::Variants {
        current: #current,
        choices: Cow::Borrowed(&[#(#choices),*]),
        selected_by: #selected_by,
        mismatch_error: #mismatch,
    }))
}

/// A `LinkTiming` literal (`LinkTiming::NONE` when the drive states no rule).
fn link_timing_tokens(timing: &vfd_runtime::serial::LinkTiming) -> TokenStream {
    use vfd_runtime::serial::{BeforeStart, LinkTiming};
    if *timing == LinkTiming::NONE {
        return quote!(::vfd_runtime::serial::LinkTiming::NONE);
    }
    let micros = |d: std::time::Duration| int_literal(d.as_micros() as u64);
    let gap = micros(timing.frame_gap_min);
    let inner = Literal::f32_unsuffixed(timing.max_inner_gap_chars);
    let before_start = match timing.before_start {
        BeforeStart::Skip => quote!(Skip),
        BeforeStart::Reject => quote!(Reject),
    };
    let reply_delay = match &timing.reply_delay {
        Some(delay) => {
            let registers = delay.registers.iter().map(|r| int_literal(*r));
            let (step, default, max) =
                (micros(delay.step), micros(delay.default), micros(delay.max));
            quote!(Some(::vfd_runtime::serial::ReplyDelay {
                registers: Cow::Borrowed(&[#(#registers),*]),
                step: ::std::time::Duration::from_micros(#step),
                default: ::std::time::Duration::from_micros(#default),
                max: ::std::time::Duration::from_micros(#max),
            }))
        }
        None => quote!(None),
    };
    quote!(::vfd_runtime::serial::LinkTiming {
        frame_gap_min: ::std::time::Duration::from_micros(#gap),
        max_inner_gap_chars: #inner,
        before_start: ::vfd_runtime::serial::BeforeStart::#before_start,
        reply_delay: #reply_delay,
    })
}
