//! A minimal JSON writer for the commands' `--json` output: numbers use
//! Rust's shortest round-trip formatting, so every `f64` reads back exactly.

use std::fmt::Write;

/// A JSON value.
#[derive(Debug, Clone)]
pub enum Json {
    Number(f64),
    Integer(u64),
    Bool(bool),
    String(String),
    Array(Vec<Json>),
    /// Keys in the order given.
    Object(Vec<(String, Json)>),
}

impl Json {
    /// An object from `(key, value)` pairs.
    pub fn object(pairs: Vec<(&str, Json)>) -> Json {
        Json::Object(pairs.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
    }

    /// An array of numbers.
    pub fn numbers(values: &[f64]) -> Json {
        Json::Array(values.iter().map(|&v| Json::Number(v)).collect())
    }

    /// An array of integers.
    pub fn integers(values: &[u64]) -> Json {
        Json::Array(values.iter().map(|&v| Json::Integer(v)).collect())
    }

    /// The compact JSON text.
    pub fn render(&self) -> String {
        let mut out = String::new();
        self.write(&mut out);
        out
    }

    fn write(&self, out: &mut String) {
        match self {
            // JSON has no NaN or infinity: write null for them.
            Json::Number(value) if !value.is_finite() => out.push_str("null"),
            Json::Number(value) => {
                let _ = write!(out, "{value:?}");
            }
            Json::Integer(value) => {
                let _ = write!(out, "{value}");
            }
            Json::Bool(value) => out.push_str(if *value { "true" } else { "false" }),
            Json::String(text) => write_string(text, out),
            Json::Array(items) => {
                out.push('[');
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    item.write(out);
                }
                out.push(']');
            }
            Json::Object(pairs) => {
                out.push('{');
                for (i, (key, value)) in pairs.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    write_string(key, out);
                    out.push(':');
                    value.write(out);
                }
                out.push('}');
            }
        }
    }
}

fn write_string(text: &str, out: &mut String) {
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_nested_values() {
        let value = Json::object(vec![
            ("name", Json::String("a\"b".into())),
            ("values", Json::numbers(&[0.0, 0.1, 1e-20])),
            ("n", Json::Integer(3)),
        ]);
        assert_eq!(
            value.render(),
            r#"{"name":"a\"b","values":[0.0,0.1,1e-20],"n":3}"#
        );
    }

    #[test]
    fn numbers_round_trip() {
        for value in [1.0 / 3.0, 0.1 + 0.2, 1e-300, 0.9999999999999999] {
            let text = Json::Number(value).render();
            assert_eq!(text.parse::<f64>().unwrap(), value);
        }
    }
}
