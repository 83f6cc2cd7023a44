//! A protocol in each of its variants, built lazily and owned by the protocol built from.

use super::command::CommandSpec;
use super::follow_up::FollowUp;
use super::Protocol;
use crate::error::EncodeError;
use crate::variant::Variants;
use std::borrow::Cow;
use std::fmt;
use std::sync::OnceLock;

impl Protocol {
    /// The id of the variant this protocol is in (`None`: the protocol has no variants).
    pub fn variant_id(&self) -> Option<&str> {
        self.variants.as_ref()?.current().map(|v| v.id.as_ref())
    }

    /// This protocol in the variant at `index` of [`Protocol::variants`] (its own when it
    /// is already in it): every literal part the variant lists gets the variant's bytes,
    /// in every command's layouts (its follow-ups included) and in the error reply.
    /// `None`: no such variant.
    pub fn in_variant(&self, index: usize) -> Option<Protocol> {
        let variants = self.variants.as_ref()?;
        let variant = variants.choices.get(index)?;
        let commands = self
            .commands
            .iter()
            .map(|command| CommandSpec {
                request: variant.apply(&command.request),
                reply: variant.apply(&command.reply),
                follow_up: command.follow_up.as_ref().map(|f| FollowUp {
                    ok: variant.apply(&f.ok),
                    again: variant.apply(&f.again),
                }),
                ..command.clone()
            })
            .collect();
        Some(Protocol {
            commands: Cow::Owned(commands),
            error_reply: self.error_reply.as_ref().map(|l| variant.apply(l)),
            variants: Some(Variants {
                current: u8::try_from(index).ok()?,
                ..variants.clone()
            }),
            ..self.clone()
        })
    }

    /// This protocol in its variant `id` (`cr_lf`), for a master or tool told which one
    /// the drive is set to; `None`: no such variant. The variant of a generated protocol
    /// is built once, on first use, and kept by the protocol it is built from (see
    /// [`VariantCache`]).
    pub fn variant(&'static self, id: &str) -> Option<&'static Protocol> {
        let index = self.variants.as_ref()?.index_of(id)?;
        Some(self.variant_at(index))
    }

    /// [`Protocol::variant`], or the typed reason there is none (naming the variants
    /// there are).
    pub fn variant_or_error(&'static self, id: &str) -> Result<&'static Protocol, EncodeError> {
        self.variant(id).ok_or_else(|| EncodeError::NoSuchVariant {
            protocol: self.id.clone(),
            variant: id.to_owned(),
            known: self
                .variants
                .iter()
                .flat_map(|v| v.choices.iter().map(|c| c.id.as_ref()))
                .collect::<Vec<_>>()
                .join(", "),
        })
    }

    /// Every variant of this protocol, in the protocol file's order, this one among them;
    /// only this one when it has no variants.
    pub fn all_variants(&'static self) -> Vec<&'static Protocol> {
        match &self.variants {
            Some(variants) => (0..variants.choices.len())
                .map(|index| self.variant_at(index))
                .collect(),
            None => vec![self],
        }
    }

    /// The variant the value `value_of(register)` of the drive's selector register selects
    /// (`None` from `value_of`: its default); this protocol when there is no selector or
    /// the value selects none.
    pub fn variant_selected(
        &'static self,
        value_of: impl Fn(u16) -> Option<u32>,
    ) -> &'static Protocol {
        let Some(variants) = &self.variants else {
            return self;
        };
        let Some(selector) = &variants.selected_by else {
            return self;
        };
        match value_of(selector.register).and_then(|value| variants.selected_by_value(value)) {
            Some(index) => self.variant_at(index),
            None => self,
        }
    }

    /// The variant at `index` (an index of [`Variants::choices`] that exists; this
    /// protocol otherwise). Every variant is built from the protocol described (a variant
    /// asked for another goes back to it), once, on first use, and kept in that protocol's
    /// [`VariantCache`] for as long as it lives: for ever, for a generated static.
    fn variant_at(&'static self, index: usize) -> &'static Protocol {
        let origin = self.variant_cache.origin.unwrap_or(self);
        let Some(variants) = &origin.variants else {
            return origin;
        };
        if usize::from(variants.current) == index {
            return origin;
        }
        let slots = origin
            .variant_cache
            .built
            .get_or_init(|| variants.choices.iter().map(|_| OnceLock::new()).collect());
        let Some(slot) = slots.get(index) else {
            return origin;
        };
        if let Some(built) = slot.get() {
            return built;
        }
        let Some(mut protocol) = origin.in_variant(index) else {
            return origin;
        };
        protocol.variant_cache.origin = Some(origin);
        // Another thread may have built it meanwhile: its copy is kept, this one dropped.
        slot.get_or_init(|| protocol)
    }
}

/// The variants built from one protocol ([`Protocol::variant`]), owned by it: built on
/// first use, one slot per variant, and dropped with it. Not part of the protocol's value:
/// it does not show in `Debug`, always compares equal, starts empty in a clone and is not
/// serialized. Const-constructible, so generated `static` protocols carry one.
pub struct VariantCache {
    /// The protocol this one is a variant of, when [`Protocol::variant`] built it (its
    /// variants are then that protocol's); `None` for a protocol as described.
    origin: Option<&'static Protocol>,
    /// A slot per variant of [`Protocol::variants`], each filled on first use.
    built: OnceLock<Box<[OnceLock<Protocol>]>>,
}

impl VariantCache {
    /// An empty cache: what every protocol is built with.
    pub const fn new() -> Self {
        VariantCache {
            origin: None,
            built: OnceLock::new(),
        }
    }
}

impl Default for VariantCache {
    fn default() -> Self {
        VariantCache::new()
    }
}

/// A clone starts empty: the variants it builds are its own.
impl Clone for VariantCache {
    fn clone(&self) -> Self {
        VariantCache::new()
    }
}

/// Caches never tell two protocols apart.
impl PartialEq for VariantCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl fmt::Debug for VariantCache {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let built = self.built.get().map_or(0, |slots| {
            slots.iter().filter(|s| s.get().is_some()).count()
        });
        f.debug_struct("VariantCache")
            .field("is_variant", &self.origin.is_some())
            .field("built", &built)
            .finish()
    }
}
