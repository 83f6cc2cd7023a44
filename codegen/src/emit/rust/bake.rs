//! The one way a runtime value becomes Rust tokens: [`Bake`], implemented beside each other
//! for every runtime type the generated code holds.
//!
//! Baked values use short paths (`Role::Address`, `FieldSpec::new(..)`): the module that
//! holds them imports the type names (see `protocols.rs` and `registers.rs`). Matches are
//! exhaustive, so a new variant in the runtime fails to compile here until it is baked.
//! Structures with many fields bake as the runtime's const constructors plus `with_*` calls
//! for what differs from the defaults, which keeps the generated code short.

use proc_macro2::{Literal, TokenStream};
use quote::{quote, ToTokens};
use vfd_runtime::meaning::{Direction, FrameMeaning};
use vfd_runtime::plan::{ChecksumStep, FieldStep, FramePlan, LengthStep, Step};
use vfd_runtime::serial::Parity;
use vfd_runtime::units::Unit;
use vfd_runtime::{
    Access, AddressMap, BitsSpec, ChecksumAlgorithm, ChecksumSpec, CommandKind, Counts, DataType,
    DecodeErrorKind, Encoding, FieldSpec, Format, FrameLayout, LengthSpec, Part, PreStep, Presence,
    Role, SizedBy, Space, TakesEffect, WordSpec,
};

/// Turns a runtime value into the tokens of an expression that rebuilds it.
pub(crate) trait Bake {
    /// The expression.
    fn bake(&self) -> TokenStream;
}

/// An unsuffixed integer literal.
pub(crate) fn int_literal(value: impl TryInto<i128>) -> Literal {
    // Every integer type the IR holds fits i128.
    Literal::i128_unsuffixed(value.try_into().ok().unwrap_or_default())
}

/// `&[1, 2, 3]` with unsuffixed literals.
fn int_slice(values: &[u32]) -> TokenStream {
    let values = values.iter().map(|v| int_literal(*v));
    quote!(&[#(#values),*])
}

macro_rules! bake_unit_enum {
    ($type:ident { $($variant:ident),* $(,)? }) => {
        impl Bake for $type {
            fn bake(&self) -> TokenStream {
                match self {
                    $($type::$variant => quote!($type::$variant),)*
                }
            }
        }
    };
}

bake_unit_enum!(Unit {
    None,
    Hertz,
    Second,
    Percent,
    Ampere,
    Volt,
    Hour,
    Kilowatt,
    Rpm
});
bake_unit_enum!(Access {
    ReadOnly,
    ReadWrite,
    WriteOnly
});
bake_unit_enum!(DataType {
    Word,
    DoubleWord,
    Bit,
    Text,
    Byte
});
bake_unit_enum!(Space { Parameter, Coil });
bake_unit_enum!(TakesEffect {
    Immediately,
    AfterReset
});
bake_unit_enum!(CommandKind {
    Read,
    WriteRam,
    WritePersistent,
    ReadText,
    Process,
    Block,
    Echo
});
bake_unit_enum!(Parity { None, Even, Odd });
bake_unit_enum!(Role {
    Address,
    Command,
    Register,
    Data,
    ErrorCode,
    Index,
    Process1,
    Process2,
    Text,
    Decimals,
    Words,
    ReadCount,
    WriteStatus,
    ReplyWait
});
bake_unit_enum!(Format {
    Decimal,
    Hex,
    Char,
    U8,
    U16Be,
    U16Le,
    U32Be,
    U32Le,
    UintBe,
    UintLe,
    Bytes
});
bake_unit_enum!(ChecksumAlgorithm {
    Sum8,
    Xor8,
    Crc16Modbus,
    Lrc8
});
bake_unit_enum!(SizedBy {
    Format,
    Rest,
    Length
});
bake_unit_enum!(DecodeErrorKind {
    UnexpectedByte,
    NotAllowed,
    ChecksumMismatch,
    LengthMismatch,
    Truncated,
    TrailingBytes
});
bake_unit_enum!(Direction { Request, Reply });

impl Bake for FrameMeaning {
    /// A `FrameMeaning` literal naming only the fields the frame carries.
    fn bake(&self) -> TokenStream {
        fn some(value: Option<TokenStream>) -> TokenStream {
            match value {
                Some(value) => quote!(Some(#value)),
                None => quote!(None),
            }
        }
        let mut fields = Vec::new();
        let mut field = |name: &str, value: Option<TokenStream>| {
            if let Some(value) = value {
                let name = proc_macro2::Ident::new(name, proc_macro2::Span::call_site());
                let value = some(Some(value));
                fields.push(quote!(#name: #value));
            }
        };
        let int = |v: Option<u32>| v.map(|v| int_literal(v).into_token_stream());
        field("address", int(self.address.map(u32::from)));
        field(
            "broadcast",
            self.broadcast.map(|broadcast| {
                let shown = broadcast.to_string();
                quote!(#shown.parse().expect("a broadcast as written"))
            }),
        );
        field("code", int(self.code));
        field("kind", self.kind.map(|k| k.bake()));
        field("space", self.space.map(|s| s.bake()));
        field("register", int(self.register.map(u32::from)));
        field("wire_register", int(self.wire_register.map(u32::from)));
        field("index", int(self.index.map(u32::from)));
        field("data", int(self.data));
        field("error_code", int(self.error_code.map(u32::from)));
        field(
            "process",
            self.process.map(|[a, b]| {
                let (a, b) = (int_literal(a), int_literal(b));
                quote!([#a, #b])
            }),
        );
        field("text", self.text.as_ref().map(|t| quote!(#t.to_owned())));
        field(
            "words",
            self.words.as_ref().map(|words| {
                let words = words.iter().map(|w| int_literal(*w));
                quote!(vec![#(#words),*])
            }),
        );
        field("read_count", int(self.read_count));
        field("write_status", int(self.write_status));
        field("reply_wait", int(self.reply_wait));
        if self.tripped {
            fields.push(quote!(tripped: true));
        }
        quote!(FrameMeaning { #(#fields,)* ..FrameMeaning::default() })
    }
}

impl Bake for vfd_runtime::BlockSpec {
    /// A `BlockSpec` literal with borrowed lists (full paths: few modules hold one).
    fn bake(&self) -> TokenStream {
        let selectors = |list: &[vfd_runtime::BlockSelector]| {
            let items = list.iter().map(|s| {
                let (register, default) = (int_literal(s.register), int_literal(s.default));
                quote!(::vfd_runtime::BlockSelector { register: #register, default: #default })
            });
            quote!(Cow::Borrowed(&[#(#items),*]))
        };
        let choices = |list: &[vfd_runtime::BlockChoice]| {
            let items = list.iter().map(|c| {
                let value = int_literal(c.value);
                let register = match c.register {
                    Some(r) => {
                        let r = int_literal(r);
                        quote!(Some(#r))
                    }
                    None => quote!(None),
                };
                quote!(::vfd_runtime::BlockChoice { value: #value, register: #register })
            });
            quote!(Cow::Borrowed(&[#(#items),*]))
        };
        let registers = |list: &[u16]| {
            let items = list.iter().map(|r| int_literal(*r));
            quote!(Cow::Borrowed(&[#(#items),*]))
        };
        let modes = self.modes.iter().map(|m| {
            let (register, value, default) = (
                int_literal(m.register),
                int_literal(m.value),
                int_literal(m.default),
            );
            let (write, read) = (registers(&m.write), registers(&m.read));
            quote!(::vfd_runtime::BlockMode {
                register: #register,
                value: #value,
                default: #default,
                write: #write,
                read: #read,
            })
        });
        let (write, read) = (selectors(&self.write), selectors(&self.read));
        let (write_choices, read_choices) =
            (choices(&self.write_choices), choices(&self.read_choices));
        quote!(::vfd_runtime::BlockSpec {
            write: #write,
            read: #read,
            write_choices: #write_choices,
            read_choices: #read_choices,
            modes: Cow::Borrowed(&[#(#modes),*]),
        })
    }
}

impl Bake for Presence {
    fn bake(&self) -> TokenStream {
        match self {
            Presence::IfFormatMatches => quote!(Presence::IfFormatMatches),
            Presence::IfByteAtMost(limit) => {
                let limit = int_literal(*limit);
                quote!(Presence::IfByteAtMost(#limit))
            }
        }
    }
}

impl Bake for Counts {
    fn bake(&self) -> TokenStream {
        match self {
            Counts::Parts { from, through } => {
                let (from, through) = (int_literal(*from), int_literal(*through));
                quote!(Counts::Parts { from: #from, through: #through })
            }
            Counts::DataSize => quote!(Counts::DataSize),
        }
    }
}

impl Bake for AddressMap {
    fn bake(&self) -> TokenStream {
        let (multiply, offset) = (int_literal(self.multiply), int_literal(self.offset));
        quote!(AddressMap { multiply: #multiply, offset: #offset })
    }
}

impl Bake for PreStep {
    fn bake(&self) -> TokenStream {
        match *self {
            PreStep::Index { register } => {
                let register = int_literal(register);
                quote!(PreStep::Index { register: #register })
            }
            PreStep::Persistence {
                space,
                register,
                data_type,
                ram,
                persistent,
            } => {
                let (space, data_type) = (space.bake(), data_type.bake());
                let (register, ram, persistent) = (
                    int_literal(register),
                    int_literal(ram),
                    int_literal(persistent),
                );
                quote! {
                    PreStep::Persistence {
                        space: #space,
                        register: #register,
                        data_type: #data_type,
                        ram: #ram,
                        persistent: #persistent,
                    }
                }
            }
        }
    }
}

impl Bake for FieldSpec {
    fn bake(&self) -> TokenStream {
        let name = self.name.as_ref();
        let (role, format, width) = (
            self.role.bake(),
            self.format.bake(),
            int_literal(self.width),
        );
        let mut tokens = quote!(FieldSpec::new(#name, #role, #format, #width));
        if self.min_width != self.width {
            let min_width = int_literal(self.min_width);
            tokens.extend(quote!(.with_min_width(#min_width)));
        }
        if let Some(presence) = self.optional {
            let presence = presence.bake();
            tokens.extend(quote!(.with_optional(#presence)));
        }
        if !self.allowed.is_empty() {
            let allowed = int_slice(&self.allowed);
            tokens.extend(quote!(.with_allowed(#allowed)));
        }
        if self.fold_case {
            tokens.extend(quote!(.with_fold_case()));
        }
        if self.sized_by != SizedBy::Format {
            let sized_by = self.sized_by.bake();
            tokens.extend(quote!(.with_sized_by(#sized_by)));
        }
        if let Some(broadcast) = &self.broadcast {
            let mut encoding = match broadcast.all_value {
                Some(value) => {
                    let value = int_literal(value);
                    quote!(BroadcastAddress::value(#value))
                }
                None => {
                    let bytes = Literal::byte_string(&broadcast.all_bytes);
                    quote!(BroadcastAddress::bytes(#bytes))
                }
            };
            if let Some(wildcard) = broadcast.wildcard {
                let wildcard = Literal::u8_suffixed(wildcard);
                encoding.extend(quote!(.with_wildcard(#wildcard)));
            }
            tokens.extend(quote!(.with_broadcast(#encoding)));
        }
        tokens
    }
}

impl Bake for ChecksumSpec {
    fn bake(&self) -> TokenStream {
        let name = self.name.as_ref();
        let (algorithm, format) = (self.algorithm.bake(), self.format.bake());
        let covers_from = int_literal(self.covers_from);
        let mut tokens = quote!(ChecksumSpec::new(#name, #algorithm, #format, #covers_from));
        if !self.marker.is_empty() {
            let marker = Literal::byte_string(&self.marker);
            tokens.extend(quote!(.with_marker(#marker)));
        }
        if self.optional {
            tokens.extend(quote!(.with_optional()));
        }
        if let Some(through) = self.covers_through {
            let through = int_literal(through);
            tokens.extend(quote!(.with_covers_through(#through)));
        }
        tokens
    }
}

impl Bake for BitsSpec {
    fn bake(&self) -> TokenStream {
        let name = self.name.as_ref();
        let role = self.role.bake();
        let (lsb, width) = (int_literal(self.lsb), int_literal(self.width));
        let mut tokens = quote!(BitsSpec::new(#name, #role, #lsb, #width));
        if !self.allowed.is_empty() {
            let allowed = int_slice(&self.allowed);
            tokens.extend(quote!(.with_allowed(#allowed)));
        }
        tokens
    }
}

impl Bake for WordSpec {
    fn bake(&self) -> TokenStream {
        let name = self.name.as_ref();
        let format = self.format.bake();
        let fields = self.fields.iter().map(Bake::bake);
        // A struct literal, not a const fn call: only through literals and tuple
        // constructors does a `&[..]` in a `const` live for `'static`.
        quote!(WordSpec { name: Cow::Borrowed(#name), format: #format, fields: Cow::Borrowed(&[#(#fields),*]) })
    }
}

impl Bake for LengthSpec {
    fn bake(&self) -> TokenStream {
        let name = self.name.as_ref();
        let (format, counts) = (self.format.bake(), self.counts.bake());
        let mut tokens = quote!(LengthSpec::new(#name, #format, #counts));
        if (self.times, self.per) != (1, 1) {
            let (times, per) = (int_literal(self.times), int_literal(self.per));
            tokens.extend(quote!(.with_ratio(#times, #per)));
        }
        tokens
    }
}

impl Bake for Part {
    fn bake(&self) -> TokenStream {
        match self {
            Part::Literal {
                name,
                bytes,
                optional,
            } => {
                let name = name.as_ref();
                let bytes = Literal::byte_string(bytes);
                if *optional {
                    quote!(Part::optional_literal(#name, #bytes))
                } else {
                    quote!(Part::literal(#name, #bytes))
                }
            }
            Part::Field(field) => {
                let field = field.bake();
                quote!(Part::Field(#field))
            }
            Part::Checksum(spec) => {
                let spec = spec.bake();
                quote!(Part::Checksum(#spec))
            }
            Part::Word(word) => {
                let word = word.bake();
                quote!(Part::Word(#word))
            }
            Part::Length(length) => {
                let length = length.bake();
                quote!(Part::Length(#length))
            }
        }
    }
}

impl Bake for FrameLayout {
    fn bake(&self) -> TokenStream {
        let name = self.name.as_ref();
        let parts = self.parts.iter().map(Bake::bake);
        // A struct literal, not a const fn call: only through literals and tuple
        // constructors does a `&[..]` in a `const` live for `'static`.
        let encoding = match self.encoding {
            Encoding::Binary => quote!(Binary),
            Encoding::HexPairs => quote!(HexPairs),
        };
        let plan = match &self.plan {
            Some(plan) => {
                let plan = plan.bake();
                quote!(Some(#plan))
            }
            None => quote!(None),
        };
        quote!(FrameLayout {
            name: Cow::Borrowed(#name),
            parts: Cow::Borrowed(&[#(#parts),*]),
            encoding: Encoding::#encoding,
            plan: #plan,
        })
    }
}

/// A layout's plan, as const data: computed at build time by the runtime's
/// [`FramePlan::of`]. Its compiled functions are added by [`compiled_plan`].
impl Bake for FramePlan {
    fn bake(&self) -> TokenStream {
        let steps = self.steps.iter().map(Bake::bake);
        quote!(::vfd_runtime::plan::FramePlan {
            steps: Cow::Borrowed(&[#(#steps),*]),
            compiled: None,
        })
    }
}

impl Bake for FieldStep {
    fn bake(&self) -> TokenStream {
        let (role, format) = (self.role.bake(), self.format.bake());
        let (width, min_width) = (int_literal(self.width), int_literal(self.min_width));
        let optional = match &self.optional {
            Some(presence) => {
                let presence = presence.bake();
                quote!(Some(#presence))
            }
            None => quote!(None),
        };
        let (by_length, checked, open_digits) = (self.by_length, self.checked, self.open_digits);
        quote!(::vfd_runtime::plan::FieldStep {
            role: #role,
            format: #format,
            width: #width,
            min_width: #min_width,
            optional: #optional,
            by_length: #by_length,
            checked: #checked,
            open_digits: #open_digits,
        })
    }
}

impl Bake for LengthStep {
    fn bake(&self) -> TokenStream {
        let (format, counts) = (self.format.bake(), self.counts.bake());
        let (times, per) = (int_literal(self.times), int_literal(self.per));
        quote!(::vfd_runtime::plan::LengthStep {
            format: #format,
            counts: #counts,
            times: #times,
            per: #per,
        })
    }
}

impl Bake for ChecksumStep {
    fn bake(&self) -> TokenStream {
        let (algorithm, format) = (self.algorithm.bake(), self.format.bake());
        let covers_from = int_literal(self.covers_from);
        let covers_through = match self.covers_through {
            Some(through) => {
                let through = int_literal(through);
                quote!(Some(#through))
            }
            None => quote!(None),
        };
        let optional = self.optional;
        quote!(::vfd_runtime::plan::ChecksumStep {
            algorithm: #algorithm,
            format: #format,
            covers_from: #covers_from,
            covers_through: #covers_through,
            optional: #optional,
        })
    }
}

impl Bake for Step {
    fn bake(&self) -> TokenStream {
        match self {
            Step::Literal { optional } => {
                quote!(::vfd_runtime::plan::Step::Literal { optional: #optional })
            }
            Step::Field(step) => {
                let step = step.bake();
                quote!(::vfd_runtime::plan::Step::Field(#step))
            }
            Step::Word { format } => {
                let format = format.bake();
                quote!(::vfd_runtime::plan::Step::Word { format: #format })
            }
            Step::Length(step) => {
                let step = step.bake();
                quote!(::vfd_runtime::plan::Step::Length(#step))
            }
            Step::Checksum(step) => {
                let step = step.bake();
                quote!(::vfd_runtime::plan::Step::Checksum(#step))
            }
        }
    }
}

/// A layout with a plan, written once: its parts as a `const` slice, its steps lowered from
/// them by the compiler (`plan::steps`), and its compiled functions written by
/// `compiled_plan!` from the two; the layout `const` names all three. `(items, value)`:
/// the items to put beside the layout and the layout's value. A layout without a plan is
/// its value alone.
pub(crate) fn compiled_plan(
    layout: &FrameLayout,
    constant: &proc_macro2::Ident,
    decode: &proc_macro2::Ident,
    encode: &proc_macro2::Ident,
) -> (TokenStream, TokenStream) {
    if layout.plan.is_none() {
        return (TokenStream::new(), layout.bake());
    }
    let name = layout.name.as_ref();
    let parts = layout.parts.iter().map(Bake::bake);
    let encoding = match layout.encoding {
        Encoding::Binary => quote!(Binary),
        Encoding::HexPairs => quote!(HexPairs),
    };
    let parts_name = quote::format_ident!("{constant}_PARTS");
    let steps_name = quote::format_ident!("{constant}_STEPS");
    let count = int_literal(layout.parts.len());
    let indexes = (0..layout.parts.len()).map(int_literal);
    let items = quote! {
        const #parts_name: &[Part] = &[#(#parts),*];
        const #steps_name: [::vfd_runtime::plan::Step; #count] = ::vfd_runtime::plan::steps(#parts_name);
        ::vfd_runtime::compiled_plan!(#decode, #encode: #parts_name, #steps_name, [#(#indexes)*]);
    };
    let value = quote!(FrameLayout {
        name: Cow::Borrowed(#name),
        parts: Cow::Borrowed(#parts_name),
        encoding: Encoding::#encoding,
        plan: Some(::vfd_runtime::plan::FramePlan {
            steps: Cow::Borrowed(&#steps_name),
            compiled: Some(::vfd_runtime::plan::Compiled {
                decode: #decode,
                encode: #encode,
            }),
        }),
    });
    (items, value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every baked value is valid Rust: it parses as an expression.
    fn parses(tokens: TokenStream) -> String {
        syn::parse2::<syn::Expr>(tokens.clone())
            .unwrap_or_else(|e| panic!("{tokens} does not parse: {e}"));
        tokens.to_string()
    }

    #[test]
    fn unit_variants_bake_to_their_paths() {
        assert_eq!(parses(Unit::Hertz.bake()), "Unit :: Hertz");
        assert_eq!(parses(Access::ReadOnly.bake()), "Access :: ReadOnly");
        assert_eq!(parses(Format::UintLe.bake()), "Format :: UintLe");
        assert_eq!(parses(Parity::Even.bake()), "Parity :: Even");
    }

    #[test]
    fn a_field_bakes_only_what_differs_from_the_defaults() {
        let field = FieldSpec::new("station", Role::Address, Format::Decimal, 2);
        assert_eq!(
            parses(field.bake()),
            "FieldSpec :: new (\"station\" , Role :: Address , Format :: Decimal , 2)"
        );
        let field = field
            .with_min_width(1)
            .with_allowed(&[82, 87])
            .with_fold_case();
        assert_eq!(
            parses(field.bake()),
            "FieldSpec :: new (\"station\" , Role :: Address , Format :: Decimal , 2) . with_min_width (1) . with_allowed (& [82 , 87]) . with_fold_case ()"
        );
    }

    #[test]
    fn literals_are_unsuffixed() {
        let tokens = parses(PreStep::Index { register: 8 }.bake());
        assert_eq!(tokens, "PreStep :: Index { register : 8 }");
        assert_eq!(int_literal(1200u32).to_string(), "1200");
    }
}
