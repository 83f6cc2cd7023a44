//! Where protocol files are found: a folder (the `protocols/` next to the drive file, or
//! one the caller names), then the files a tool ships built in (`vfd` carries the
//! repository's `drives/protocols/`), so a drive file outside any checkout still finds the
//! protocol families the tool knows.

use crate::parse::SourceFile;
use std::path::{Path, PathBuf};

/// Protocol files shipped inside a program, by id (`modbus-rtu`) and text.
pub type Shipped = &'static [(&'static str, &'static str)];

/// The places a drive's protocol files are looked up, in order.
#[derive(Debug, Clone)]
pub(crate) struct Shelf {
    /// The folder tried first.
    pub dir: PathBuf,
    /// Tried when the folder has no file of the id.
    pub shipped: Shipped,
}

impl Shelf {
    /// The protocol file `id`: `<dir>/<id>.yaml`, else the shipped one. `Err` holds the
    /// path that was looked for.
    pub fn read(&self, id: &str) -> Result<SourceFile, PathBuf> {
        let path = self.path_of(id);
        if path.exists() {
            return SourceFile::read(&path).map_err(|_| path);
        }
        match self.shipped_text(id) {
            Some(text) => Ok(SourceFile::from_text(&shipped_path(id), text.to_owned())),
            None => Err(path),
        }
    }

    /// Why `read`, the file `id` as found in the folder, deserves a warning: it differs from
    /// the file of the same id the tool ships (a drive-local copy of an older version reads
    /// silently otherwise). `None` when it is the shipped file, equal to it, or the tool
    /// ships none of that id.
    pub fn differs_from_shipped(&self, id: &str, read: &SourceFile) -> Option<String> {
        let shipped = self.shipped_text(id)?;
        if read.path == shipped_path(id) || read.text == shipped {
            return None;
        }
        Some(format!(
            "{} differs from the protocol file `{id}` shipped with the tool; the local file is used",
            read.path.display()
        ))
    }

    /// The path of `id` in the folder.
    pub fn path_of(&self, id: &str) -> PathBuf {
        self.dir.join(format!("{id}.yaml"))
    }

    /// The shipped text of `id`, if the program ships one.
    pub fn shipped_text(&self, id: &str) -> Option<&'static str> {
        self.shipped
            .iter()
            .find(|(shipped, _)| *shipped == id)
            .map(|(_, text)| *text)
    }

    /// Where the files are looked up, for a message.
    pub fn describe(&self) -> String {
        if self.shipped.is_empty() {
            self.dir.display().to_string()
        } else {
            format!(
                "{} and among the files shipped with the tool",
                self.dir.display()
            )
        }
    }

    /// The ids found in the folder and shipped, sorted, for a hint.
    pub fn available(&self) -> String {
        let mut names: Vec<String> = std::fs::read_dir(&self.dir)
            .map(|entries| {
                entries
                    .filter_map(|e| e.ok())
                    .filter_map(|e| {
                        e.file_name()
                            .to_str()
                            .and_then(|n| n.strip_suffix(".yaml"))
                            .map(str::to_owned)
                    })
                    .collect()
            })
            .unwrap_or_default();
        names.extend(self.shipped.iter().map(|(id, _)| (*id).to_owned()));
        names.sort();
        names.dedup();
        if names.is_empty() {
            "none".to_owned()
        } else {
            names.join(", ")
        }
    }
}

/// The path diagnostics show for a shipped protocol file.
pub(crate) fn shipped_path(id: &str) -> PathBuf {
    Path::new("<shipped>/protocols").join(format!("{id}.yaml"))
}
