//! The formulas of `conversions:`: `+ - * /` and parentheses over numbers and input names,
//! parsed into the runtime's postfix program ([`vfd_runtime::conversion::Op`]).

use vfd_runtime::conversion::Op;

/// Parses `formula`, whose names are `inputs` (in argument order), into a postfix
/// program; an error says what is wrong and where.
pub(crate) fn parse(formula: &str, inputs: &[&str]) -> Result<Vec<Op>, String> {
    let tokens = tokens(formula)?;
    let mut parser = Parser {
        tokens: &tokens,
        at: 0,
        inputs,
        out: Vec::new(),
    };
    parser.sum()?;
    if let Some(token) = tokens.get(parser.at) {
        return Err(format!(
            "unexpected `{}` after a complete formula",
            token.text()
        ));
    }
    Ok(parser.out)
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    Symbol(char),
}

impl Token {
    fn text(&self) -> String {
        match self {
            Token::Number(value) => value.to_string(),
            Token::Name(name) => name.clone(),
            Token::Symbol(symbol) => symbol.to_string(),
        }
    }
}

fn tokens(formula: &str) -> Result<Vec<Token>, String> {
    let mut tokens = Vec::new();
    let mut chars = formula.char_indices().peekable();
    while let Some(&(start, c)) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
        } else if c.is_ascii_digit() || c == '.' {
            let mut end = start;
            while let Some(&(i, d)) = chars.peek() {
                if d.is_ascii_digit() || d == '.' {
                    end = i + d.len_utf8();
                    chars.next();
                } else {
                    break;
                }
            }
            let text = &formula[start..end];
            let value = text
                .parse()
                .map_err(|_| format!("`{text}` is not a number"))?;
            tokens.push(Token::Number(value));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let mut end = start;
            while let Some(&(i, d)) = chars.peek() {
                if d.is_ascii_alphanumeric() || d == '_' {
                    end = i + d.len_utf8();
                    chars.next();
                } else {
                    break;
                }
            }
            tokens.push(Token::Name(formula[start..end].to_owned()));
        } else if "+-*/()".contains(c) {
            tokens.push(Token::Symbol(c));
            chars.next();
        } else {
            return Err(format!(
                "`{c}` is not allowed: use numbers, input names, + - * / and parentheses"
            ));
        }
    }
    Ok(tokens)
}

struct Parser<'a> {
    tokens: &'a [Token],
    at: usize,
    inputs: &'a [&'a str],
    out: Vec<Op>,
}

impl Parser<'_> {
    fn symbol(&self) -> Option<char> {
        match self.tokens.get(self.at) {
            Some(Token::Symbol(symbol)) => Some(*symbol),
            _ => None,
        }
    }

    fn sum(&mut self) -> Result<(), String> {
        self.product()?;
        while let Some(symbol @ ('+' | '-')) = self.symbol() {
            self.at += 1;
            self.product()?;
            self.out.push(if symbol == '+' { Op::Add } else { Op::Sub });
        }
        Ok(())
    }

    fn product(&mut self) -> Result<(), String> {
        self.atom()?;
        while let Some(symbol @ ('*' | '/')) = self.symbol() {
            self.at += 1;
            self.atom()?;
            self.out.push(if symbol == '*' { Op::Mul } else { Op::Div });
        }
        Ok(())
    }

    fn atom(&mut self) -> Result<(), String> {
        let token = self
            .tokens
            .get(self.at)
            .ok_or("the formula ends where a number, a name or `(` is expected")?;
        self.at += 1;
        match token {
            Token::Number(value) => self.out.push(Op::Number(*value)),
            Token::Name(name) => {
                let index = self
                    .inputs
                    .iter()
                    .position(|input| input == name)
                    .ok_or_else(|| {
                        format!(
                            "`{name}` is not an input (inputs: {})",
                            self.inputs.join(", ")
                        )
                    })?;
                self.out.push(Op::Input(index as u8));
            }
            Token::Symbol('(') => {
                self.sum()?;
                if self.symbol() != Some(')') {
                    return Err("a `(` is not closed".to_owned());
                }
                self.at += 1;
            }
            Token::Symbol('-') => {
                // A leading minus: 0 - atom.
                self.out.push(Op::Number(0.0));
                self.atom()?;
                self.out.push(Op::Sub);
            }
            Token::Symbol(symbol) => {
                return Err(format!(
                    "`{symbol}` where a number, a name or `(` is expected"
                ))
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vfd_runtime::conversion::run;

    fn eval(formula: &str, inputs: &[(&str, f64)]) -> Result<Option<f64>, String> {
        let names: Vec<&str> = inputs.iter().map(|(n, _)| *n).collect();
        let program = parse(formula, &names)?;
        Ok(run(&program, |i| {
            inputs.get(usize::from(i)).map(|(_, v)| *v)
        }))
    }

    #[test]
    fn precedence_and_parentheses_are_kept() {
        assert_eq!(eval("1 + 2 * 3", &[]), Ok(Some(7.0)));
        assert_eq!(eval("(1 + 2) * 3", &[]), Ok(Some(9.0)));
        assert_eq!(eval("10 - 4 - 3", &[]), Ok(Some(3.0)));
        assert_eq!(eval("-2 * 3", &[]), Ok(Some(-6.0)));
        assert_eq!(
            eval(
                "(speed * poles * 10 + 6) / 12",
                &[("speed", 1800.0), ("poles", 4.0)]
            ),
            Ok(Some(6000.5))
        );
    }

    #[test]
    fn mistakes_are_named() {
        assert_eq!(
            eval("a + 1", &[]),
            Err("`a` is not an input (inputs: )".to_owned())
        );
        assert_eq!(eval("(1 + 2", &[]), Err("a `(` is not closed".to_owned()));
        assert!(eval("1 +", &[]).unwrap_err().contains("ends"));
        assert!(eval("1 2", &[])
            .unwrap_err()
            .contains("after a complete formula"));
        assert!(eval("2 ^ 3", &[])
            .unwrap_err()
            .contains("`^` is not allowed"));
    }
}
