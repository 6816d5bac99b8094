//! A small YAML writer for the job bundle's files: block mappings and sequences in the order
//! given, every string double-quoted with JSON's escapes (which YAML's double-quoted scalars
//! read the same), so no value can be mistaken for a number, a boolean or YAML syntax.

use std::fmt::Write as _;

/// A YAML value.
#[derive(Debug, Clone, PartialEq)]
pub enum Yaml {
    /// A string, always quoted.
    Str(String),
    /// An integer.
    Int(i64),
    /// A sequence.
    List(Vec<Yaml>),
    /// A mapping, in the order given.
    Map(Vec<(String, Yaml)>),
}

impl Yaml {
    /// A string value.
    pub fn str(s: impl Into<String>) -> Self {
        Yaml::Str(s.into())
    }

    /// A mapping from `(key, value)` pairs.
    pub fn map<const N: usize>(pairs: [(&str, Yaml); N]) -> Self {
        Yaml::Map(pairs.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
    }

    /// A list of strings.
    pub fn strs<S: AsRef<str>>(items: impl IntoIterator<Item = S>) -> Self {
        Yaml::List(items.into_iter().map(|s| Yaml::str(s.as_ref())).collect())
    }

    /// The document text: this value (a mapping) as block YAML, ending with a newline.
    pub fn to_document(&self) -> String {
        let mut out = String::new();
        write_block(self, 0, &mut out);
        out
    }
}

/// A scalar's text, or an empty collection's flow form; `None` for a non-empty collection.
fn inline(v: &Yaml) -> Option<String> {
    match v {
        Yaml::Str(s) => Some(serde_json::to_string(s).expect("strings serialise")),
        Yaml::Int(i) => Some(i.to_string()),
        Yaml::List(l) if l.is_empty() => Some("[]".into()),
        Yaml::Map(m) if m.is_empty() => Some("{}".into()),
        _ => None,
    }
}

/// Writes `v` (a collection) as block lines indented by `indent` spaces.
fn write_block(v: &Yaml, indent: usize, out: &mut String) {
    let pad = " ".repeat(indent);
    match v {
        Yaml::Map(pairs) => {
            for (k, v) in pairs {
                let key = serde_json::to_string(k).expect("strings serialise");
                let key = if k.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
                    k.clone()
                } else {
                    key
                };
                match inline(v) {
                    Some(text) => {
                        let _ = writeln!(out, "{pad}{key}: {text}");
                    }
                    None => {
                        let _ = writeln!(out, "{pad}{key}:");
                        write_block(v, indent + 2, out);
                    }
                }
            }
        }
        Yaml::List(items) => {
            for item in items {
                match inline(item) {
                    Some(text) => {
                        let _ = writeln!(out, "{pad}- {text}");
                    }
                    None => {
                        // The item's block at indent + 2, its first line's indent turned into "- ".
                        let mut inner = String::new();
                        write_block(item, indent + 2, &mut inner);
                        let _ = write!(out, "{pad}- {}", &inner[indent + 2..]);
                    }
                }
            }
        }
        scalar => {
            let _ = writeln!(out, "{pad}{}", inline(scalar).unwrap_or_default());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_block_yaml_with_quoted_strings() {
        let doc = Yaml::map([
            ("name", Yaml::str("a \"b\"\n{{c}}")),
            ("n", Yaml::Int(3)),
            ("empty", Yaml::List(vec![])),
            (
                "steps",
                Yaml::List(vec![
                    Yaml::map([("name", Yaml::str("S")), ("args", Yaml::strs(["x", "1"]))]),
                    Yaml::str("plain"),
                ]),
            ),
        ]);
        assert_eq!(
            doc.to_document(),
            "name: \"a \\\"b\\\"\\n{{c}}\"\nn: 3\nempty: []\nsteps:\n  - name: \"S\"\n    \
             args:\n      - \"x\"\n      - \"1\"\n  - \"plain\"\n"
        );
    }
}
