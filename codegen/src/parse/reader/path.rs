//! The YAML path of the node being read (`registers[3].range.max`).

use std::fmt;

/// A YAML path, built on the stack as the reader descends and written out only for a
/// problem.
#[derive(Clone, Copy)]
pub(super) enum Path<'a> {
    Root,
    Key(&'a Path<'a>, &'a str),
    Index(&'a Path<'a>, usize),
}

impl fmt::Display for Path<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Path::Root => Ok(()),
            Path::Key(Path::Root, key) => f.write_str(key),
            Path::Key(parent, key) => write!(f, "{parent}.{key}"),
            Path::Index(parent, index) => write!(f, "{parent}[{index}]"),
        }
    }
}

impl Path<'_> {
    /// The element a placeholder at this path makes incomplete: the nearest sequence item,
    /// or else the top-level key.
    pub(super) fn element(&self) -> String {
        let mut path = self;
        let mut top = self;
        loop {
            match path {
                Path::Root => return top.to_string(),
                Path::Index(..) => return path.to_string(),
                Path::Key(parent, _) => {
                    top = path;
                    path = parent;
                }
            }
        }
    }
}
