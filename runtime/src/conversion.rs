//! Formulas of a manual between registers (a motor speed from a frequency and the number
//! of poles), as data: a postfix program over numbers and named inputs that the code
//! generator compiles from the description's `conversions:` and that anything (the typed
//! API, the virtual drive, tools) can evaluate. Nothing here names a drive or a register.

/// One step of a conversion's postfix program.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Op {
    /// Pushes a number.
    Number(f64),
    /// Pushes the input with this position in [`Conversion::inputs`].
    Input(u8),
    /// Pops b, then a; pushes a + b.
    Add,
    /// Pops b, then a; pushes a - b.
    Sub,
    /// Pops b, then a; pushes a x b.
    Mul,
    /// Pops b, then a; pushes a / b (a division by zero makes the result unknown).
    Div,
}

/// Where a conversion's input comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConversionInput {
    /// The input's name in the formula (and the generated function's argument).
    pub name: &'static str,
    /// Code of the register giving it (its engineering value), if it is a register.
    pub register: Option<&'static str>,
    /// Factor applied to the register's value first (1 for none).
    pub times: f64,
}

/// A formula of the manual.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conversion {
    /// Identifier in the description (also the generated function's name).
    pub id: &'static str,
    /// The formula as the description writes it.
    pub formula: &'static str,
    /// The inputs, in argument order.
    pub inputs: &'static [ConversionInput],
    /// The formula in postfix order.
    pub program: &'static [Op],
    /// The result is cut towards zero to a whole number (the drive's integer arithmetic).
    pub truncate: bool,
    /// Code of the register the result belongs to, if any.
    pub result: Option<&'static str>,
    /// The selector register (code) and the value for which the formula applies
    /// (`None`: any value but 0); `None` altogether: always.
    pub when: Option<(&'static str, Option<u32>)>,
}

impl Conversion {
    /// The result for `inputs` given in argument order (register inputs as the register's
    /// engineering value, before `times`). `None` when an input is missing, the program is
    /// malformed, a division by zero occurs or the result is not finite.
    pub fn evaluate(&self, inputs: &[f64]) -> Option<f64> {
        if inputs.len() != self.inputs.len() {
            return None;
        }
        let value = run(self.program, |index| {
            let input = self.inputs.get(usize::from(index))?;
            Some(inputs.get(usize::from(index))? * input.times)
        })?;
        Some(if self.truncate { value.trunc() } else { value })
    }

    /// The result with each register input taken from `value_of` (by register code) and
    /// the other inputs from `free` (in argument order, skipping register inputs).
    pub fn evaluate_with(
        &self,
        value_of: impl Fn(&str) -> Option<f64>,
        free: &[f64],
    ) -> Option<f64> {
        let mut free = free.iter();
        let mut values = Vec::with_capacity(self.inputs.len());
        for input in self.inputs {
            values.push(match input.register {
                Some(code) => value_of(code)?,
                None => *free.next()?,
            });
        }
        self.evaluate(&values)
    }

    /// Whether the formula applies when its selector holds `selector`.
    pub fn applies(&self, selector: Option<u32>) -> bool {
        match (self.when, selector) {
            (None, _) => true,
            (Some((_, Some(value))), Some(selector)) => value == selector,
            (Some((_, None)), Some(selector)) => selector != 0,
            (Some(_), None) => false,
        }
    }
}

/// Runs a postfix `program`, taking input values from `input`.
pub fn run(program: &[Op], input: impl Fn(u8) -> Option<f64>) -> Option<f64> {
    let mut stack: Vec<f64> = Vec::with_capacity(program.len());
    for op in program {
        let value = match *op {
            Op::Number(value) => value,
            Op::Input(index) => input(index)?,
            Op::Add | Op::Sub | Op::Mul | Op::Div => {
                let b = stack.pop()?;
                let a = stack.pop()?;
                match op {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    _ if b == 0.0 => return None,
                    _ => a / b,
                }
            }
        };
        stack.push(value);
    }
    let result = stack.pop()?;
    (stack.is_empty() && result.is_finite()).then_some(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPEED: Conversion = Conversion {
        id: "frequency_from_speed",
        formula: "(speed * poles * 10 + 6) / 12",
        inputs: &[
            ConversionInput {
                name: "speed",
                register: None,
                times: 1.0,
            },
            ConversionInput {
                name: "poles",
                register: Some("P"),
                times: 2.0,
            },
        ],
        program: &[
            Op::Input(0),
            Op::Input(1),
            Op::Mul,
            Op::Number(10.0),
            Op::Mul,
            Op::Number(6.0),
            Op::Add,
            Op::Number(12.0),
            Op::Div,
        ],
        truncate: true,
        result: None,
        when: None,
    };

    #[test]
    fn a_program_evaluates_with_factors_and_truncation() {
        // 1800 x 4 x 10 + 6 = 72006; / 12 = 6000.5, cut to 6000.
        assert_eq!(SPEED.evaluate(&[1800.0, 2.0]), Some(6000.0));
        assert_eq!(
            SPEED.evaluate_with(|code| (code == "P").then_some(2.0), &[1800.0]),
            Some(6000.0)
        );
        assert_eq!(SPEED.evaluate(&[1800.0]), None, "an input is missing");
        assert_eq!(SPEED.evaluate_with(|_| None, &[1800.0]), None);
    }

    #[test]
    fn malformed_programs_and_divisions_by_zero_give_nothing() {
        assert_eq!(run(&[Op::Add], |_| None), None);
        assert_eq!(run(&[Op::Number(1.0), Op::Number(2.0)], |_| None), None);
        assert_eq!(
            run(&[Op::Number(1.0), Op::Number(0.0), Op::Div], |_| None),
            None
        );
        assert_eq!(run(&[Op::Input(3)], |_| None), None);
    }

    #[test]
    fn a_condition_chooses_when_the_formula_applies() {
        let mut conversion = SPEED;
        assert!(conversion.applies(None));
        conversion.when = Some(("SEL", Some(0)));
        assert!(conversion.applies(Some(0)) && !conversion.applies(Some(1)));
        assert!(!conversion.applies(None));
        conversion.when = Some(("SEL", None));
        assert!(conversion.applies(Some(2)) && !conversion.applies(Some(0)));
    }
}
