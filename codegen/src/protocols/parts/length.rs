//! A computed length (`length: u8` with `counts:`).

use super::PartContext;
use crate::diagnostics::Diagnostics;
use crate::parse::model::{CountsModel, PartModel};
use std::borrow::Cow;
use vfd_runtime::{Counts, Format, LengthSpec, Part};

/// A computed length (`length: u8` with `counts:`).
pub(super) fn length(
    name: &str,
    format: Format,
    model: &PartModel,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Part> {
    if !matches!(format, Format::U8 | Format::U16Be) {
        return context.fail(
            out,
            "length",
            format!("`length: {}` is not a length format", format.as_str()),
            "use u8 or u16be",
        );
    };
    let counts = match &model.counts {
        Some(CountsModel::DataSize) => Counts::DataSize,
        Some(CountsModel::Parts { from, through }) => counted_parts(from, through, context, out)?,
        None => {
            return context.fail(
                out,
                "counts",
                "a length needs `counts: { from: part, through: part }` or `counts: data_size`",
                "FC LGE: { from: addr, through: bcc }",
            )
        }
    };
    Some(Part::Length(LengthSpec {
        name: Cow::Owned(name.to_owned()),
        format,
        counts,
        times: model.times.unwrap_or(1),
        per: model.per.unwrap_or(1).max(1),
    }))
}

/// `counts: { from, through }`: two later parts of the layout, `from` first.
fn counted_parts(
    from: &str,
    through: &str,
    context: &PartContext<'_>,
    out: &mut Diagnostics,
) -> Option<Counts> {
    let from_index = context.position_of(from).filter(|i| *i > context.index);
    let through_index = context
        .position_of(through)
        .filter(|i| Some(*i) >= from_index);
    if let (Some(from), Some(through)) = (from_index, through_index) {
        return Some(Counts::Parts {
            from: from as u8,
            through: through as u8,
        });
    }
    let layout = context.layout;
    let unknown: Vec<String> = [from, through]
        .into_iter()
        .filter(|n| context.position_of(n).is_none())
        .map(|n| format!("`{n}`"))
        .collect();
    let why = if unknown.is_empty() {
        "they must be later parts, `from` before `through`".to_owned()
    } else {
        format!(
            "layout `{layout}` has no part named {}",
            unknown.join(" or ")
        )
    };
    context.fail(
        out,
        "counts",
        format!("in layout `{layout}`, `counts: {{ from: {from}, through: {through} }}` does not fit: {why}"),
        format!("parts of layout `{layout}`: {}", context.names.join(", ")),
    )
}
