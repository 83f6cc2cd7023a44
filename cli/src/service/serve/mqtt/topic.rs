//! Topic names: the layout under the prefix and the rule that makes a register's code a
//! topic segment.
//!
//! A segment keeps the code as the manual writes it (`FA01`, `3-03`, `P0.01`) except that
//! the characters MQTT reserves or that break a level (`/`, `+`, `#`), white space and
//! control characters each become `_`; an empty code becomes `_`.

/// `code` made a single topic level (see the module documentation).
pub fn segment(code: &str) -> String {
    let text: String = code
        .chars()
        .map(|c| {
            if matches!(c, '/' | '+' | '#') || c.is_whitespace() || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    if text.is_empty() {
        "_".to_string()
    } else {
        text
    }
}

/// The topics of one service.
#[derive(Debug, Clone)]
pub struct Topics {
    /// The prefix (`vfd`), without a trailing `/`.
    pub prefix: String,
}

impl Topics {
    /// `PREFIX/status`: the service's own `online` / `offline` (the last will).
    pub fn status(&self) -> String {
        format!("{}/status", self.prefix)
    }

    /// `PREFIX/BUS/DRIVE/available`.
    pub fn available(&self, bus: &str, drive: &str) -> String {
        format!("{}/{bus}/{drive}/available", self.prefix)
    }

    /// `PREFIX/BUS/DRIVE/CODE`: a register's state.
    pub fn state(&self, bus: &str, drive: &str, code: &str) -> String {
        format!("{}/{bus}/{drive}/{}", self.prefix, segment(code))
    }

    /// `PREFIX/+/+/+/set`: what the service subscribes to.
    pub fn set_filter(&self) -> String {
        format!("{}/+/+/+/set", self.prefix)
    }

    /// Splits `PREFIX/BUS/DRIVE/CODE/set` into bus, drive and code segment.
    pub fn parse_set<'a>(&self, topic: &'a str) -> Option<(&'a str, &'a str, &'a str)> {
        let rest = topic.strip_prefix(&self.prefix)?.strip_prefix('/')?;
        let rest = rest.strip_suffix("/set")?;
        let mut parts = rest.split('/');
        let (bus, drive, code) = (parts.next()?, parts.next()?, parts.next()?);
        if parts.next().is_some() {
            return None;
        }
        Some((bus, drive, code))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reserved_characters_become_underscores() {
        assert_eq!(segment("FA01"), "FA01");
        assert_eq!(segment("3-03"), "3-03");
        assert_eq!(segment("P0.01"), "P0.01");
        assert_eq!(segment("a/b+c#d e"), "a_b_c_d_e");
        assert_eq!(segment(""), "_");
    }

    #[test]
    fn set_topics_split_into_bus_drive_and_code() {
        let topics = Topics {
            prefix: "site/vfd".into(),
        };
        assert_eq!(
            topics.parse_set("site/vfd/line1/pump/FA01/set"),
            Some(("line1", "pump", "FA01"))
        );
        assert_eq!(topics.parse_set("site/vfd/line1/pump/set"), None);
        assert_eq!(topics.parse_set("other/line1/pump/FA01/set"), None);
        assert_eq!(topics.set_filter(), "site/vfd/+/+/+/set");
    }
}
