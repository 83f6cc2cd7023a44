//! Poll intervals as plant files write them: a number and a unit (`250ms`, `1s`, `2.5s`,
//! `1min`, `1h`), from [`SHORTEST`] to [`LONGEST`].

use std::time::Duration;

/// The shortest interval a plant file may ask for.
pub const SHORTEST: Duration = Duration::from_millis(10);
/// The longest interval a plant file may ask for.
pub const LONGEST: Duration = Duration::from_secs(24 * 3600);

/// The units, longest name first where one is a prefix of another, with their length in
/// milliseconds.
const UNITS: &[(&str, f64)] = &[
    ("ms", 1.0),
    ("min", 60_000.0),
    ("s", 1000.0),
    ("h", 3_600_000.0),
];

/// `text` as an interval, or what is wrong with it (a sentence, and a hint).
pub fn parse(text: &str) -> Result<Duration, (String, String)> {
    let hint = "write a number and a unit: `ms`, `s`, `min` or `h` (`500ms`, `1s`, `2.5s`, `1min`)";
    let trimmed = text.trim();
    let split = trimmed
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(trimmed.len());
    let (number, unit) = trimmed.split_at(split);
    let unit = unit.trim();
    if number.is_empty() {
        return Err((format!("`{text}` is not an interval"), hint.to_owned()));
    }
    if unit.is_empty() {
        return Err((
            format!("the interval `{text}` has no unit"),
            format!("{hint}; a bare number is ambiguous"),
        ));
    }
    let Some((_, per)) = UNITS.iter().find(|(name, _)| *name == unit) else {
        return Err((
            format!("`{unit}` is not a unit of time here (in `{text}`)"),
            hint.to_owned(),
        ));
    };
    let Ok(value) = number.parse::<f64>() else {
        return Err((
            format!("`{number}` is not a number (in `{text}`)"),
            hint.to_owned(),
        ));
    };
    let millis = value * per;
    if millis <= 0.0 {
        return Err((
            format!("the interval `{text}` is zero"),
            format!(
                "poll at least every {} ms; to stop polling a register, leave it out",
                SHORTEST.as_millis()
            ),
        ));
    }
    let every = Duration::from_secs_f64(millis / 1000.0);
    if every < SHORTEST || every > LONGEST {
        return Err((
            format!(
                "the interval `{text}` is outside {} ms to 24 h",
                SHORTEST.as_millis()
            ),
            "a bus polls one register at a time: a shorter interval only keeps the line busy"
                .to_owned(),
        ));
    }
    Ok(every)
}

/// `every` as a plant file would write it (`1s`, `250ms`, `2.5s`, `1min`).
pub fn show(every: Duration) -> String {
    let millis = every.as_millis();
    if millis.is_multiple_of(3_600_000) {
        format!("{}h", millis / 3_600_000)
    } else if millis.is_multiple_of(60_000) {
        format!("{}min", millis / 60_000)
    } else if millis >= 1000 {
        format!("{}s", every.as_secs_f64())
    } else {
        format!("{millis}ms")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_with_units_are_intervals() {
        assert_eq!(parse("100ms"), Ok(Duration::from_millis(100)));
        assert_eq!(parse("1s"), Ok(Duration::from_secs(1)));
        assert_eq!(parse("2.5s"), Ok(Duration::from_millis(2500)));
        assert_eq!(parse("1min"), Ok(Duration::from_secs(60)));
        assert_eq!(parse(" 2 h "), Ok(Duration::from_secs(7200)));
    }

    #[test]
    fn zero_bare_numbers_and_strange_units_are_refused() {
        for (text, says) in [
            ("0s", "is zero"),
            ("5", "has no unit"),
            ("5 sec", "not a unit"),
            ("fast", "not an interval"),
            ("1.2.3s", "not a number"),
            ("1ms", "outside"),
            ("2d", "not a unit"),
            ("25h", "outside"),
        ] {
            let (message, _) = parse(text).unwrap_err();
            assert!(message.contains(says), "{text}: {message}");
        }
    }

    #[test]
    fn intervals_show_as_written() {
        for text in ["250ms", "1s", "2.5s", "1min", "2h"] {
            assert_eq!(show(parse(text).unwrap()), text);
        }
    }
}
