//! The node deserializer as serde drives it: numbers, text, lists, maps and enums, each
//! value of the wrong shape reported and replaced by a placeholder.

use super::access::{EnumDe, MapDe, SeqDe};
use super::error::{Error, REPORTED};
use super::hints::{list, unknown_hint};
use super::node::NodeDe;
use super::path::Path;
use super::scalar::{resolve, Scalar};
use crate::parse::tree::{Node, Value};
use serde::de::{self, DeserializeSeed, Visitor};

impl<'a> NodeDe<'a> {
    fn integer<'de, V: Visitor<'de>>(
        self,
        min: i128,
        max: i128,
        visitor: V,
    ) -> Result<V::Value, Error> {
        let value = match self.node.map(resolve) {
            None => 0,
            Some(Some(Scalar::Int(n))) if (min..=max).contains(&n) => n,
            Some(Some(Scalar::Int(n))) => {
                self.report(
                    format!("{n} is out of range: expected a whole number from {min} to {max}"),
                    None,
                );
                self.placeholder();
                0
            }
            Some(_) => {
                self.wrong(&format!("a whole number from {min} to {max}"));
                0
            }
        };
        let result = if min < 0 {
            visitor.visit_i64(value as i64)
        } else {
            visitor.visit_u64(value as u64)
        };
        result.map_err(|e| self.locate(e))
    }

    fn number<'de, V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let value = match self.node.map(resolve) {
            None => 0.0,
            Some(Some(Scalar::Int(n))) => n as f64,
            Some(Some(Scalar::Float(x))) => x,
            Some(_) => {
                self.wrong("a number");
                0.0
            }
        };
        visitor.visit_f64(value).map_err(|e| self.locate(e))
    }

    fn text<'de, V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let text = match self.node {
            None => "",
            Some(node) => match (resolve(node), node.text()) {
                (Some(Scalar::Null), _) => {
                    self.wrong("text");
                    ""
                }
                (Some(_), Some(text)) => text,
                _ => {
                    self.wrong("text");
                    ""
                }
            },
        };
        visitor.visit_str(text).map_err(|e| self.locate(e))
    }

    fn sequence<'de, V: Visitor<'de>>(
        self,
        length: Option<usize>,
        visitor: V,
    ) -> Result<V::Value, Error> {
        let items: &[Node] = match self.node.map(|n| &n.value) {
            Some(Value::Sequence(items)) => match length {
                Some(length) if items.len() != length => {
                    self.report(
                        format!("expected a list of {length} values, found {}", items.len()),
                        None,
                    );
                    self.placeholder();
                    let access = SeqDe {
                        items: &[],
                        placeholders: length,
                        index: 0,
                        path: self.path,
                        reader: self.reader,
                    };
                    return visitor.visit_seq(access).map_err(|e| self.locate(e));
                }
                _ => items,
            },
            None => &[],
            Some(_) => {
                match length {
                    Some(length) => self.wrong(&format!("a list of {length} values")),
                    None => self.wrong("a list"),
                }
                &[]
            }
        };
        let placeholders = if items.is_empty() {
            length.unwrap_or(0)
        } else {
            0
        };
        let access = SeqDe {
            items,
            placeholders,
            index: 0,
            path: self.path,
            reader: self.reader,
        };
        visitor.visit_seq(access).map_err(|e| self.locate(e))
    }
}

macro_rules! integers {
    ($($method:ident: $ty:ty),* $(,)?) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            self.integer(<$ty>::MIN as i128, <$ty>::MAX as i128, visitor)
        }
    )*};
}

/// Methods that read any scalar as its text.
macro_rules! texts {
    ($($method:ident),* $(,)?) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            self.text(visitor)
        }
    )*};
}

impl<'de> de::Deserializer<'de> for NodeDe<'_> {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let Some(node) = self.node else {
            return visitor.visit_u64::<Error>(0).map_err(|_| REPORTED);
        };
        let result = match &node.value {
            Value::Sequence(_) => return self.sequence(None, visitor),
            Value::Mapping(entries) => visitor.visit_map(MapDe {
                entries,
                index: 0,
                path: self.path,
                reader: self.reader,
            }),
            Value::Scalar { .. } => match resolve(node) {
                Some(Scalar::Null) | None => visitor.visit_unit(),
                Some(Scalar::Bool(value)) => visitor.visit_bool(value),
                Some(Scalar::Int(n)) => match (u64::try_from(n), i64::try_from(n)) {
                    (Ok(n), _) => visitor.visit_u64(n),
                    (_, Ok(n)) => visitor.visit_i64(n),
                    _ => visitor.visit_f64(n as f64),
                },
                Some(Scalar::Float(x)) => visitor.visit_f64(x),
                Some(Scalar::Text(text)) => visitor.visit_str(text),
            },
        };
        result.map_err(|e| self.locate(e))
    }

    integers!(
        deserialize_u8: u8, deserialize_u16: u16, deserialize_u32: u32, deserialize_u64: u64,
        deserialize_i8: i8, deserialize_i16: i16, deserialize_i32: i32, deserialize_i64: i64,
    );

    fn deserialize_f32<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.number(visitor)
    }

    fn deserialize_f64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.number(visitor)
    }

    fn deserialize_bool<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let value = match self.node.map(resolve) {
            None => false,
            Some(Some(Scalar::Bool(value))) => value,
            Some(_) => {
                self.wrong("`true` or `false`");
                false
            }
        };
        visitor.visit_bool(value).map_err(|e| self.locate(e))
    }

    texts!(
        deserialize_char,
        deserialize_str,
        deserialize_string,
        deserialize_bytes,
        deserialize_byte_buf,
        deserialize_identifier,
    );

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        match self.node.map(resolve) {
            None | Some(Some(Scalar::Null)) => visitor.visit_none().map_err(|e| self.locate(e)),
            Some(_) => visitor.visit_some(self),
        }
    }

    fn deserialize_unit<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        match self.node.map(resolve) {
            None | Some(Some(Scalar::Null)) => {}
            Some(_) => self.wrong("nothing"),
        }
        visitor.visit_unit().map_err(|e| self.locate(e))
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.deserialize_unit(visitor)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.sequence(None, visitor)
    }

    fn deserialize_tuple<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, Error> {
        self.sequence(Some(len), visitor)
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.sequence(Some(len), visitor)
    }

    fn deserialize_map<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let entries: &[(Node, Node)] = match self.node.map(|n| &n.value) {
            Some(Value::Mapping(entries)) => entries,
            None => &[],
            Some(_) if matches!(self.node.map(resolve), Some(Some(Scalar::Null))) => &[],
            Some(_) => {
                self.wrong("a mapping (keys with values)");
                &[]
            }
        };
        visitor
            .visit_map(MapDe {
                entries,
                index: 0,
                path: self.path,
                reader: self.reader,
            })
            .map_err(|e| self.locate(e))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.structure(name, fields, visitor)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        let first = variants.first().copied().unwrap_or("");
        let (variant, content): (&str, Option<&Node>) = match self.node {
            None => (first, None),
            Some(node) => match (&node.value, resolve(node)) {
                (Value::Scalar { text, .. }, Some(scalar)) if scalar != Scalar::Null => {
                    if variants.contains(&text.as_str()) {
                        (text.as_str(), None)
                    } else {
                        self.report(
                            format!("unknown value `{text}`"),
                            Some(unknown_hint(text, variants, "value")),
                        );
                        self.placeholder();
                        (first, None)
                    }
                }
                (Value::Mapping(entries), _) if entries.len() == 1 => {
                    let (key, value) = &entries[0];
                    match key.text().filter(|k| variants.contains(k)) {
                        Some(key) => (key, Some(value)),
                        None => {
                            self.report(
                                format!("unknown value `{}`", key.text().unwrap_or("")),
                                Some(unknown_hint(key.text().unwrap_or(""), variants, "value")),
                            );
                            self.placeholder();
                            (first, None)
                        }
                    }
                }
                _ => {
                    self.wrong(&format!("one of {}", list(variants)));
                    (first, None)
                }
            },
        };
        let path = Path::Key(self.path, variant);
        let access = EnumDe {
            variant,
            content: self.child(content, if content.is_some() { &path } else { self.path }),
        };
        visitor.visit_enum(access).map_err(|e| self.locate(e))
    }

    fn deserialize_ignored_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        visitor.visit_unit()
    }
}

impl<'de> de::VariantAccess<'de> for NodeDe<'_> {
    type Error = Error;

    fn unit_variant(self) -> Result<(), Error> {
        Ok(())
    }

    fn newtype_variant_seed<S: DeserializeSeed<'de>>(self, seed: S) -> Result<S::Value, Error> {
        seed.deserialize(self)
    }

    fn tuple_variant<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, Error> {
        self.sequence(Some(len), visitor)
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.structure("", fields, visitor)
    }
}
