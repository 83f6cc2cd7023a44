//! Text and lists that are borrowed in generated code and owned in the code generator.

use std::borrow::Cow;

/// Text that is `&'static str` in generated code and owned in the generator.
pub type Text = Cow<'static, str>;
/// A list that is a `&'static [T]` in generated code and a `Vec<T>` in the generator.
pub type List<T> = Cow<'static, [T]>;
