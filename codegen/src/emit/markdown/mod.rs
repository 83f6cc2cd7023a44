//! Renders the Markdown reference pages from the IR with minijinja templates: [`view`]
//! words the IR for people, [`layouts`] describes frame layouts part by part.

mod layouts;
mod view;

use crate::ir::DriveIr;
use crate::output_names::OutputNames;
use minijinja::{context, Environment};

const DRIVE_TEMPLATE: &str = include_str!("../../../templates/drive.md.j2");
const INDEX_TEMPLATE: &str = include_str!("../../../templates/index.md.j2");

fn environment() -> Result<Environment<'static>, String> {
    let mut env = Environment::new();
    env.set_trim_blocks(false);
    env.add_filter("cell", |value: String| {
        value.replace('|', "\\|").replace('\n', " ")
    });
    env.add_template("drive.md", DRIVE_TEMPLATE)
        .map_err(|e| format!("drive template: {e}"))?;
    env.add_template("index.md", INDEX_TEMPLATE)
        .map_err(|e| format!("index template: {e}"))?;
    Ok(env)
}

/// The reference page of one drive, naming the module, manual, protocol files and
/// regenerate command as `names` says.
pub fn drive_page_with(drive: &DriveIr, names: &OutputNames) -> Result<String, String> {
    let env = environment()?;
    let template = env.get_template("drive.md").map_err(|e| e.to_string())?;
    let protocol_files: std::collections::BTreeMap<&str, String> = drive
        .protocols
        .iter()
        .map(|p| (p.uses.as_str(), names.protocol_file_shown(&p.uses)))
        .collect();
    let text = template
        .render(context! {
            drive => view::DriveView::new(drive),
            regenerate => names.regenerate_hint(),
            module_path => names.module_path(&drive.module),
            manual_shown => names.manual_shown(&drive.manual),
            protocol_files => protocol_files,
        })
        .map_err(|e| format!("rendering {}: {e:#}", drive.id))?;
    Ok(tidy(&text))
}

/// The index page listing every drive, naming the regenerate command as `names` says.
pub fn index_page_with(drives: &[DriveIr], names: &OutputNames) -> Result<String, String> {
    let env = environment()?;
    let template = env.get_template("index.md").map_err(|e| e.to_string())?;
    let text = template
        .render(context! { drives => drives, regenerate => names.regenerate_hint() })
        .map_err(|e| format!("rendering the index: {e:#}"))?;
    Ok(tidy(&text))
}

/// Collapses runs of blank lines, wraps prose ([`crate::emit::wrap`]) and ends the file
/// with one newline.
fn tidy(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut blank = 0;
    for line in text.lines() {
        let line = line.trim_end();
        if line.is_empty() {
            blank += 1;
            if blank > 1 {
                continue;
            }
        } else {
            blank = 0;
        }
        out.push_str(line);
        out.push('\n');
    }
    while out.ends_with("\n\n") {
        out.pop();
    }
    crate::emit::wrap::wrap_markdown(&out, crate::emit::wrap::WIDTH)
}
