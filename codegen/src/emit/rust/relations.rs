//! Emits the relations between registers: the `ports` module (the drive's serial ports,
//! one `Port` static each) and the `conversions` module (the manual's formulas, one typed
//! function each, over the runtime's postfix programs).

use super::*;
use crate::ir::ConversionIr;
use vfd_runtime::conversion::Op;

/// The `ports` module, and the tokens of `DriveInfo::ports` (`None` without ports).
pub(super) fn ports_module(drive: &DriveIr) -> (TokenStream, TokenStream) {
    let Some(ports) = &drive.ports else {
        return (quote!(), quote!(None));
    };
    let infos = ports.ports.iter().map(|port| {
        let (id, name, name_zh) = (
            str_literal(&port.id),
            str_literal(&port.name),
            str_literal(&port.name_zh),
        );
        let settings = port.settings.iter().map(|(what, code)| {
            let (what, code) = (str_literal(what), str_literal(code));
            quote!((#what, #code))
        });
        quote!(PortInfo { id: #id, name: #name, name_zh: #name_zh, settings: &[#(#settings),*] })
    });
    let shared = ports.shared.iter().map(|code| str_literal(code));
    let rows = ports.registers.iter().map(|row| {
        let codes = row.iter().map(|code| str_literal(code));
        quote!(&[#(#codes),*])
    });
    let handles = ports.ports.iter().map(|port| {
        let name = ident(&port.const_name);
        let id = str_literal(&port.id);
        let pairs: Vec<String> = ports
            .registers
            .iter()
            .filter_map(|row| {
                let index = ports.ports.iter().position(|p| p.id == port.id)?;
                let first = row.first()?;
                let mine = row.get(index)?;
                (first != mine).then(|| format!("{first} -> {mine}"))
            })
            .collect();
        let doc = doc_text(if pairs.is_empty() {
            format!(
                "The {} port: requests for per-port registers go to this port's copies (as written).",
                port.name
            )
        } else {
            format!(
                "The {} port: requests for per-port registers go to this port's copies ({}).",
                port.name,
                pairs.join(", ")
            )
        });
        quote! {
            #[doc = #doc]
            pub static #name: Port = Port { drive: &super::DRIVE, id: #id };
        }
    });
    let doc = doc_text(format!(
        "The serial ports (manual section {}): each port's own settings, the registers they share and those that exist once per port. Give a port to a master with `Master::with_port(Some(ports::NAME))`.",
        ports.source
    ));
    let tokens = quote! {
        #[doc = #doc]
        pub mod ports {
            use ::vfd_runtime::{Port, PortInfo, Ports};
            /// The ports, their shared registers and the per-port register groups, as data.
            pub static PORTS: Ports = Ports {
                ports: &[#(#infos),*],
                shared: &[#(#shared),*],
                registers: &[#(#rows),*],
            };
            #(#handles)*
        }
    };
    (tokens, quote!(Some(&ports::PORTS)))
}

fn op_tokens(op: &Op) -> TokenStream {
    match op {
        Op::Number(value) => {
            let value = f64_literal(*value);
            quote!(Op::Number(#value))
        }
        Op::Input(index) => {
            let index = int_literal(*index);
            quote!(Op::Input(#index))
        }
        Op::Add => quote!(Op::Add),
        Op::Sub => quote!(Op::Sub),
        Op::Mul => quote!(Op::Mul),
        Op::Div => quote!(Op::Div),
    }
}

/// What the generated function's documentation says of an input.
fn input_doc(conversion: &ConversionIr) -> Vec<String> {
    conversion
        .inputs
        .iter()
        .map(|input| {
            let what = match &input.register {
                Some(code) if (input.times - 1.0).abs() > f64::EPSILON => {
                    format!(
                        "the value of {code} (it is multiplied by {} first)",
                        input.times
                    )
                }
                Some(code) => format!("the value of {code}"),
                None => input.description.clone(),
            };
            format!("* `{}`: {what}", input.name)
        })
        .collect()
}

/// The `conversions` module: `ALL` and one function per conversion.
pub(super) fn conversions_module(drive: &DriveIr) -> TokenStream {
    let statics = drive.conversions.iter().map(|conversion| {
        let (id, formula) = (
            str_literal(&conversion.id),
            str_literal(&conversion.formula),
        );
        let inputs = conversion.inputs.iter().map(|input| {
            let name = str_literal(&input.name);
            let register = match &input.register {
                Some(code) => {
                    let code = str_literal(code);
                    quote!(Some(#code))
                }
                None => quote!(None),
            };
            let times = f64_literal(input.times);
            quote!(ConversionInput { name: #name, register: #register, times: #times })
        });
        let program = conversion.program.iter().map(op_tokens);
        let truncate = conversion.truncate;
        let result = match &conversion.result {
            Some(code) => {
                let code = str_literal(code);
                quote!(Some(#code))
            }
            None => quote!(None),
        };
        let when = match &conversion.when {
            Some((code, value)) => {
                let code = str_literal(code);
                let value = match value {
                    Some(value) => {
                        let value = int_literal(*value);
                        quote!(Some(#value))
                    }
                    None => quote!(None),
                };
                quote!(Some((#code, #value)))
            }
            None => quote!(None),
        };
        quote! {
            Conversion {
                id: #id,
                formula: #formula,
                inputs: &[#(#inputs),*],
                program: &[#(#program),*],
                truncate: #truncate,
                result: #result,
                when: #when,
            }
        }
    });
    let functions = drive
        .conversions
        .iter()
        .enumerate()
        .map(|(index, conversion)| {
            let name = ident(&conversion.id);
            let args: Vec<Ident> = conversion.inputs.iter().map(|i| ident(&i.name)).collect();
            let mut doc = vec![
                format!(
                    "{} (manual section {}):",
                    conversion.name, conversion.source
                ),
                String::new(),
                format!(
                    "`{}`{}",
                    conversion.formula,
                    if conversion.truncate {
                        ", cut to a whole number"
                    } else {
                        ""
                    }
                ),
                String::new(),
            ];
            doc.extend(input_doc(conversion));
            if let Some((code, value)) = &conversion.when {
                doc.push(String::new());
                doc.push(match value {
                    Some(value) => format!("Applies when {code} = {value}."),
                    None => format!("Applies when {code} is not 0."),
                });
            }
            let unit = conversion.unit.symbol();
            if !unit.is_empty() || conversion.result.is_some() {
                doc.push(String::new());
                doc.push(format!(
                    "The result{}{}.",
                    if unit.is_empty() {
                        String::new()
                    } else {
                        format!(" is in {unit}")
                    },
                    conversion
                        .result
                        .as_ref()
                        .map_or_else(String::new, |code| format!(" (register {code})"))
                ));
            }
            if !conversion.note.is_empty() {
                doc.push(String::new());
                doc.push(conversion.note.clone());
            }
            doc.push(String::new());
            doc.push("`None` when the formula divides by zero.".to_owned());
            let doc = doc_texts(&doc);
            let index = int_literal(index);
            quote! {
                #(#[doc = #doc])*
                pub fn #name(#(#args: f64),*) -> Option<f64> {
                    ALL[#index].evaluate(&[#(#args),*])
                }
            }
        });
    let count = int_literal(drive.conversions.len());
    let imports = if drive.conversions.is_empty() {
        quote!(
            use ::vfd_runtime::conversion::Conversion;
        )
    } else {
        quote!(
            use ::vfd_runtime::conversion::{Conversion, ConversionInput, Op};
        )
    };
    quote! {
        /// The manual's formulas between registers, one function each (arguments in the
        /// formula's input order), and as data in `ALL`.
        pub mod conversions {
            #imports
            /// Every conversion, as data.
            pub static ALL: [Conversion; #count] = [#(#statics),*];
            #(#functions)*
        }
    }
}

/// The drive's forbidden combinations as a `&[ForbiddenCombination]` literal.
pub(super) fn forbidden_tokens(drive: &DriveIr) -> TokenStream {
    let items = drive.forbidden_combinations.iter().map(|combination| {
        let (id, rule, meaning, source) = (
            str_literal(&combination.id),
            str_literal(&combination.rule),
            str_literal(&combination.meaning),
            str_literal(&combination.source),
        );
        let when = combination.when.iter().map(|(register, raw)| {
            let register = str_literal(register);
            let raw = raw.iter().map(|r| int_literal(*r));
            quote!(::vfd_runtime::Condition { register: #register, raw: &[#(#raw),*] })
        });
        quote! {
            ::vfd_runtime::ForbiddenCombination {
                id: #id,
                rule: #rule,
                meaning: #meaning,
                source: #source,
                when: &[#(#when),*],
            }
        }
    });
    quote!(&[#(#items),*])
}
