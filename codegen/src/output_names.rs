//! [`OutputNames`]: how generated output names anything outside a drive description (the
//! regenerate command, the Rust path of the generated modules, where manuals and protocol
//! files are). Set through the [`crate::Builder`]; emitters read it.

/// How generated output refers to anything outside the drive description: the command that
/// regenerates it, the Rust path of the generated modules, where manuals and protocol files
/// are. Set through the [`crate::Builder`]; the defaults name nothing but the description itself.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputNames {
    /// Command that regenerates the output, named in `@generated` headers (`None`: "regenerate
    /// with vfd-codegen").
    pub regenerate_command: Option<String>,
    /// Rust path of the module holding the generated drive modules, as golden tests and
    /// reference pages reach them (`crate`, or `my_drives` from another crate).
    pub crate_path: String,
    /// Folder shown in front of manual file names (`None`: the file name alone).
    pub manuals_location: Option<String>,
    /// Folder shown in front of protocol file names (`None`: the file name alone). The
    /// [`crate::Builder`] sets it per drive when the protocol folder lies under its display root.
    pub protocols_location: Option<String>,
}

impl Default for OutputNames {
    fn default() -> Self {
        OutputNames {
            regenerate_command: None,
            crate_path: "crate".to_owned(),
            manuals_location: None,
            protocols_location: None,
        }
    }
}

impl OutputNames {
    /// How to regenerate, completing "Do not edit: change the YAML and ...":
    /// "run `<command>`", or "regenerate with vfd-codegen".
    pub fn regenerate_hint(&self) -> String {
        match &self.regenerate_command {
            Some(command) => format!("run `{command}`"),
            None => "regenerate with vfd-codegen".to_owned(),
        }
    }

    /// The Rust path of a generated drive module (`crate::yd1000`).
    pub fn module_path(&self, module: &str) -> String {
        format!("{}::{module}", self.crate_path)
    }

    /// A manual's file name with its folder, when one is configured.
    pub fn manual_shown(&self, manual: &str) -> String {
        shown_in(self.manuals_location.as_deref(), manual)
    }

    /// A protocol file's name (`<uses>.yaml`) with its folder, when one is known.
    pub fn protocol_file_shown(&self, uses: &str) -> String {
        shown_in(self.protocols_location.as_deref(), &format!("{uses}.yaml"))
    }
}

fn shown_in(folder: Option<&str>, file: &str) -> String {
    match folder.map(|f| f.trim_end_matches('/')) {
        Some(folder) if !folder.is_empty() => format!("{folder}/{file}"),
        _ => file.to_owned(),
    }
}
