//! Emits one marker type per register: its manual text as docs, its `RegisterInfo` as one
//! const builder chain, its value type, and the `Writable`/`Persistable` markers. Reading
//! and writing are the runtime's generic trait methods, so nothing else is repeated.

use super::*;
use crate::emit::words::{address_label, default_text, inferred_text, range_text, warning_text};
use proc_macro2::{Delimiter, Group};
use vfd_runtime::{Access, DataType, Space, TakesEffect};

fn register_doc(drive: &DriveIr, register: &RegisterIr) -> Vec<String> {
    let mut lines = vec![
        format!(
            "**{} — {}**{}",
            register.code,
            register.name,
            zh(&register.name_zh)
        ),
        String::new(),
    ];
    if !register.aliases.is_empty() {
        lines.push(format!("Also named {}.", register.aliases.join(", ")));
        lines.push(String::new());
    }
    let mut facts = vec![if register.wire_only {
        "no address of its own (its protocols reach it by its wire numbers)".to_owned()
    } else {
        format!("address `{}`", address_label(register))
    }];
    let unit = register.unit.symbol();
    if !unit.is_empty() {
        facts.push(format!("unit {unit} in steps of {}", register.scale));
    } else if (register.scale - 1.0).abs() > f64::EPSILON {
        facts.push(format!("steps of {}", register.scale));
    }
    facts.push(format!("range {}", range_text(register)));
    facts.push(format!("default {}", default_text(register)));
    facts.push(register.access.as_str().to_owned());
    if register.ram_only {
        facts.push("RAM only (no persistent write)".into());
    }
    if register.persistent_write_to_ram {
        facts.push("a persistent write is accepted but stored in RAM only".into());
    }
    facts.push(if register.writable_while_running {
        "writable while running".into()
    } else if register.while_running_unknown {
        "the manual does not say whether it may be written while running (the write is attempted; a refusal is reported)".into()
    } else {
        "not writable while running".into()
    });
    if register.panel_only {
        facts.push("effective only when set from the panel".into());
    }
    if register.no_reply {
        facts.push("writes are never answered (sending returns once the frame is sent)".into());
    }
    if register.takes_effect == TakesEffect::AfterReset {
        facts.push("takes effect after a reset".into());
    }
    lines.push(format!("{}.", facts.join(", ")));
    if !register.inferred.is_empty() {
        lines.push(String::new());
        lines.push(format!(
            "Inferred by the description, not stated by the manual: {}.",
            inferred_text(&register.inferred)
        ));
    }
    for warning in &register.warnings {
        lines.push(String::new());
        lines.push(format!("**Warning:** {}", warning_text(warning)));
    }
    for line in relation_lines(register) {
        lines.push(String::new());
        lines.push(line);
    }
    for text in [&register.description, &register.note] {
        if !text.is_empty() {
            lines.push(String::new());
            lines.push(text.clone());
        }
    }
    lines.push(String::new());
    lines.push(format!(
        "Source: {}, section {}.",
        drive.manual_cited(),
        register.source
    ));
    lines
}

/// What the description says of the register's relations to others: the live register
/// it holds at a trip, its scale selector, its copies on each port.
pub(crate) fn relation_lines(register: &RegisterIr) -> Vec<String> {
    let mut lines = Vec::new();
    if let Some(live) = &register.held_at_trip_of {
        lines.push(format!(
            "Holds the value {live} had at the moment of the last trip."
        ));
    }
    if let Some(other) = &register.shares_address_with {
        let (this, that) = if register.access == vfd_runtime::Access::WriteOnly {
            ("written", "read")
        } else {
            ("read", "written")
        };
        lines.push(format!(
            "Its address {:04X}h has two meanings: {this}, it is this register; {that}, it is {other}.",
            register.address
        ));
    }
    if register.live_except_while_tripped {
        lines.push("Shows the live value, except while the drive is tripped: then it keeps the value it had.".to_owned());
    }
    if let Some(scale_by) = &register.scale_by {
        let unit = register.unit.symbol();
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        let describe = |selector: String, c: &crate::ir::ScaleChoiceIr| {
            let decimals = usize::from(vfd_runtime::units::decimals_of(c.scale));
            let end = |raw: i64| format!("{:.*}", decimals, raw as f64 * c.scale);
            format!(
                "{} {selector}: steps of {}{unit} ({}-{}{unit})",
                scale_by.register,
                c.scale,
                end(c.raw_min),
                end(c.raw_max),
            )
        };
        let mut choices: Vec<String> = scale_by
            .choices
            .iter()
            .map(|c| describe(format!("= {}", c.value), c))
            .collect();
        if let Some(other) = &scale_by.otherwise {
            choices.push(describe("any other value".to_owned(), other));
        }
        lines.push(format!(
            "Its scale is chosen by {}: {}.",
            scale_by.register,
            choices.join("; ")
        ));
    }
    for special in &register.special_values {
        lines.push(format!(
            "Also takes {} (`{}`: {}{}), carried as {:04X}h.",
            special.value,
            special.id,
            special.name,
            if special.name_zh.is_empty() {
                String::new()
            } else {
                format!(" / {}", special.name_zh)
            },
            special.raw
        ));
    }
    if !register.per_port.is_empty() {
        let copies: Vec<String> = register
            .per_port
            .iter()
            .map(|(port, code)| format!("{code} on port `{port}`"))
            .collect();
        lines.push(format!("Exists once per port: {}.", copies.join(", ")));
    }
    lines
}

/// The register's `RegisterInfo` as a const builder chain naming only what differs from
/// [`vfd_runtime::RegisterInfo::new`]'s defaults.
fn info_chain(drive: &DriveIr, register: &RegisterIr) -> TokenStream {
    let address = hex_u16(register.address);
    let (code, id, name, name_zh) = (
        str_literal(&register.code),
        str_literal(&register.id),
        str_literal(&register.name),
        str_literal(&register.name_zh),
    );
    let mut chain = quote!(RegisterInfo::new(#address, #code, #id).with_names(#name, #name_zh));
    if !register.aliases.is_empty() {
        let aliases = register.aliases.iter().map(|alias| str_literal(alias));
        chain.extend(quote!(.with_aliases(&[#(#aliases),*])));
    }
    if register.unit != vfd_runtime::units::Unit::None || register.scale != 1.0 {
        let unit = register.unit.bake();
        let scale = f64_literal(register.scale);
        chain.extend(quote!(.with_unit(#unit, #scale)));
    }
    if register.signed {
        chain.extend(quote!(.with_signed()));
    }
    if register.data_type != DataType::Word {
        let data_type = register.data_type.bake();
        chain.extend(quote!(.with_data_type(#data_type)));
    }
    let (raw_min, raw_max) = register.raw_range();
    if (raw_min, raw_max) != (0, i64::from(u16::MAX)) {
        let (raw_min, raw_max) = (int_literal(raw_min), int_literal(raw_max));
        chain.extend(quote!(.with_raw_range(#raw_min, #raw_max)));
    }
    if let Some(code) = register.min.as_ref().and_then(|b| b.register.as_ref()) {
        let code = str_literal(code);
        chain.extend(quote!(.with_min_bound(#code)));
    }
    if let Some(code) = register.max.as_ref().and_then(|b| b.register.as_ref()) {
        let code = str_literal(code);
        chain.extend(quote!(.with_max_bound(#code)));
    }
    if register.access != Access::ReadWrite {
        let access = register.access.bake();
        chain.extend(quote!(.with_access(#access)));
    }
    if register.ram_only {
        chain.extend(quote!(.with_ram_only()));
    }
    if register.persistent_write_to_ram {
        chain.extend(quote!(.with_persistent_write_to_ram()));
    }
    if register.wire_only {
        chain.extend(quote!(.without_address()));
    }
    if register.writable_while_running {
        chain.extend(quote!(.with_writable_while_running()));
    }
    if register.while_running_unknown {
        chain.extend(quote!(.with_while_running_unknown()));
    }
    if register.panel_only {
        chain.extend(quote!(.with_panel_only()));
    }
    if register.no_reply {
        chain.extend(quote!(.with_no_reply()));
    }
    if register.takes_effect != TakesEffect::Immediately {
        let takes_effect = register.takes_effect.bake();
        chain.extend(quote!(.with_takes_effect(#takes_effect)));
    }
    if register.space != Space::Parameter {
        let space = register.space.bake();
        chain.extend(quote!(.with_space(#space)));
    }
    if register.array_len > 0 {
        let len = int_literal(register.array_len);
        chain.extend(quote!(.with_array(#len)));
    }
    if let Some(raw) = register.default_raw() {
        let raw = int_literal(raw);
        chain.extend(quote!(.with_default_raw(#raw)));
    }
    if let Some(id) = bitfield_id(drive, register) {
        let name = super::code_tables::info_const(id);
        chain.extend(quote!(.with_bits(&bits::#name)));
    }
    if let Some(id) = &register.code_table {
        let name = super::code_tables::info_const(id);
        chain.extend(quote!(.with_codes(&codes::#name)));
    }
    let text: Vec<&str> = [register.description.as_str(), register.note.as_str()]
        .into_iter()
        .filter(|t| !t.is_empty())
        .collect();
    if !text.is_empty() {
        let text = str_literal(&text.join(" "));
        chain.extend(quote!(.with_text(#text)));
    }
    if let Some(live) = &register.held_at_trip_of {
        let live = str_literal(live);
        chain.extend(quote!(.with_held_at_trip_of(#live)));
    }
    if register.live_except_while_tripped {
        chain.extend(quote!(.with_live_except_while_tripped()));
    }
    if register.scale_by.is_some() {
        let name = scale_by_const(register);
        chain.extend(quote!(.with_scale_by(&#name)));
    }
    if !register.special_values.is_empty() {
        let specials = register.special_values.iter().map(|special| {
            let (value, raw) = (f64_literal(special.value), int_literal(special.raw));
            let (id, name) = (str_literal(&special.id), str_literal(&special.name));
            quote!(::vfd_runtime::SpecialValue { value: #value, raw: #raw, id: #id, name: #name })
        });
        chain.extend(quote!(.with_special_values(&[#(#specials),*])));
    }
    if !register.per_port.is_empty() {
        let pairs = register.per_port.iter().map(|(port, code)| {
            let (port, code) = (str_literal(port), str_literal(code));
            quote!((#port, #code))
        });
        chain.extend(quote!(.with_per_port(&[#(#pairs),*])));
    }
    chain
}

/// The name of the const holding a register's `ScaleBy`.
fn scale_by_const(register: &RegisterIr) -> Ident {
    ident(&format!(
        "SCALE_BY_{}",
        crate::naming::const_name(&register.id)
    ))
}

/// The `ScaleBy` const of a register whose scale another register chooses: per choice,
/// the register's info with that choice's scale and raw range (and no default, which is
/// given in the register's own scale).
fn scale_by_item(drive: &DriveIr, register: &RegisterIr) -> TokenStream {
    let Some(scale_by) = &register.scale_by else {
        return quote!();
    };
    let name = scale_by_const(register);
    let selector = str_literal(&scale_by.register);
    let info_of =
        |choice: &crate::ir::ScaleChoiceIr| info_chain(drive, &register.with_scale_choice(choice));
    let choices = scale_by.choices.iter().map(|choice| {
        let info = info_of(choice);
        let value = int_literal(choice.value);
        quote!(::vfd_runtime::ScaleChoice { value: #value, info: &#info })
    });
    let otherwise = match &scale_by.otherwise {
        Some(choice) => {
            let info = info_of(choice);
            quote!(Some(&#info))
        }
        None => quote!(None),
    };
    let doc = doc_text(format!(
        "The scale of {} as register {} chooses it.",
        register.code, scale_by.register
    ));
    quote! {
        #[doc = #doc]
        const #name: ::vfd_runtime::ScaleBy = ::vfd_runtime::ScaleBy {
            register: #selector,
            choices: &[#(#choices),*],
            otherwise: #otherwise,
        };
    }
}

pub(super) fn registers_module(drive: &DriveIr) -> TokenStream {
    let imports = registers_imports(drive);
    // The module's items are appended to one stream as they are made: interpolating a
    // stream with `#` copies it, which a 10,000-register drive would do 10,000 times.
    let mut body = quote! {
        #imports
        /// Register metadata as [`Register::INFO`] holds it.
        type Info = &'static RegisterInfo;
    };
    let mut all = Vec::new();
    for register in &drive.registers {
        let name = ident(&register.type_name);
        let docs: Vec<Literal> = register_doc(drive, register)
            .iter()
            .map(|line| str_literal(&doc_text(line)))
            .collect();
        let value = value_type(&register.value);
        let info = info_chain(drive, register);
        let mut markers = Vec::new();
        if register.writable() {
            markers.push(quote!(impl Writable for #name {}));
        }
        if register.persistable() {
            markers.push(quote!(impl Persistable for #name {}));
        }
        body.extend(scale_by_item(drive, register));
        body.extend(quote! {
            #(#[doc = #docs])*
            #[derive(Debug, Clone, Copy)]
            pub struct #name;
            impl Register for #name {
                type Drive = super::Drive;
                const INFO: Info = &#info;
                type Value = #value;
            }
            #(#markers)*
        });
        for alias in &register.aliases {
            if let Some(alias_name) = crate::naming::alias_type_name(alias) {
                let alias_name = ident(&alias_name);
                let doc = str_literal(&format!(
                    " {alias}: the manual's other name for [`{}`] ({}).",
                    register.type_name, register.code
                ));
                body.extend(quote! {
                    #[doc = #doc]
                    pub type #alias_name = #name;
                });
            }
        }
        all.push(quote!(#name::INFO));
    }
    let count = int_literal(all.len());
    body.extend(quote! {
        /// Every register, in the manual's order.
        pub static ALL: [&RegisterInfo; #count] = [#(#all),*];
    });
    let body = Group::new(Delimiter::Brace, body);
    quote! {
        /// One type per register. Each implements [`vfd_runtime::Register`], and
        /// [`vfd_runtime::Writable`] or [`vfd_runtime::Persistable`] when the manual allows
        /// it: read with `R::read()`, write with `R::write_ram(value)` (the traits come into
        /// scope with `use vfd_runtime::prelude::*`).
        pub mod registers #body
    }
}

/// The id of the bit-field layout of a bit-field register.
fn bitfield_id<'d>(drive: &'d DriveIr, register: &RegisterIr) -> Option<&'d str> {
    let ValueKind::Bitfield(type_name) = &register.value else {
        return None;
    };
    drive
        .bitfields
        .iter()
        .find(|b| &b.type_name == type_name)
        .map(|b| b.id.as_str())
}

/// The `use` lines the registers module needs, so each item can use short paths.
fn registers_imports(drive: &DriveIr) -> TokenStream {
    let registers = &drive.registers;
    let mut runtime = vec![quote!(Register), quote!(RegisterInfo)];
    if registers.iter().any(|r| r.writable()) {
        runtime.push(quote!(Writable));
    }
    if registers.iter().any(|r| r.persistable()) {
        runtime.push(quote!(Persistable));
    }
    for (used, name) in [
        (
            registers.iter().any(|r| r.access != Access::ReadWrite),
            quote!(Access),
        ),
        (
            registers.iter().any(|r| r.data_type != DataType::Word),
            quote!(DataType),
        ),
        (
            registers.iter().any(|r| r.space != Space::Parameter),
            quote!(Space),
        ),
        (
            registers
                .iter()
                .any(|r| r.takes_effect != TakesEffect::Immediately),
            quote!(TakesEffect),
        ),
    ] {
        if used {
            runtime.push(name);
        }
    }
    let mut units: Vec<TokenStream> = Vec::new();
    if registers
        .iter()
        .any(|r| r.unit != vfd_runtime::units::Unit::None || r.scale != 1.0)
    {
        units.push(quote!(Unit));
    }
    let mut quantities: Vec<&str> = registers
        .iter()
        .filter_map(|r| match &r.value {
            ValueKind::Quantity(name) => Some(name.as_str()),
            _ => None,
        })
        .collect();
    quantities.sort_unstable();
    quantities.dedup();
    units.extend(quantities.into_iter().map(|name| {
        let name = ident(name);
        quote!(#name)
    }));
    let mut local = Vec::new();
    if registers
        .iter()
        .any(|r| matches!(r.value, ValueKind::Bitfield(_)))
    {
        local.push(quote!(bits));
    }
    if registers
        .iter()
        .any(|r| matches!(r.value, ValueKind::CodeTable(_)) || r.code_table.is_some())
    {
        local.push(quote!(codes));
    }
    let units = (!units.is_empty()).then(|| quote!(use ::vfd_runtime::units::{#(#units),*};));
    let local = (!local.is_empty()).then(|| quote!(use super::{#(#local),*};));
    quote! {
        use ::vfd_runtime::{#(#runtime),*};
        #units
        #local
    }
}
