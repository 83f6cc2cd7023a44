//! The serde access types the node deserializer hands to visitors: a mapping read as a
//! map, a sequence's items, a mapping key, an enum's variant.

use super::error::Error;
use super::node::NodeDe;
use super::path::Path;
use super::state::Reader;
use crate::parse::tree::Node;
use serde::de::{self, DeserializeSeed, Visitor};

/// A mapping read as a map (keys of any type).
pub(super) struct MapDe<'a> {
    pub(super) entries: &'a [(Node, Node)],
    pub(super) index: usize,
    pub(super) path: &'a Path<'a>,
    pub(super) reader: &'a Reader,
}

impl<'de> de::MapAccess<'de> for MapDe<'_> {
    type Error = Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Error> {
        while let Some((key, _)) = self.entries.get(self.index) {
            let earlier = self.entries[..self.index]
                .iter()
                .find(|(k, _)| k.text() == key.text());
            let Some((first, _)) = earlier else { break };
            self.reader.duplicate_key(self.path, key, first.at.line);
            self.index += 1;
        }
        let Some((key, _)) = self.entries.get(self.index) else {
            return Ok(None);
        };
        let path = Path::Key(self.path, key.text().unwrap_or(""));
        seed.deserialize(NodeDe {
            node: Some(key),
            path: &path,
            reader: self.reader,
            parent: None,
        })
        .map(Some)
    }

    fn next_value_seed<S: DeserializeSeed<'de>>(&mut self, seed: S) -> Result<S::Value, Error> {
        let (key, value) = &self.entries[self.index];
        self.index += 1;
        let path = Path::Key(self.path, key.text().unwrap_or(""));
        seed.deserialize(NodeDe {
            node: Some(value),
            path: &path,
            reader: self.reader,
            parent: None,
        })
    }
}

/// A sequence's items, or placeholders for a list of fixed length.
pub(super) struct SeqDe<'a> {
    pub(super) items: &'a [Node],
    pub(super) placeholders: usize,
    pub(super) index: usize,
    pub(super) path: &'a Path<'a>,
    pub(super) reader: &'a Reader,
}

impl<'de> de::SeqAccess<'de> for SeqDe<'_> {
    type Error = Error;

    fn next_element_seed<S: DeserializeSeed<'de>>(
        &mut self,
        seed: S,
    ) -> Result<Option<S::Value>, Error> {
        let index = self.index;
        if index >= self.items.len().max(self.placeholders) {
            return Ok(None);
        }
        self.index += 1;
        let path = Path::Index(self.path, index);
        seed.deserialize(NodeDe {
            node: self.items.get(index),
            path: &path,
            reader: self.reader,
            parent: None,
        })
        .map(Some)
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.items.len().max(self.placeholders) - self.index)
    }
}

/// A mapping key, read as text.
pub(super) struct KeyDe<'k>(pub(super) &'k str);

impl<'de> de::Deserializer<'de> for KeyDe<'_> {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        visitor.visit_str(self.0)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf option unit unit_struct newtype_struct seq tuple
        tuple_struct map struct enum identifier ignored_any
    }
}

/// An enum's variant and its content.
pub(super) struct EnumDe<'a> {
    pub(super) variant: &'a str,
    pub(super) content: NodeDe<'a>,
}

impl<'de, 'a> de::EnumAccess<'de> for EnumDe<'a> {
    type Error = Error;
    type Variant = NodeDe<'a>;

    fn variant_seed<S: DeserializeSeed<'de>>(
        self,
        seed: S,
    ) -> Result<(S::Value, NodeDe<'a>), Error> {
        let variant = seed.deserialize(KeyDe(self.variant))?;
        Ok((variant, self.content))
    }
}
