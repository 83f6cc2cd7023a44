//! Variants: the protocol file's `variants` (other bytes for some literal parts) and the
//! drive's `protocols[].variant` (the register that selects one, the error a frame in
//! another variant's form gets), lowered into the runtime's [`Variants`].

use super::parts::parse_hex;
use super::Input;
use crate::diagnostics::Diagnostics;
use crate::parse::model::{PartModel, VariantLiteralModel};
use std::borrow::Cow;
use std::collections::BTreeSet;
use vfd_runtime::variant::{Variant, VariantLiteral, VariantSelector, VariantValue, Variants};
use vfd_runtime::{Part, Protocol, Space};

/// The protocol's variants as this drive speaks them, checked; `None` when the file has
/// none or a problem was reported.
pub(super) fn lower_variants(
    input: &Input<'_>,
    base: &Protocol,
    out: &mut Diagnostics,
) -> Option<Variants> {
    let models = &input.file.variants;
    let rule_path = format!("{}.variant", input.reference_path);
    if models.is_empty() {
        if input.reference.variant.is_some() {
            out.push(
                input
                    .drive_source
                    .error(
                        &rule_path,
                        format!(
                            "protocol file `{}` declares no variants to select",
                            input.reference.uses
                        ),
                    )
                    .hint("leave `variant` out, or declare `variants:` in the protocol file"),
            );
        }
        return None;
    }
    let before = out.items.len();
    let choices = choices(input, out);
    if out.items.len() > before {
        return None;
    }
    let mut variants = Variants {
        current: 0,
        choices: Cow::Owned(choices),
        selected_by: None,
        mismatch_error: None,
    };
    check_sizes(input, base, &variants, out);
    if let Some(rule) = &input.reference.variant {
        if rule.mismatch_error.is_some() && base.error_reply.is_none() {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{rule_path}.mismatch_error"),
                        "the protocol has no error reply to carry it",
                    )
                    .hint("leave `mismatch_error` out: the drive cannot answer with an error"),
            );
        }
        variants.selected_by = selector(input, &rule.register, &variants, out);
        variants.mismatch_error = rule
            .mismatch_error
            .as_deref()
            .and_then(|id| mismatch_error(input, id, out));
    }
    (out.items.len() == before).then_some(variants)
}

/// Every variant with the bytes of every literal part some variant varies (the first
/// variant's are the parts as written).
fn choices(input: &Input<'_>, out: &mut Diagnostics) -> Vec<Variant> {
    let (file, source) = (input.file, input.source);
    let mut ids = BTreeSet::new();
    if file.variants.len() < 2 {
        out.push(
            source
                .error("variants", "one variant is the protocol itself")
                .hint("declare at least two variants, or leave `variants` out"),
        );
    }
    for (index, model) in file.variants.iter().enumerate() {
        let path = format!("variants[{index}]");
        if !ids.insert(model.id.as_str()) {
            out.push(
                source
                    .error(
                        &format!("{path}.id"),
                        format!("variant `{}` is declared twice", model.id),
                    )
                    .hint("give each variant its own id"),
            );
        }
        if index == 0 && !model.literals.is_empty() {
            out.push(
                source
                    .error(
                        &format!("{path}.literals"),
                        "the first variant is the protocol as its parts are written",
                    )
                    .hint("change the parts under `parts:` instead, or list this variant later"),
            );
        }
    }
    // The literal parts some variant varies, by key, with their bytes as written.
    let mut varied: Vec<(String, Vec<u8>)> = Vec::new();
    for (index, model) in file.variants.iter().enumerate() {
        for key in model.literals.keys() {
            let path = format!("variants[{index}].literals.{key}");
            match file.parts.get(key).map(|part| (part, literal_bytes(part))) {
                Some((part, Some(Ok(bytes)))) => {
                    let name = part.name.clone().unwrap_or_else(|| key.clone());
                    if !varied.iter().any(|(known, _)| *known == name) {
                        varied.push((name, bytes));
                    }
                }
                Some((_, Some(Err(_)))) => {} // reported where the part is lowered
                Some((_, None)) => out.push(
                    source
                        .error(&path, format!("part `{key}` is not a literal"))
                        .hint("a variant gives other bytes to literal parts only"),
                ),
                None => out.push(
                    source
                        .error(&path, format!("part `{key}` is not defined"))
                        .hint(format!(
                            "name a literal part under `parts:`; defined: {}",
                            super::names_of(file.parts.keys())
                        )),
                ),
            }
        }
    }
    file.variants
        .iter()
        .enumerate()
        .map(|(index, model)| {
            let literals = varied
                .iter()
                .map(|(name, written)| {
                    let key = model.literals.iter().find(|(key, _)| {
                        file.parts
                            .get(*key)
                            .is_some_and(|part| part.name.as_deref().unwrap_or(key) == name)
                    });
                    let bytes = match key {
                        Some((key, literal)) => {
                            let path = format!("variants[{index}].literals.{key}");
                            variant_bytes(literal, &path, input, out).unwrap_or_default()
                        }
                        None => written.clone(),
                    };
                    VariantLiteral {
                        part: Cow::Owned(name.clone()),
                        bytes: Cow::Owned(bytes),
                    }
                })
                .collect();
            Variant {
                id: Cow::Owned(model.id.clone()),
                name: Cow::Owned(model.name.clone()),
                name_zh: Cow::Owned(model.name_zh.clone()),
                literals: Cow::Owned(literals),
            }
        })
        .collect()
}

/// A shared part's bytes when it is a literal (`None`: it is another kind of part).
fn literal_bytes(part: &PartModel) -> Option<Result<Vec<u8>, String>> {
    match (&part.literal, &part.literal_hex) {
        (Some(text), None) => Some(Ok(text.as_bytes().to_vec())),
        (None, Some(hex)) => Some(parse_hex(hex)),
        _ => None,
    }
}

/// A variant's bytes for a literal: exactly one of `literal` and `literal_hex`; empty
/// (`{ literal: "" }`) where the variant leaves the part out (no terminator).
fn variant_bytes(
    model: &VariantLiteralModel,
    path: &str,
    input: &Input<'_>,
    out: &mut Diagnostics,
) -> Option<Vec<u8>> {
    let bytes = match (&model.literal, &model.literal_hex) {
        (Some(text), None) => Ok(text.as_bytes().to_vec()),
        (None, Some(hex)) => parse_hex(hex),
        _ => Err("give exactly one of `literal` and `literal_hex`".to_owned()),
    };
    match bytes {
        Ok(bytes) => Some(bytes),
        Err(message) => {
            out.push(
                input
                    .source
                    .error(path, message)
                    .hint("e.g. { literal_hex: \"0D 0A\" } or { literal: \"\\r\\n\" }"),
            );
            None
        }
    }
}

/// Every variant's frames of a fixed size fit `max_frame_len`, and none starts with an
/// empty literal.
fn check_sizes(input: &Input<'_>, base: &Protocol, variants: &Variants, out: &mut Diagnostics) {
    let with_variants = Protocol {
        variants: Some(variants.clone()),
        ..base.clone()
    };
    let max = usize::from(base.max_frame_len);
    for index in 1..variants.choices.len() {
        let Some(protocol) = with_variants.in_variant(index) else {
            continue;
        };
        let layouts = protocol
            .commands
            .iter()
            .flat_map(|c| [&c.request, &c.reply])
            .chain(protocol.error_reply.as_ref());
        for layout in layouts {
            // A variant may leave a literal out (no terminator), but not a frame's start:
            // a receiver finds a frame by it.
            if let Some(Part::Literal { name, bytes, .. }) = layout.parts.first() {
                if bytes.is_empty() {
                    out.push(
                        input
                            .source
                            .error(
                                &format!("variants[{index}].literals"),
                                format!(
                                    "variant `{}` leaves out `{name}`, the start of layout `{}`",
                                    variants.choices[index].id, layout.name
                                ),
                            )
                            .hint("only a literal that does not start a frame may be empty (a terminator: `{ literal: \"\" }`)"),
                    );
                    return;
                }
            }
            let fixed: Option<usize> = layout.parts.iter().map(Part::fixed_size).sum();
            if let Some(size) = fixed.filter(|size| *size > max) {
                out.push(
                    input
                        .source
                        .error(
                            &format!("variants[{index}].literals"),
                            format!(
                                "layout `{}` is {size} bytes in variant `{}`, longer than max_frame_len {max}",
                                layout.name, variants.choices[index].id
                            ),
                        )
                        .hint("raise max_frame_len to the longest frame of every variant"),
                );
                return;
            }
        }
    }
}

/// The register that selects the variant: a parameter whose code table names every
/// variant by a value's id.
fn selector(
    input: &Input<'_>,
    name: &str,
    variants: &Variants,
    out: &mut Diagnostics,
) -> Option<VariantSelector> {
    let path = format!("{}.variant.register", input.reference_path);
    let fail = |message: String, hint: &str, out: &mut Diagnostics| {
        out.push(input.drive_source.error(&path, message).hint(hint));
        None
    };
    let Some(register) = input.drive.registers.iter().find(|r| r.is_named(name)) else {
        return fail(
            format!("no register `{name}`"),
            "name a described register by its code or id",
            out,
        );
    };
    if register
        .space
        .is_some_and(|space| space != Space::Parameter)
    {
        return fail(
            format!("register `{name}` is not a parameter"),
            "the selecting register must be in the parameter space",
            out,
        );
    }
    let Some(table) = register
        .code_table
        .as_deref()
        .and_then(|id| input.drive.codes.iter().find(|t| t.id == id))
    else {
        return fail(
            format!("register `{name}` has no code table to name the variants"),
            "give the register a `code_table` whose values' ids are the variant ids",
            out,
        );
    };
    let mut values = Vec::new();
    for (index, variant) in variants.choices.iter().enumerate() {
        let selecting = table.values.iter().filter(|v| v.id == variant.id);
        let before = values.len();
        for value in selecting {
            values.push(VariantValue {
                value: value.value,
                variant: index as u8,
            });
        }
        if values.len() == before {
            return fail(
                format!(
                    "no value of code table `{}` selects variant `{}`",
                    table.id, variant.id
                ),
                &format!(
                    "the variants are {}: give each variant's id to the value that selects it",
                    variants
                        .choices
                        .iter()
                        .map(|v| v.id.as_ref())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                out,
            );
        }
    }
    values.sort_by_key(|v| v.value);
    Some(VariantSelector {
        register: register.address as u16,
        values: Cow::Owned(values),
    })
}

/// The code of the error `id` in the table naming this protocol's error replies.
fn mismatch_error(input: &Input<'_>, id: &str, out: &mut Diagnostics) -> Option<u16> {
    let table = super::error_codes::error_table(input);
    match table.iter().find(|code| code.id == id) {
        Some(code) => Some(code.code),
        None => {
            out.push(
                input
                    .drive_source
                    .error(
                        &format!("{}.variant.mismatch_error", input.reference_path),
                        format!("no error code `{id}` names this protocol's error replies"),
                    )
                    .hint(format!(
                        "name an error code id of the protocol's table: {}",
                        table
                            .iter()
                            .map(|c| c.id.as_ref())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )),
            );
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{
        drive_with, lower_both, lowered, parts, problems_of, protocol_with,
    };

    const VARIANTS: &str = "error_reply: error_reply\nvariants:\n  - { id: cr, name: CR }\n  - { id: cr_lf, name: CR LF, literals: { cr: { literal_hex: \"0D 0A\" } } }\n  - { id: bang, name: Bang, literals: { start: { literal: \"!\" } } }\n";

    /// A variant as compared: its id, and each varied literal's part name and bytes.
    type Shown<'a> = (&'a str, Vec<(&'a str, &'a [u8])>);

    fn with_variants() -> String {
        protocol_with(&[("error_reply: error_reply\n", VARIANTS)])
    }

    #[test]
    fn every_variant_gets_the_bytes_of_every_literal_some_variant_varies() {
        let protocol = lowered(&with_variants());
        let variants = protocol.variants.as_ref().expect("variants");
        let shown: Vec<Shown> = variants
            .choices
            .iter()
            .map(|choice| {
                let literals = choice
                    .literals
                    .iter()
                    .map(|l| (l.part.as_ref(), l.bytes.as_ref()))
                    .collect();
                (choice.id.as_ref(), literals)
            })
            .collect();
        assert_eq!(
            shown,
            [
                ("cr", vec![("cr", &b"\r"[..]), ("start", b"(")]),
                ("cr_lf", vec![("cr", &b"\r\n"[..]), ("start", b"(")]),
                ("bang", vec![("cr", &b"\r"[..]), ("start", b"!")]),
            ]
        );
        // Without a drive rule nothing selects a variant, and no error answers a mismatch.
        assert_eq!(variants.selected_by, None);
        assert_eq!(variants.mismatch_error, None);
        // The layouts in a variant carry its bytes; the protocol's own stay as written.
        let cr_lf = protocol.in_variant(1).unwrap();
        assert_eq!(
            parts(&cr_lf, "read_request").last(),
            Some(&vfd_runtime::Part::Literal {
                name: "cr".into(),
                bytes: b"\r\n".to_vec().into(),
                optional: false,
            })
        );
        assert_eq!(cr_lf.variant_id(), Some("cr_lf"));
        let bang = protocol.in_variant(2).unwrap();
        assert!(matches!(&parts(&bang, "error_reply")[0],
            vfd_runtime::Part::Literal { bytes, .. } if bytes.as_ref() == b"!"));
        assert!(matches!(&parts(&protocol, "reply")[0],
            vfd_runtime::Part::Literal { bytes, .. } if bytes.as_ref() == b"("));
    }

    #[test]
    fn the_selecting_register_must_be_described() {
        let drive = drive_with("    variant: { register: F999, mismatch_error: data_error }\n");
        let problems = problems_of(lower_both(&drive, &with_variants()));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].ends_with("protocols[0].variant.register: no register `F999`"),
            "{problems:?}"
        );
    }
}
