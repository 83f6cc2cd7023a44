//! Stage 4b: renders the Markdown reference pages from the IR with minijinja templates.

use crate::ir::DriveIr;
use minijinja::{context, Environment};

const DRIVE_TEMPLATE: &str = include_str!("../../templates/drive.md.j2");
const INDEX_TEMPLATE: &str = include_str!("../../templates/index.md.j2");

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

/// The reference page of one drive.
pub fn drive_page(drive: &DriveIr) -> Result<String, String> {
    let env = environment()?;
    let template = env.get_template("drive.md").map_err(|e| e.to_string())?;
    let text = template
        .render(context! { drive => drive })
        .map_err(|e| format!("rendering {}: {e:#}", drive.id))?;
    Ok(tidy(&text))
}

/// The index page listing every drive.
pub fn index_page(drives: &[DriveIr]) -> Result<String, String> {
    let env = environment()?;
    let template = env.get_template("index.md").map_err(|e| e.to_string())?;
    let text = template
        .render(context! { drives => drives })
        .map_err(|e| format!("rendering the index: {e:#}"))?;
    Ok(tidy(&text))
}

/// Collapses runs of blank lines and ends the file with one newline.
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
    out
}
